// The same triangles under other ids: for tests that a pass depends on positions only
// (the tiled path runs the post-passes on parts of the mesh, with other ids);
// compare with verticesByPosition and pipeline_checks.h's trianglesByPosition.
#pragma once
#include <pcl_vts/core/mesh_arrays.h>

#include <array>
#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace test {

/// mesh with its vertex ids and triangle order shuffled and each triangle's corners
/// rotated; halfedges rebuilt.
TriangleMesh shuffledIds(const TriangleMesh& mesh, std::uint32_t seed);

/// Every vertex as (x, y, z), sorted: the vertex set without its ids.
std::vector<std::array<double, 3>> verticesByPosition(const TriangleMesh& mesh);

} // namespace test
} // namespace pcl_vts
