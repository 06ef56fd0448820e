// Independent oracle for the triangulator: CGAL's Delaunay_triangulation_2 over the
// XY projection (Projection_traits_xy_3, exact predicates). The only place in
// pcl_vts that includes CGAL; tests and benchmarks only.
#pragma once

#include <pcl_vts/core/point2.h>

#include <array>
#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace test {

using IndexTriangle = std::array<std::uint32_t, 3>;

/// Delaunay triangulation of points by CGAL.
/// \param[in] points  #P points; duplicates are merged by CGAL (one index survives)
/// \return finite faces as CCW triples of indices into points; empty when the points
///         are collinear or fewer than 3.
/// \note Cocircular ties are broken by CGAL's own symbolic perturbation, in which the
///       lexicographically largest point is perturbed most: the reverse of pcl_vts'
///       rule. cgalDelaunayMirrored() gives the pcl_vts tie-break.
std::vector<IndexTriangle> cgalDelaunay(const std::vector<Point2>& points);

/// As cgalDelaunay(), but CGAL triangulates the points mirrored through the origin
/// ((x, y) -> (-x, -y), exact). The mirror keeps orientation and circles and reverses
/// the lexicographic order, so CGAL's perturbation becomes pcl_vts' (smallest point
/// perturbed most) and with cocircular ties the result is still comparable.
std::vector<IndexTriangle> cgalDelaunayMirrored(const std::vector<Point2>& points);

/// Canonical form for set comparison: each triangle rotated (orientation kept) so
/// its smallest id comes first, then the list sorted.
std::vector<IndexTriangle> canonicalTriangles(std::vector<IndexTriangle> triangles);

/// Same, from a flat list (3 ids per triangle) with every id mapped through map.
std::vector<IndexTriangle> canonicalTriangles(const std::vector<std::uint32_t>& flat,
                                              const std::vector<std::uint32_t>& map);

} // namespace test
} // namespace pcl_vts
