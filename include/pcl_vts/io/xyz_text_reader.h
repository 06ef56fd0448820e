// Reads x y z from a text table (.xyz, .txt, .csv): values separated by whitespace,
// commas or semicolons, one point per line, extra columns ignored. An optional first
// line of column names picks the x, y, z columns by name (any case); '#' and '//'
// lines are comments. Numbers are parsed strictly: a bad token is an error, not 0.
// PCL-free.
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/io/export.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {

struct XyzTextInfo {
  std::size_t points = 0;              ///< data lines read
  std::string header;                  ///< the column-name line, "" if none
  std::array<std::size_t, 3> column{}; ///< 0-based columns used for x, y, z
};

/// Reads every data line.
/// \param[out] xyz 3 doubles per line, in file order; cleared on error
/// \return IO_ERROR (one line naming the file and line) when it is missing, empty,
///         binary, a line has fewer columns than needed or a value that is not a
///         number; EMPTY_INPUT when it holds no data line (header or comments only).
PCL_VTS_IO_EXPORT Status readXyzText(const std::string& path, std::vector<double>& xyz,
                                     XyzTextInfo& info);

/// Same, on bytes in memory; name is used in messages only.
PCL_VTS_IO_EXPORT Status parseXyzText(const std::uint8_t* data, std::size_t size,
                                      const std::string& name, std::vector<double>& xyz,
                                      XyzTextInfo& info);

} // namespace pcl_vts
