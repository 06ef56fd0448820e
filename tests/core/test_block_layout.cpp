// The cache blocks' layout (src/core/strip_growth.h, blockColumnEnd and blockBandEnd):
// a thin rest of columns or rows at the grid's right side or top is joined to the
// blocks before it, the rows only while every block stays within MAX_BLOCK_POINTS.
// The triangulation is the same for any layout (test_cache_blocks); these tests pin
// the rule itself, so that a loosened or dropped rule fails here.
#include "../../src/core/strip_growth.h"

#include <pcl_vts/core/cell_grid.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace {

using detail::blockBandEnd;
using detail::blockColumnEnd;
using detail::MAX_BLOCK_POINTS;

/// A 105 x 105 grid of unit cells, `per_cell` distinct points in each cell of a row
/// below `dense_from`, `dense` points in each cell from that row on.
CellGrid gridOf(std::uint32_t per_cell, std::uint32_t dense_from, std::uint32_t dense)
{
  constexpr std::uint32_t SIDE = 105;
  std::vector<Point2> points;
  for (std::uint32_t j = 0; j < SIDE; ++j)
    for (std::uint32_t i = 0; i < SIDE; ++i) {
      const std::uint32_t m = j < dense_from ? per_cell : dense;
      for (std::uint32_t k = 0; k < m; ++k)
        points.push_back({i + 0.05 + 0.9 * (k + 1.0) / (m + 1.0), j + 0.5});
    }
  CellGrid grid;
  std::vector<std::uint32_t> order;
  EXPECT_TRUE(buildCellGrid(points, 1.0, grid, order).ok());
  return grid;
}

std::vector<std::uint32_t> bandEnds(const CellGrid& grid)
{
  std::vector<std::uint32_t> ends;
  for (std::uint32_t j0 = 0; j0 < grid.ny; j0 = ends.back())
    ends.push_back(blockBandEnd(grid, 0, grid.nx, j0, 32));
  return ends;
}

TEST(BlockLayout, AThinRestOfColumnsJoinsTheLastBlock)
{
  EXPECT_EQ(blockColumnEnd(0, 105, 32), 32u);
  EXPECT_EQ(blockColumnEnd(64, 105, 32), 105u); // 9 columns left: joined
  EXPECT_EQ(blockColumnEnd(64, 111, 32), 111u); // 15 left: joined
  EXPECT_EQ(blockColumnEnd(64, 112, 32), 96u);  // 16 left: a block of their own
  EXPECT_EQ(blockColumnEnd(0, 20, 32), 20u);    // a narrow strip: one block
  EXPECT_EQ(blockColumnEnd(0, 64, 32), 32u);
  EXPECT_EQ(blockColumnEnd(32, 64, 32), 64u);
}

TEST(BlockLayout, AThinRestOfRowsJoinsTheBandBelowWithinTheBudget)
{
  // One point a cell (ISPRS FSite8's grid: 105 x 105 cells, 1.17 points a cell):
  // 96 rows, the cap, then a rest of 9 rows joined: one band.
  const CellGrid sparse = gridOf(1, 105, 1);
  ASSERT_EQ(sparse.nx, 105u);
  ASSERT_EQ(sparse.ny, 105u);
  EXPECT_EQ(bandEnds(sparse), (std::vector<std::uint32_t>{105}));
  // The top 9 rows crowded: the joined band's first block would hold
  // 32 * 96 + 32 * 9 * 11 points, over the budget, so the rest stays a band.
  const CellGrid crowded_top = gridOf(1, 96, 11);
  ASSERT_EQ(crowded_top.ny, 105u);
  ASSERT_GT(detail::windowPoints(crowded_top, {0, 32, 0, 105}), MAX_BLOCK_POINTS);
  EXPECT_EQ(bandEnds(crowded_top), (std::vector<std::uint32_t>{96, 105}));
  // Two points a cell: the last block (41 columns) of 64 rows would hold 5248
  // points, so the bands are one block tall, until the last one: 41 rows left, a
  // band of them within the budget.
  const CellGrid dense = gridOf(2, 105, 2);
  EXPECT_EQ(bandEnds(dense), (std::vector<std::uint32_t>{32, 64, 105}));
  // Every band taller than one block row keeps each block within the budget.
  for (const CellGrid* grid : {&sparse, &crowded_top, &dense}) {
    std::uint32_t j0 = 0;
    for (const std::uint32_t j1 : bandEnds(*grid)) {
      if (j1 - j0 > 32)
        for (std::uint32_t i0 = 0, i1 = 0; i0 < grid->nx; i0 = i1) {
          i1 = blockColumnEnd(i0, grid->nx, 32);
          EXPECT_LE(detail::windowPoints(*grid, {i0, i1, j0, j1}), MAX_BLOCK_POINTS);
        }
      j0 = j1;
    }
  }
}

} // namespace
} // namespace pcl_vts
