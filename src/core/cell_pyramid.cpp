#include <pcl_vts/core/cell_pyramid.h>
#include <pcl_vts/core/parallel_for.h>

#include <algorithm>
#include <cstdint>

namespace pcl_vts {
namespace {

/// Threads for `rows` rows of `columns` cells: one per 65536 cells at most
/// (usefulThreads), none without rows.
unsigned rowThreads(unsigned threads, std::size_t rows, std::size_t columns)
{
  return static_cast<unsigned>(
      std::min<std::size_t>(usefulThreads(threads, rows * columns), rows));
}

void shape(CellPyramid::Level& level, std::uint32_t nx, std::uint32_t ny)
{
  level.nx = nx;
  level.ny = ny;
  level.row_words = (nx + 63) / 64;
  level.occupied.assign(static_cast<std::size_t>(level.row_words) * ny, 0);
}

} // namespace

void startCellPyramid(std::uint32_t nx, std::uint32_t ny, CellPyramid& pyramid)
{
  pyramid.levels.assign(1, CellPyramid::Level{});
  shape(pyramid.levels[0], nx, ny);
}

void buildCellPyramid(const CellGrid& grid, CellPyramid& pyramid, unsigned threads)
{
  startCellPyramid(grid.nx, grid.ny, pyramid);
  CellPyramid::Level& base = pyramid.levels[0];
  parallelChunks(rowThreads(threads, grid.ny, grid.nx), grid.ny,
                 [&](std::size_t j0, std::size_t j1, unsigned) {
                   for (std::size_t j = j0; j < j1; ++j) {
                     const std::uint32_t* start = &grid.cell_start[j * grid.nx];
                     std::uint64_t* out = &base.occupied[j * base.row_words];
                     for (std::uint32_t i = 0; i < grid.nx; ++i)
                       if (start[i + 1] > start[i])
                         out[i >> 6] |= std::uint64_t{1} << (i & 63u);
                   }
                 });
  buildCellPyramidLevels(pyramid, threads);
}

void buildCellPyramidLevels(CellPyramid& pyramid, unsigned threads)
{
  pyramid.levels.resize(1);
  while (pyramid.levels.back().nx > 1 || pyramid.levels.back().ny > 1) {
    const CellPyramid::Level& fine = pyramid.levels.back();
    CellPyramid::Level coarse;
    shape(coarse, (fine.nx + 1) / 2, (fine.ny + 1) / 2);
    // Row by row of the coarse level: each reads its two fine rows.
    const auto rows = [&](std::size_t j0, std::size_t j1) {
      for (std::size_t j = j0; j < j1; ++j) {
        const std::uint64_t* row0 = &fine.occupied[2 * j * fine.row_words];
        const std::uint64_t* row1 = 2 * j + 1 < fine.ny ? row0 + fine.row_words : row0;
        std::uint64_t* out = &coarse.occupied[j * coarse.row_words];
        for (std::uint32_t i = 0; i < coarse.nx; ++i) {
          // Fine columns 2i and 2i + 1 share a word (2i is even); bits past fine.nx
          // are 0.
          const std::uint32_t f = 2 * i;
          const std::uint64_t both = (row0[f >> 6] | row1[f >> 6]) >> (f & 63u);
          if ((both & 3u) != 0)
            out[i >> 6] |= std::uint64_t{1} << (i & 63u);
        }
      }
    };
    parallelChunks(rowThreads(threads, coarse.ny, coarse.nx), coarse.ny,
                   [&](std::size_t j0, std::size_t j1, unsigned) { rows(j0, j1); });
    pyramid.levels.push_back(std::move(coarse));
  }
}

} // namespace pcl_vts
