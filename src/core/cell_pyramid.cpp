#include <pcl_vts/core/cell_pyramid.h>
#include <pcl_vts/core/parallel_for.h>

#include <algorithm>
#include <cstdint>

namespace pcl_vts {
namespace {

/// Threads for `rows` rows of `columns` cells: one per 65536 cells at most.
unsigned rowThreads(unsigned threads, std::size_t rows, std::size_t columns)
{
  constexpr std::size_t MIN_CELLS_PER_THREAD = 1u << 16;
  const std::size_t useful =
      std::max<std::size_t>(1, rows * columns / MIN_CELLS_PER_THREAD);
  return static_cast<unsigned>(std::min<std::size_t>({threads, useful, rows}));
}

} // namespace

void buildCellPyramid(const CellGrid& grid, CellPyramid& pyramid, unsigned threads)
{
  pyramid.levels.clear();
  CellPyramid::Level base;
  base.nx = grid.nx;
  base.ny = grid.ny;
  base.occupied.resize(grid.cellCount());
  parallelRanges(threads, grid.cellCount(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c)
      base.occupied[c] = grid.cell_start[c + 1] > grid.cell_start[c] ? 1 : 0;
  });
  pyramid.levels.push_back(std::move(base));
  while (pyramid.levels.back().nx > 1 || pyramid.levels.back().ny > 1) {
    const CellPyramid::Level& fine = pyramid.levels.back();
    CellPyramid::Level coarse;
    coarse.nx = (fine.nx + 1) / 2;
    coarse.ny = (fine.ny + 1) / 2;
    coarse.occupied.resize(static_cast<std::size_t>(coarse.nx) * coarse.ny);
    // Row by row of the coarse level: each reads its two fine rows.
    const auto rows = [&](std::size_t j0, std::size_t j1) {
      for (std::size_t j = j0; j < j1; ++j) {
        const std::uint8_t* row0 = &fine.occupied[2 * j * fine.nx];
        const std::uint8_t* row1 = 2 * j + 1 < fine.ny ? row0 + fine.nx : row0;
        std::uint8_t* out = &coarse.occupied[j * coarse.nx];
        for (std::size_t i = 0; 2 * i + 1 < fine.nx; ++i)
          out[i] = static_cast<std::uint8_t>(row0[2 * i] | row0[2 * i + 1] |
                                             row1[2 * i] | row1[2 * i + 1]);
        if (fine.nx % 2 == 1)
          out[coarse.nx - 1] =
              static_cast<std::uint8_t>(row0[fine.nx - 1] | row1[fine.nx - 1]);
      }
    };
    parallelChunks(rowThreads(threads, coarse.ny, coarse.nx), coarse.ny,
                   [&](std::size_t j0, std::size_t j1, unsigned) { rows(j0, j1); });
    pyramid.levels.push_back(std::move(coarse));
  }
}

} // namespace pcl_vts
