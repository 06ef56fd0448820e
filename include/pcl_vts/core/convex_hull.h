// The convex hull of the distinct XY points, with every point lying on a hull edge
// kept (collinear boundary points are vertices of the triangulation's boundary).
// Hull edges are the boundary of the Delaunay triangulation: the region growing
// never searches beyond them, and the first hull edge is the seed edge.
#pragma once

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>

#include <vector>

namespace pcl_vts {

/// Convex hull by Akl-Toussaint filtering and Andrew's monotone chain, exact
/// predicates throughout.
/// \param[in] points distinct points (no two equal)
/// \param[out] hull vertex ids, counter-clockwise, starting at the lexicographically
///             smallest point; points on hull edges included
/// \return TOO_FEW_POINTS for < 3 points, ALL_COLLINEAR when the hull has no area
Status convexHull(const std::vector<Point2>& points, std::vector<VertexId>& hull);

} // namespace pcl_vts
