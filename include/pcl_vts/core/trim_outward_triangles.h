// Outward-triangle removal (thesis section 4.2, Algorithm 5 TriangleRemoving): a
// Delaunay triangulation covers the convex hull, so it bridges concave parts of the
// outline and data voids with oversized triangles. A triangle is oversized when its
// longest edge exceeds trim_factor times the local point spacing (an alpha-shape-like
// test); oversized triangles are peeled from the boundary inwards until nothing
// changes, never creating a pinch vertex. docs/reconstruction.md, "Trimming".
#pragma once

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>

#include <cstddef>

namespace pcl_vts {

struct TrimOptions {
  /// A triangle is oversized when its longest XY edge exceeds trim_factor times the
  /// local spacing at its vertices (point_spacing.h: largest of the three). Finite,
  /// > 1 (at 1 even regular lattices would be eaten).
  double trim_factor = 4.0;
  /// A triangle with an XY edge longer than this is also oversized (input units);
  /// 0 = no absolute limit. Finite, >= 0.
  double max_edge = 0.0;
  /// Also remove oversized triangles inside the mesh (over a data void), which
  /// opens the void into a hole; otherwise only the peel from the boundary.
  bool open_voids = true;
};

/// Checks every option; the message names the offending value.
Status validateTrimOptions(const TrimOptions& options);

struct TrimResult {
  std::size_t triangles_removed = 0;
  /// Vertices that had triangles before and have none after (kept in xy/z, unused).
  std::size_t vertices_lost = 0;
  /// Oversized triangles kept because removing them would pinch a vertex.
  std::size_t kept_to_stay_manifold = 0;
  /// Median nearest-neighbour spacing of the input (the scale the test used).
  double spacing = 0.0;
};

/// Removes outward triangles of mesh in place.
/// \param[in,out] mesh CCW triangles, consistent halfedges, every vertex with a
///   manifold fan (the VTS output is); vertices are never renumbered or removed, so
///   vertex ids stay valid; triangles keep their relative order; halfedges rebuilt.
/// Post-conditions: edge-manifold, no new pinch vertex, twins consistent.
/// Deterministic (no dependence on anything but the arrays).
Status trimOutwardTriangles(TriangleMesh& mesh, const TrimOptions& options,
                            TrimResult& result);

} // namespace pcl_vts
