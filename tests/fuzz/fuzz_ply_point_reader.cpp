// libFuzzer harness for the PLY point reader (ply_point_reader.h): any bytes must give
// a status, never a crash, leak, hang or giant allocation; a success must be
// consistent. Built and run by tests/fuzz/run_fuzzers.sh.
#include <pcl_vts/io/ply_point_reader.h>

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  std::vector<double> xyz;
  pcl_vts::PlyPointInfo info;
  const pcl_vts::Status s = pcl_vts::parsePlyPoints(data, size, "fuzz", xyz, info);
  if (s.ok() ? (xyz.size() != 3 * info.vertices || info.vertices == 0) : !xyz.empty())
    __builtin_trap();
  return 0;
}
