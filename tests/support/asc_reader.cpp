// ESRI ASCII grid reader: six header lines (NODATA_value optional), then nrows rows
// of ncols values, top row first.
#include "support/asc_reader.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

namespace pcl_vts {
namespace test {
namespace {

bool fail(std::string* error, const std::string& text)
{
  if (error)
    *error = text;
  return false;
}

std::string lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

} // namespace

bool readAsciiGrid(const std::string& path, AsciiGrid& grid, std::string* error)
{
  std::ifstream in(path);
  if (!in)
    return fail(error, "cannot open " + path);
  grid = AsciiGrid();
  bool x_center = false, y_center = false;
  bool have_x = false, have_y = false;
  // Header: "key value" pairs until the first token that is a number.
  std::string key;
  while (in >> key) {
    const std::string k = lower(key);
    if (!k.empty() && (std::isdigit(static_cast<unsigned char>(k[0])) || k[0] == '-' ||
                       k[0] == '+' || k[0] == '.')) {
      // First data value: push it back by re-reading from its start.
      in.seekg(-static_cast<std::streamoff>(key.size()), std::ios::cur);
      break;
    }
    double value = 0.0;
    if (!(in >> value))
      return fail(error, path + ": no value for header key '" + key + "'");
    if (k == "ncols")
      grid.ncols = static_cast<std::size_t>(value);
    else if (k == "nrows")
      grid.nrows = static_cast<std::size_t>(value);
    else if (k == "xllcorner" || k == "xllcenter") {
      grid.xll = value;
      x_center = k == "xllcenter";
      have_x = true;
    } else if (k == "yllcorner" || k == "yllcenter") {
      grid.yll = value;
      y_center = k == "yllcenter";
      have_y = true;
    } else if (k == "cellsize")
      grid.cellsize = value;
    else if (k == "nodata_value")
      grid.nodata = value;
    else
      return fail(error, path + ": unknown header key '" + key + "'");
  }
  if (grid.ncols == 0 || grid.nrows == 0 || !(grid.cellsize > 0.0) || !have_x ||
      !have_y)
    return fail(error, path + ": incomplete header (ncols, nrows, xll, yll, cellsize)");
  if (x_center)
    grid.xll -= 0.5 * grid.cellsize;
  if (y_center)
    grid.yll -= 0.5 * grid.cellsize;
  grid.xyz.reserve(3 * grid.ncols * grid.nrows);
  for (std::size_t r = 0; r < grid.nrows; ++r) {
    for (std::size_t c = 0; c < grid.ncols; ++c) {
      double z = 0.0;
      if (!(in >> z)) {
        std::ostringstream out;
        out << path << ": expected " << grid.ncols * grid.nrows << " values, got "
            << r * grid.ncols + c;
        return fail(error, out.str());
      }
      if (z == grid.nodata) {
        ++grid.nodata_cells;
        continue;
      }
      grid.xyz.push_back(grid.xll + (static_cast<double>(c) + 0.5) * grid.cellsize);
      grid.xyz.push_back(grid.yll +
                         (static_cast<double>(grid.nrows - r) - 0.5) * grid.cellsize);
      grid.xyz.push_back(z);
    }
  }
  return true;
}

} // namespace test
} // namespace pcl_vts
