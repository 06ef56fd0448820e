// Top-down pictures of 2.5D meshes for docs/reconstruction.md: each triangle filled
// with a hill-shaded colour of its class (kept, removed, filled), written as a small
// palette PNG by a self-contained encoder (fixed-Huffman deflate with run-length
// matches: no zlib dependency in the test binaries).
#pragma once

#include <pcl_vts/core/mesh_arrays.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {
namespace test {

enum class TriangleClass : std::uint8_t { KEPT = 0, REMOVED = 1, FILLED = 2 };

/// Renders the triangles of mesh (XY from above, north up) into a width-pixel-wide
/// palette image, each triangle coloured by classes[t] and shaded by its normal;
/// vertices flagged in marks are drawn as dark dots. Returns false when the file
/// cannot be written.
bool writeMeshPicture(const std::string& path, const TriangleMesh& mesh,
                      const std::vector<TriangleClass>& classes,
                      const std::vector<std::uint8_t>& marks, int width);

/// The PNG encoder alone: 8-bit palette image (rgb: 3 bytes per palette entry).
bool writePalettePng(const std::string& path, int width, int height,
                     const std::vector<std::uint8_t>& pixels,
                     const std::vector<std::uint8_t>& rgb);

} // namespace test
} // namespace pcl_vts
