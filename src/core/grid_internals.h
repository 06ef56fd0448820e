// What buildCellGrid / subdivideCrowdedCells share with the pipeline's grid stage
// (grid_stage.cpp), so that both build the same grid: the geometry chosen from the
// points' XY bounding box and the quadtree of one crowded cell. Internal to the core.
#pragma once

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/cell_subdivision.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace detail {

/// Columns (or rows) over `extent` of the occupancy count at cell size `size`.
std::size_t occupancyColumns(double extent, double size);

/// The cell size asked for (clamped to the extent), or defaultCellSize when 0.
double initialCellSize(double cell_size, double width, double height, std::size_t n);

/// Inputs below this many points keep the area-based cell size (refinedCellSize).
constexpr std::size_t REFINE_MIN_POINTS = std::size_t{1} << 16;

/// The automatic cell size refined for clustered data, given the number of occupied
/// cells of side `size` anchored at the bounding box's min (occupancyColumns wide);
/// `size` itself below REFINE_MIN_POINTS points.
double refinedCellSize(double width, double height, std::size_t n, double size,
                       std::size_t occupied);

/// Sets origin, cell size, nx, ny and slack; INVALID_PARAMETER when the cell size
/// gives an absurd number of cells.
Status setGridGeometry(double xmin, double ymin, double width, double height,
                       std::size_t n, double size, CellGrid& grid);

/// Builds the quadtree of crowded cell (i, j) over the slots [begin, end): slot k
/// holds points[slots[k - offset]]. Appends the nodes to `nodes`, the root first (its
/// children's indices are into `nodes`), and permutes slots[begin - offset, end -
/// offset) into the leaves' order.
void subdivideCell(const CellGrid& grid, std::uint32_t i, std::uint32_t j,
                   const Point2* points, std::uint32_t* slots, std::uint32_t offset,
                   std::uint32_t begin, std::uint32_t end, std::vector<SubCell>& nodes);

} // namespace detail
} // namespace pcl_vts
