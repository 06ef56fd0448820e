// Constrained Delaunay triangulation of a simple polygon with interior Steiner
// points: ear clipping, Lawson flips of every non-polygon edge to the constrained
// Delaunay triangulation, then each point inserted (split, flip back to Delaunay).
// Polygon edges are never flipped, so the patch meets its rim exactly. Signs from
// the exact predicates only. docs/reconstruction.md, "Triangulating a hole".
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/point2.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {

struct PolygonTriangulation {
  /// 3 per triangle, CCW, as indices into the input points.
  std::vector<std::uint32_t> triangles;
  /// Per Steiner point (points[polygon_size + k]): 1 when it is a vertex of the
  /// output; 0 when skipped because it lay on a polygon edge, on another point or
  /// outside the polygon.
  std::vector<std::uint8_t> steiner_used;
};

/// Triangulates the polygon points[0..polygon_size) (simple, counter-clockwise, no
/// repeated position) with the points[polygon_size..) inside it.
/// \return INVALID_PARAMETER when polygon_size < 3 or the polygon is not simple and
///   counter-clockwise (no ear can be cut); OK otherwise. Deterministic.
/// Post-condition: triangles tile the polygon; each polygon edge is a triangle edge;
/// every edge not on the polygon is locally Delaunay (exact in-circle).
PCL_VTS_CORE_EXPORT Status triangulatePolygon(const std::vector<Point2>& points,
                                              std::size_t polygon_size,
                                              PolygonTriangulation& output);

} // namespace pcl_vts
