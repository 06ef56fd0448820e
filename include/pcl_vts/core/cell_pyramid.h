// Occupancy pyramid over the cell grid: level 0 flags the non-empty cells, level k+1
// merges 2x2 blocks of level k. The widening search descends it best-first, so a long
// edge over a void skips empty regions in O(log) blocks instead of scanning them.
#pragma once

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/export.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace pcl_vts {

struct CellPyramid {
  struct Level {
    std::uint32_t nx = 0;
    std::uint32_t ny = 0;
    std::uint32_t row_words = 0; ///< 64-bit words per row: (nx + 63) / 64
    /// One bit per block, bit i % 64 of word j * row_words + i / 64 (rows padded to
    /// whole words, so that threads building different rows share no word): a bit a
    /// cell, not a byte, as clustered input has several empty cells a point.
    std::vector<std::uint64_t> occupied;
  };
  std::vector<Level> levels; ///< levels[0] = cells; the last level is 1 x 1

  bool occupied(std::size_t level, std::uint32_t i, std::uint32_t j) const
  {
    const Level& l = levels[level];
    return ((l.occupied[static_cast<std::size_t>(j) * l.row_words + (i >> 6)] >>
             (i & 63u)) &
            1u) != 0;
  }
};

/// Builds the pyramid of a grid. Linear in the number of cells; the same for any
/// number of threads.
PCL_VTS_CORE_EXPORT void buildCellPyramid(const CellGrid& grid, CellPyramid& pyramid,
                                          unsigned threads = 1);

/// The pyramid in two steps, for a caller that knows the occupied cells as it fills
/// the grid (the grid stage): level 0 of nx x ny cells, all empty (pyramid holds only
/// it), then, once the occupied cells' bits are set, the levels above it (the same
/// pyramid as buildCellPyramid's when the bits are the grid's non-empty cells).
PCL_VTS_CORE_EXPORT void startCellPyramid(std::uint32_t nx, std::uint32_t ny,
                                          CellPyramid& pyramid);
PCL_VTS_CORE_EXPORT void buildCellPyramidLevels(CellPyramid& pyramid,
                                                unsigned threads = 1);

/// An axis-aligned world rectangle.
struct BlockRect {
  double x0, y0, x1, y1;
  /// Squared distance from (px, py) to the rectangle (0 inside).
  double squaredDistance(double px, double py) const
  {
    const double dx = std::max({x0 - px, 0.0, px - x1});
    const double dy = std::max({y0 - py, 0.0, py - y1});
    return dx * dx + dy * dy;
  }
};

/// World rectangle of pyramid block (i, j) of `level`, widened by the grid slack:
/// every point bucketed into the block lies inside it.
inline BlockRect blockRect(const CellGrid& grid, std::uint32_t level, std::uint32_t i,
                           std::uint32_t j)
{
  const double span = grid.cell_size * static_cast<double>(1u << level);
  return {grid.origin_x + span * i - grid.slack, grid.origin_y + span * j - grid.slack,
          grid.origin_x + span * (i + 1) + grid.slack,
          grid.origin_y + span * (j + 1) + grid.slack};
}

/// Calls visit(ci, cj) for each occupied child, at level - 1, of block (i, j) of
/// `level` (> 0).
template <typename Visit>
void forEachOccupiedChild(const CellPyramid& pyramid, std::uint32_t level,
                          std::uint32_t i, std::uint32_t j, const Visit& visit)
{
  const CellPyramid::Level& fine = pyramid.levels[level - 1];
  for (std::uint32_t cj = 2 * j; cj < std::min(2 * j + 2, fine.ny); ++cj)
    for (std::uint32_t ci = 2 * i; ci < std::min(2 * i + 2, fine.nx); ++ci)
      if (pyramid.occupied(level - 1, ci, cj))
        visit(ci, cj);
}

} // namespace pcl_vts
