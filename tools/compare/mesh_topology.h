// Counts that say whether a mesh is a clean 2.5D surface over its points: edges used
// by one triangle (boundary) or more than two (non-manifold), triangles seen from
// below (flipped: normal z < 0, i.e. clockwise in XY, for terrain), and input points
// that no triangle uses. PCL-free.
#pragma once

#include "compare_mesh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace compare {

struct TopologyCounts {
  std::size_t triangles = 0;
  std::size_t vertices_used = 0; ///< distinct vertex ids referenced by triangles
  std::size_t boundary_edges = 0;
  std::size_t non_manifold_edges = 0;
  std::size_t flipped = 0;  ///< signed XY area < 0
  std::size_t vertical = 0; ///< XY area exactly 0 (neither up nor down)
  /// Vertex-id pairs, 2 per edge, for pictures.
  std::vector<std::uint32_t> boundary_edge_list;
  std::vector<std::uint32_t> non_manifold_edge_list;
};

/// Edges are vertex-id pairs (unordered); a triangle with a repeated id contributes
/// only its proper edges.
TopologyCounts countTopology(const CompareMesh& mesh);

/// Input points not used by any triangle: a point counts as used when a triangle
/// references a vertex whose source is that point or another input point with
/// exactly the same XY (merged duplicates are represented). Returns -1 when the mesh
/// has no vertex with a source (not a vertex-based method: Poisson).
long long countUnusedPoints(const CompareMesh& mesh, const PointSet& input);

/// Signed XY area of triangle t (> 0: counter-clockwise seen from +z).
double signedXyArea(const CompareMesh& mesh, std::size_t t);

} // namespace compare
} // namespace pcl_vts
