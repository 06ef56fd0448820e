// Occupancy pyramid over the cell grid: level 0 flags the non-empty cells, level k+1
// merges 2x2 blocks of level k. The widening search descends it best-first, so a long
// edge over a void skips empty regions in O(log) blocks instead of scanning them.
#pragma once

#include <pcl_vts/core/cell_grid.h>

#include <cstdint>
#include <vector>

namespace pcl_vts {

struct CellPyramid {
  struct Level {
    std::uint32_t nx = 0;
    std::uint32_t ny = 0;
    std::vector<std::uint8_t> occupied; ///< nx * ny flags
  };
  std::vector<Level> levels; ///< levels[0] = cells; the last level is 1 x 1

  bool occupied(std::size_t level, std::uint32_t i, std::uint32_t j) const
  {
    const Level& l = levels[level];
    return l.occupied[static_cast<std::size_t>(j) * l.nx + i] != 0;
  }
};

/// Builds the pyramid of a grid. Linear in the number of cells.
void buildCellPyramid(const CellGrid& grid, CellPyramid& pyramid);

} // namespace pcl_vts
