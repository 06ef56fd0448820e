// Flat, delaunator-style mesh arrays: the vocabulary every core pass speaks.
// A triangle t owns halfedges 3t, 3t+1, 3t+2; halfedge e runs from triangles[e] to
// triangles[next(e)], and halfedges[e] is its twin in the neighbouring triangle or
// INVALID_ID on the boundary. Triangles are counter-clockwise seen from +z.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/point2.h>

#include <cstdint>
#include <limits>
#include <vector>

namespace pcl_vts {

using VertexId = std::uint32_t;
using HalfedgeId = std::uint32_t;
using TriangleId = std::uint32_t;
using CellId = std::uint32_t;

/// Marks "no vertex", "no twin" (boundary) or "no cell".
constexpr std::uint32_t INVALID_ID = std::numeric_limits<std::uint32_t>::max();

//            v2 = triangles[3t+2]
//            /  \    .
//   e = 3t+2 /    \   e = 3t+1   halfedge e goes from triangles[e] to
//          /      \  .           triangles[next(e)]
//        v0 ------ v1           next(3t) = 3t+1, next(3t+2) = 3t
//            e = 3t
inline HalfedgeId nextHalfedge(HalfedgeId e)
{
  return (e % 3 == 2) ? e - 2 : e + 1;
}

inline HalfedgeId prevHalfedge(HalfedgeId e)
{
  return (e % 3 == 0) ? e + 2 : e - 1;
}

inline TriangleId triangleOf(HalfedgeId e)
{
  return e / 3;
}

/// A triangle mesh over a set of 2.5D vertices.
struct PCL_VTS_CORE_EXPORT TriangleMesh {
  std::vector<Point2> xy;            ///< 1 per vertex, input units
  std::vector<double> z;             ///< 1 per vertex
  std::vector<VertexId> triangles;   ///< 3 per triangle, CCW in XY
  std::vector<HalfedgeId> halfedges; ///< 1 per halfedge: twin or INVALID_ID

  std::size_t vertexCount() const { return z.size(); }
  std::size_t triangleCount() const { return triangles.size() / 3; }
  /// Rebuilds halfedges from triangles (twins matched by vertex pair).
  /// Returns false when an edge is used by more than two triangles or twice in the
  /// same direction (the mesh is not an oriented 2-manifold).
  bool rebuildHalfedges();
};

} // namespace pcl_vts
