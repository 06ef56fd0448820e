// libFuzzer harness for the XYZ text reader (xyz_text_reader.h): any bytes must give a
// status, never a crash, leak or hang; a success must be consistent. Built and run by
// tests/fuzz/run_fuzzers.sh.
#include <pcl_vts/io/xyz_text_reader.h>

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  std::vector<double> xyz;
  pcl_vts::XyzTextInfo info;
  const pcl_vts::Status s = pcl_vts::parseXyzText(data, size, "fuzz", xyz, info);
  if (s.ok() ? (xyz.size() != 3 * info.points || info.points == 0) : !xyz.empty())
    __builtin_trap();
  return 0;
}
