// Stage 2: Delaunay triangulation by region growing (VTS, thesis section 3.6). From
// seed Delaunay edges, every open edge of the growing region asks the mediatrix
// search for its third point on the open side; each answer is the unique Delaunay
// triangle of the perturbed point set, so triangles never overlap and the growth
// stops exactly when the hull is tiled. Hull edges are never searched. The grid's
// columns are cut into strips grown independently (in parallel) and merged.
#pragma once

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/cell_pyramid.h>
#include <pcl_vts/core/export.h>
#include <pcl_vts/core/mediatrix_search.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <functional>
#include <vector>

namespace pcl_vts {

/// Most triangles one mesh can hold: 3 halfedges per triangle with 32-bit ids, the
/// top values reserved (strip_growth.h). A Delaunay mesh of n points with h on the
/// hull has 2n - h - 2 triangles, so about 357.9 million points fit.
constexpr std::size_t MAX_MESH_TRIANGLES = 0x7ffffffeu / 3;

/// CAPACITY_EXCEEDED, with a message naming the limit, when `points` distinct points
/// with `hull_vertices` of them on the convex hull need more than MAX_MESH_TRIANGLES.
PCL_VTS_CORE_EXPORT Status checkTriangleCapacity(std::size_t points,
                                                 std::size_t hull_vertices);

/// Triangulates the grid points.
/// \param[in] grid distinct points in cell order
/// \param[in] pyramid occupancy pyramid of grid
/// \param[in] subdivision quadtrees of the crowded cells
/// \param[in] hull CCW convex hull of grid.points (convexHull), at least 3 vertices
/// \param[out] triangles 3 grid point ids per triangle, CCW
/// \param[out] halfedges twin per halfedge, INVALID_ID on the hull
/// \param[out] stats search statistics
/// \param[in] threads threads growing strips (0 or 1: one); the output is identical
///            for every value
/// \param[in] strip_columns strip width in columns, a power of two; 0 = automatic
/// \param[in] cache_blocks add the triangles proven by block-local triangulations
///            first (docs/scaling.md, "Cache blocks"): the same triangles, another
///            order
/// \param[in] grown when set, called once every strip is grown, before the last
///            strips are appended to the output (its peak) and before the border
///            halfedges are paired: grid, pyramid and subdivision are not read after
///            it, so it may release them
/// \return CAPACITY_EXCEEDED (checkTriangleCapacity), INTERNAL_ERROR if the region
///         growing failed to tile the hull (a bug)
PCL_VTS_CORE_EXPORT Status triangulateGrid(
    const CellGrid& grid, const CellPyramid& pyramid,
    const CellSubdivision& subdivision, const std::vector<VertexId>& hull,
    std::vector<VertexId>& triangles, std::vector<HalfedgeId>& halfedges,
    SearchStats& stats, unsigned threads = 1, std::uint32_t strip_columns = 0,
    bool cache_blocks = false, const std::function<void()>& grown = nullptr);

} // namespace pcl_vts
