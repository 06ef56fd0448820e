// Reads the x, y, z of the vertex element of a PLY file (a point cloud or a mesh,
// whose faces are ignored): ascii, binary_little_endian or binary_big_endian; x, y, z
// of any scalar type (float, double, integers) kept in double. Elements before the
// vertex element, and list properties, are stepped over. PCL-free.
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

struct PlyPointInfo {
  std::string format;                   ///< "ascii", "binary_little_endian", ...
  std::size_t vertices = 0;             ///< vertex element count
  std::array<std::string, 3> xyz_types; ///< PLY type names of x, y, z
  std::size_t faces = 0;                ///< face element count (not read)
};

/// Reads every vertex of a PLY file.
/// \param[out] xyz 3 doubles per vertex, in file order; cleared on error
/// \return IO_ERROR (one line naming the file) when it is missing, empty, not PLY, has
///         a bad header (no vertex element, no x/y/z, unknown type), a value that is
///         not a number, or a body shorter than its header claims; EMPTY_INPUT when
///         it has 0 vertices.
PCL_VTS_IO_EXPORT Status readPlyPoints(const std::string& path,
                                       std::vector<double>& xyz, PlyPointInfo& info);

/// Same, on bytes in memory; name is used in messages only.
PCL_VTS_IO_EXPORT Status parsePlyPoints(const std::uint8_t* data, std::size_t size,
                                        const std::string& name,
                                        std::vector<double>& xyz, PlyPointInfo& info);

/// Receives vertices, xyz triples in file order, a chunk at a time.
using PlyChunkSink = std::function<Status(const double* xyz, std::size_t n)>;

/// Same as readPlyPoints, but the vertices go to `sink` in chunks of at most
/// chunk_points, and the file's pages are released behind the reader: memory stays
/// bounded by the chunk whatever the file's size. A body error after some chunks
/// went out is returned; a sink error stops the read and is returned.
PCL_VTS_IO_EXPORT Status readPlyPointChunks(const std::string& path,
                                            std::size_t chunk_points,
                                            const PlyChunkSink& sink,
                                            PlyPointInfo& info);

} // namespace pcl_vts
