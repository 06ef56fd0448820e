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
#include <functional>
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

/// Receives points, xyz triples in file order, a chunk at a time.
using XyzChunkSink = std::function<Status(const double* xyz, std::size_t n)>;

/// Same as readXyzText, but the points go to `sink` in chunks of at most chunk_points,
/// and the file's pages are released behind the reader: memory stays bounded by the
/// chunk whatever the file's size. Binary bytes are found line by line (a file that
/// turns binary fails there, after its earlier points went out); a sink error stops
/// the read and is returned.
PCL_VTS_IO_EXPORT Status readXyzTextChunks(const std::string& path,
                                           std::size_t chunk_points,
                                           const XyzChunkSink& sink, XyzTextInfo& info);

/// Same, on bytes in memory; name is used in messages only.
PCL_VTS_IO_EXPORT Status parseXyzText(const std::uint8_t* data, std::size_t size,
                                      const std::string& name, std::vector<double>& xyz,
                                      XyzTextInfo& info);

} // namespace pcl_vts
