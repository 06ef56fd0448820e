// Adaptivity for clustered input: a uniform grid sized by the average density puts
// thousands of points in one cell when the points are clustered, and every search
// touching that cell would test them all. Cells holding more than CROWDED_CELL_POINTS
// points get a quadtree of sub-cells over their points, which the widening search
// descends like the pyramid above the cells.
#pragma once

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/export.h>

#include <cstdint>
#include <vector>

namespace pcl_vts {

/// Cells with more points than this are subdivided.
constexpr std::uint32_t CROWDED_CELL_POINTS = 32;

/// A node of the quadtree inside a crowded cell. Its points are grid.points[begin,
/// end); [x0, x1] x [y0, y1] is their exact bounding box (empty nodes keep their
/// parent's box).
struct SubCell {
  double x0, y0, x1, y1;
  std::uint32_t begin, end;
  std::uint32_t first_child; ///< 4 consecutive SubCells, or INVALID_ID for a leaf
};

struct CellSubdivision {
  std::vector<SubCell> nodes;
  /// Per grid cell: its quadtree root in nodes, or INVALID_ID (not crowded).
  std::vector<std::uint32_t> root;
  bool any() const { return !nodes.empty(); }
};

/// Builds the quadtrees of the crowded cells, reordering each crowded cell's points.
/// \param[in,out] grid points of crowded cells are permuted within their cell
/// \param[out] sub the quadtrees
/// \param[out] old_slot per grid slot after the call: the slot it held before (the
///             identity when nothing was crowded; then left empty)
PCL_VTS_CORE_EXPORT void subdivideCrowdedCells(CellGrid& grid, CellSubdivision& sub,
                                               std::vector<std::uint32_t>& old_slot);

} // namespace pcl_vts
