// libFuzzer harness for the LAS reader (las_reader.h), LAZ included: any bytes must
// give a status, never a crash, leak, overflow, hang or giant allocation; a success
// must be consistent (an uncompressed file holds its records).
// Built and run by tests/fuzz/run_fuzzers.sh.
#include <pcl_vts/io/las_reader.h>

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  pcl_vts::LasReadOptions filtered;
  filtered.classes = {2, 65};
  filtered.returns = pcl_vts::LasReturnFilter::LAST;
  filtered.threads = 2;
  for (const pcl_vts::LasReadOptions& options : {pcl_vts::LasReadOptions(), filtered}) {
    std::vector<double> xyz;
    pcl_vts::LasInfo info;
    const pcl_vts::Status s =
        pcl_vts::parseLasCloud(data, size, "fuzz", options, xyz, info);
    if (s.ok() ? (xyz.size() != 3 * info.points_kept || info.points_kept == 0 ||
                  info.points_kept > info.points_read ||
                  (info.laz.empty() && info.points_read * info.record_length > size))
               : !xyz.empty())
      __builtin_trap();
  }
  return 0;
}
