// libFuzzer harness for the ESRI ASCII grid reader (asc_grid_reader.h): any bytes must
// give a status, never a crash, leak, hang or giant allocation; a success must be
// consistent. Built and run by tests/fuzz/run_fuzzers.sh.
#include <pcl_vts/io/asc_grid_reader.h>

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  std::vector<double> xyz;
  pcl_vts::AscGridInfo info;
  const pcl_vts::Status s = pcl_vts::parseAscGrid(data, size, "fuzz", xyz, info);
  if (s.ok() ? (xyz.size() != 3 * info.points || info.points == 0 ||
                info.points + info.nodata_cells != info.ncols * info.nrows)
             : !xyz.empty())
    __builtin_trap();
  return 0;
}
