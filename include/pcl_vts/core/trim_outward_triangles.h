// Outward-triangle removal (thesis section 4.2, Algorithm 5 TriangleRemoving): a
// Delaunay triangulation covers the convex hull, so it bridges concave parts of the
// outline and data voids with oversized triangles. A triangle is oversized when its
// longest edge or circumradius exceeds trim_factor times the local point spacing (an
// alpha-shape-like test); oversized triangles are peeled from the boundary inwards
// until nothing changes; removed triangles that would leave a pinch vertex (two fans)
// are then restored. docs/reconstruction.md, "Trimming".
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {

struct TrimOptions {
  /// A triangle is oversized when its longest XY edge or its circumradius exceeds
  /// trim_factor times the local spacing at its vertices (point_spacing.h: largest of
  /// the three). Finite, > 1 (at 1 even regular lattices would be eaten).
  double trim_factor = 3.0;
  /// A triangle with an XY edge longer than this is also oversized (input units);
  /// 0 = no absolute limit. Finite, >= 0.
  double max_edge = 0.0;
  /// Also open data voids from inside: an oversized non-obtuse triangle (its
  /// circumcentre, a local maximum of the distance to the data, inside it) is
  /// removed even with no boundary edge, and the peel grows the hole from there;
  /// otherwise only the peel from the outline runs.
  bool open_voids = true;
};

/// Checks every option; the message names the offending value.
PCL_VTS_CORE_EXPORT Status validateTrimOptions(const TrimOptions& options);

struct TrimResult {
  std::size_t triangles_removed = 0;
  /// Vertices that had triangles before and have none after (kept in xy/z, unused).
  std::size_t vertices_lost = 0;
  /// Oversized triangles restored because removing them would pinch a vertex.
  std::size_t kept_to_stay_manifold = 0;
  /// Median nearest-neighbour spacing of the input (the scale the test used).
  double spacing = 0.0;
};

/// The static test of one triangle, the part of the trim that needs no neighbour.
struct TriangleSize {
  bool oversized = false;
  /// Oversized and non-obtuse: its circumcentre, a local maximum of the distance to
  /// the data, lies inside it, so it can open a void from inside.
  bool void_seed = false;
};

/// Classifies triangle abc against trim_factor * scale (scale: the largest local
/// spacing of its corners, point_spacing.h) and max_edge.
PCL_VTS_CORE_EXPORT TriangleSize classifyTriangle(const Point2& a, const Point2& b,
                                                  const Point2& c, double scale,
                                                  const TrimOptions& options);

/// Flags of peelOutwardTriangles' input, per triangle.
enum TriangleSizeFlag : std::uint8_t { OVERSIZED = 1, VOID_SEED = 2 };

/// The peel and the pinch repair, given each triangle's classification: sets
/// removed[t] for the oversized triangles connected (across edges, through oversized
/// triangles) to an oversized one on the hull or, with open_voids, to a void seed;
/// then restores the removed triangles that would pinch a vertex. The repair visits
/// vertices in lexicographic (x, y) order and breaks ties between the gaps of a fan
/// by position, so the result depends on the geometry alone, not on the ids: a
/// sub-mesh holding every triangle around each vertex of an oversized triangle gives
/// the same answer as the whole mesh (the tiled path relies on it).
/// \param mesh triangles with consistent halfedges; twin-less edges of oversized
///   triangles are hull edges.
/// \return the number of triangles restored by the repair.
PCL_VTS_CORE_EXPORT std::size_t
peelOutwardTriangles(const TriangleMesh& mesh, const std::vector<std::uint8_t>& flags,
                     bool open_voids, std::vector<bool>& removed);

/// Removes outward triangles of mesh in place.
/// \param[in,out] mesh CCW triangles, consistent halfedges, every vertex with a
///   manifold fan (the VTS output is); vertices are never renumbered or removed, so
///   vertex ids stay valid; triangles keep their relative order; halfedges rebuilt.
/// Post-conditions: edge-manifold, no new pinch vertex, twins consistent.
/// Deterministic (no dependence on anything but the arrays).
PCL_VTS_CORE_EXPORT Status trimOutwardTriangles(TriangleMesh& mesh,
                                                const TrimOptions& options,
                                                TrimResult& result);

} // namespace pcl_vts
