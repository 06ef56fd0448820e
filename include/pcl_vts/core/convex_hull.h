// The convex hull of the distinct XY points, with every point lying on a hull edge
// kept (collinear boundary points are vertices of the triangulation's boundary).
// Hull edges are the boundary of the Delaunay triangulation: the region growing
// never searches beyond them, and the first hull edge is the seed edge.
#pragma once

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/cell_pyramid.h>
#include <pcl_vts/core/export.h>
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>

#include <vector>

namespace pcl_vts {

/// Convex hull by Akl-Toussaint filtering and Andrew's monotone chain, exact
/// predicates throughout.
/// \param[in] points distinct points (no two equal)
/// \param[out] hull vertex ids, counter-clockwise, starting at the lexicographically
///             smallest point; points on hull edges included
/// \param[in] candidates when given, a superset of the points that can lie on the
///            hull boundary (gridHullCandidates); default: every point
/// \return TOO_FEW_POINTS for < 3 points, ALL_COLLINEAR when the hull has no area
PCL_VTS_CORE_EXPORT Status
convexHull(const std::vector<Point2>& points, std::vector<VertexId>& hull,
           const std::vector<VertexId>* candidates = nullptr);

/// Points of the grid that may lie on the hull boundary: those in cells without a
/// filled cell two or more steps away in each of the four axis directions (in their
/// row and column), so about the perimeter's cells. The row and column ends are read
/// from the occupancy bits of `pyramid` (the grid's, buildCellPyramid), built here
/// when it is null.
PCL_VTS_CORE_EXPORT std::vector<VertexId>
gridHullCandidates(const CellGrid& grid, const CellPyramid* pyramid = nullptr);

} // namespace pcl_vts
