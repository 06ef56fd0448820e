// Boundary loops of a triangle mesh from its halfedges: each loop is a closed walk of
// twin-less halfedges with the mesh on its left, so an outer boundary runs CCW and a
// hole CW. Each connected piece (triangles joined by shared edges) has exactly one
// outer loop: its loop of largest signed area. Pinch vertices (two fans meeting at
// one vertex) are walked fan by fan, so a loop may visit a vertex twice.
// Thesis section 4.3.2 "Determining holes"; docs/reconstruction.md.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {

struct BoundaryLoop {
  /// Twin-less halfedges in walking order; halfedges[i] ends where halfedges[i+1]
  /// starts. The mesh lies on the left of each.
  std::vector<HalfedgeId> halfedges;
  /// Origin vertex of each halfedge (same length); may repeat at a pinch vertex.
  std::vector<VertexId> vertices;
  /// Twice the signed (shoelace) area of the vertex cycle: > 0 outer, < 0 hole.
  double twice_area = 0.0;
  /// Connected piece (index into BoundaryLoops::component_triangles) owning it.
  std::uint32_t component = 0;
  /// The outer boundary of its piece (otherwise an inner hole).
  bool is_outer = false;
  /// Some vertex appears twice in the loop (it passes through a pinch vertex).
  bool has_repeated_vertex = false;
};

struct PCL_VTS_CORE_EXPORT BoundaryLoops {
  std::vector<BoundaryLoop> loops;
  /// Per triangle: its connected piece (triangles sharing an edge are connected).
  std::vector<std::uint32_t> triangle_component;
  /// Per piece: number of triangles.
  std::vector<std::size_t> component_triangles;

  std::size_t componentCount() const { return component_triangles.size(); }
  std::size_t holeCount() const;
};

/// Finds every boundary loop of mesh and tells outer loops from holes.
/// \param[in] mesh triangles CCW with consistent halfedges (twin-symmetric)
/// \param[out] loops every loop; each twin-less halfedge belongs to exactly one
/// \return INVALID_PARAMETER when halfedges does not match triangles in size or a
///   walk does not close (inconsistent twins); OK otherwise (also for no triangle).
PCL_VTS_CORE_EXPORT Status findBoundaryLoops(const TriangleMesh& mesh,
                                             BoundaryLoops& loops);

/// The loops of findBoundaryLoops without the pieces (component 0, is_outer false):
/// one pass over the halfedges and one walk per loop, for callers that tell holes by
/// the sign of twice_area alone (hole filling).
PCL_VTS_CORE_EXPORT Status traceBoundaryLoops(const TriangleMesh& mesh,
                                              std::vector<BoundaryLoop>& loops);

/// Next twin-less halfedge after boundary halfedge e along its loop: rotates around
/// the end vertex of e inside e's fan. Precondition: halfedges[e] == INVALID_ID.
/// Returns INVALID_ID if the rotation does not reach a boundary halfedge within the
/// mesh's halfedge count (inconsistent twins).
PCL_VTS_CORE_EXPORT HalfedgeId nextBoundaryHalfedge(const TriangleMesh& mesh,
                                                    HalfedgeId e);

} // namespace pcl_vts
