// Test-side reader of ESRI ASCII grids (.asc, AAIGrid): one point per valid cell at
// the cell centre, NODATA cells skipped. Enough for the DEMs in ../shared/data.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace pcl_vts {
namespace test {

struct AsciiGrid {
  std::size_t ncols = 0;
  std::size_t nrows = 0;
  double xll = 0.0; ///< x of the lower-left cell's corner (centre convention converted)
  double yll = 0.0; ///< y of the lower-left cell's corner
  double cellsize = 0.0;
  double nodata = -9999.0;
  std::size_t nodata_cells = 0;
  /// xyz of every valid cell centre, 3 doubles per point, rows from the top.
  std::vector<double> xyz;
};

/// Reads path. Header keys are case-insensitive; xllcorner|xllcenter and
/// yllcorner|yllcenter are both understood (cell centre of column c, row r counted
/// from the top: (xll + (c + 0.5) cs, yll + (nrows - r - 0.5) cs)). Returns false and
/// sets *error on a missing file, a bad header or too few values.
bool readAsciiGrid(const std::string& path, AsciiGrid& grid,
                   std::string* error = nullptr);

} // namespace test
} // namespace pcl_vts
