// Stage 1 of the pipeline: bucket the XY points into a uniform grid of square cells
// with a counting sort (flat arrays, no vector per cell). Points are stored grouped by
// cell, row-major, and lexicographically inside a cell, so equal XY become neighbours.
// Cell lookup is a monotone floating-point function of x (and y): the search relies on
// that, not on exact cell bounds (docs/algorithm.md, "Why the stop rule is exact").
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {

struct CellGrid {
  double origin_x = 0.0; ///< lower-left corner of cell (0, 0): the XY bounding-box min
  double origin_y = 0.0;
  double cell_size = 0.0; ///< edge length of a square cell
  double inv_cell_size = 0.0;
  std::uint32_t nx = 0; ///< cells along x
  std::uint32_t ny = 0; ///< cells along y
  /// How far (at most) a point may lie outside the nominal rectangle of its cell,
  /// from rounding in the cell computation. Searches widen cells by this much.
  double slack = 0.0;
  std::vector<std::uint32_t> cell_start; ///< nx*ny + 1 offsets into points
  std::vector<Point2> points;            ///< grouped by cell
  /// The offsets held compactly instead (compactCellStarts; cell_start is then
  /// empty): cell c starts at block_start[c / 16] + cell_offset[c].
  std::vector<std::uint32_t> block_start;
  std::vector<std::uint8_t> cell_offset;

  std::size_t cellCount() const { return static_cast<std::size_t>(nx) * ny; }
  /// Cell c's first slot in points (c = cellCount(): the point count): cell_start[c]
  /// in either form.
  std::uint32_t start(std::size_t c) const
  {
    return cell_start.empty() ? block_start[c >> 4] + cell_offset[c] : cell_start[c];
  }
  CellId cellId(std::uint32_t i, std::uint32_t j) const { return j * nx + i; }
  /// Column of x, clamped to [0, nx-1]; monotone non-decreasing in x.
  std::uint32_t column(double x) const
  {
    return clampIndex((x - origin_x) * inv_cell_size, nx);
  }
  /// Row of y, clamped to [0, ny-1]; monotone non-decreasing in y.
  std::uint32_t row(double y) const
  {
    return clampIndex((y - origin_y) * inv_cell_size, ny);
  }
  CellId cellOf(const Point2& p) const { return cellId(column(p.x), row(p.y)); }

  /// The column and row rule: floor(t) clamped to [0, n - 1] (0 when t is NaN),
  /// `limit` being n as a double (the grid stage's lookups keep it converted).
  static std::uint32_t clampIndex(double t, double limit, std::uint32_t n)
  {
    if (!(t > 0.0))
      return 0;
    if (t >= limit)
      return n - 1;
    return static_cast<std::uint32_t>(t);
  }

 private:
  static std::uint32_t clampIndex(double t, std::uint32_t n)
  {
    return clampIndex(t, static_cast<double>(n), n);
  }
};

/// Replaces cell_start by block_start + cell_offset (1.25 bytes a cell instead of 4)
/// when the grid has over two cells a point (clustered input) and every block of 16
/// cells starts its cells within 255 slots of its first; else leaves the grid as is.
PCL_VTS_CORE_EXPORT void compactCellStarts(CellGrid& grid);

/// Average points per cell targeted by the automatic cell size.
constexpr double DEFAULT_POINTS_PER_CELL = 2.0;

/// Cell size from the point density: sqrt(area * k / n) over the XY bounding box,
/// but never so small that one row or column gets more than n / k cells (thin strips).
PCL_VTS_CORE_EXPORT double defaultCellSize(double width, double height, std::size_t n);

/// Buckets points into a grid. `cell_size` 0 means automatic: defaultCellSize(), then
/// shrunk (up to 4 cells per point) when the occupied cells hold over twice the
/// target count, as clustered data does.
/// \param[in] points XY of n points (finite).
/// \param[out] grid the grid; grid.points holds the points in cell order.
/// \param[out] order per grid slot k: the index in `points` it came from.
/// \param[in] threads threads for the gather and the per-cell sort (same result for
///            any number)
/// \return INVALID_PARAMETER when the cell size would give an absurd number of cells.
PCL_VTS_CORE_EXPORT Status buildCellGrid(const std::vector<Point2>& points,
                                         double cell_size, CellGrid& grid,
                                         std::vector<std::uint32_t>& order,
                                         unsigned threads = 1);

} // namespace pcl_vts
