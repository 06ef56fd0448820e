// Unit tests of the first stages: the cell grid (bounds, cell order, lexicographic
// order inside a cell, thread independence, the cell limit), the convex hull (CCW from
// the smallest point, collinear boundary points kept, input order, candidates) and the
// duplicate merge (each rule, ties, input order, compaction of the grid).
#include "support/generators.h"

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/convex_hull.h>
#include <pcl_vts/core/merge_duplicates.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace pcl_vts {
namespace {

// 7 points on a 3 x 2 box, cell size 1: 4 x 3 cells; points 3 and 5 share XY.
const std::vector<Point2> SMALL = {{3.0, 2.0}, {0.0, 0.0},  {0.5, 0.25}, {0.25, 0.5},
                                   {1.5, 0.5}, {0.25, 0.5}, {2.0, 1.0}};

TEST(CellGrid, BoundsCellsAndOrderOfASmallSet)
{
  CellGrid grid;
  std::vector<std::uint32_t> order;
  ASSERT_TRUE(buildCellGrid(SMALL, 1.0, grid, order).ok());
  EXPECT_EQ(grid.origin_x, 0.0);
  EXPECT_EQ(grid.origin_y, 0.0);
  EXPECT_EQ(grid.cell_size, 1.0);
  EXPECT_EQ(grid.nx, 4u);
  EXPECT_EQ(grid.ny, 3u);
  // Cell 0 holds 1, 3, 5, 2 (x, then y, then input index); then cells 1, 6 and 11.
  EXPECT_EQ(order, (std::vector<std::uint32_t>{1, 3, 5, 2, 4, 6, 0}));
  EXPECT_EQ(grid.cell_start,
            (std::vector<std::uint32_t>{0, 4, 5, 5, 5, 5, 5, 6, 6, 6, 6, 6, 7}));
  for (std::size_t k = 0; k < order.size(); ++k)
    EXPECT_EQ(grid.points[k], SMALL[order[k]]) << k;
  EXPECT_EQ(grid.cellOf({3.0, 2.0}), 11u);
  EXPECT_EQ(grid.cellOf({1.5, 0.5}), 1u);
}

TEST(CellGrid, ColumnAndRowClampAndAreMonotone)
{
  CellGrid grid;
  std::vector<std::uint32_t> order;
  ASSERT_TRUE(buildCellGrid(SMALL, 1.0, grid, order).ok());
  EXPECT_EQ(grid.column(-1e300), 0u);
  EXPECT_EQ(grid.column(std::nan("")), 0u);
  EXPECT_EQ(grid.column(1e300), grid.nx - 1);
  EXPECT_EQ(grid.row(-5.0), 0u);
  EXPECT_EQ(grid.row(2.0), 2u);
  EXPECT_EQ(grid.row(99.0), grid.ny - 1);
  std::uint32_t last = 0;
  for (double x = -1.0; x <= 4.0; x += 0.0625) {
    EXPECT_GE(grid.column(x), last) << x;
    last = grid.column(x);
  }
}

TEST(CellGrid, EveryPointInItsCellInLexicographicOrderForAnyThreadCount)
{
  const std::vector<double> xyz =
      test::generatePoints(test::Distribution::CLUSTERED, 20000, 3);
  std::vector<Point2> points;
  for (std::size_t i = 0; i < xyz.size(); i += 3)
    points.push_back({xyz[i], xyz[i + 1]});
  // Some exact duplicates, far apart in the input.
  for (std::size_t i = 0; i < 500; ++i)
    points.push_back(points[37 * i]);
  CellGrid one;
  std::vector<std::uint32_t> order_one;
  ASSERT_TRUE(buildCellGrid(points, 0.0, one, order_one, 1).ok());
  // The oracle: a stable sort by (cell, x, y, input index).
  std::vector<std::uint32_t> expected(points.size());
  std::iota(expected.begin(), expected.end(), 0u);
  std::sort(expected.begin(), expected.end(), [&](std::uint32_t a, std::uint32_t b) {
    return std::make_tuple(one.cellOf(points[a]), points[a].x, points[a].y, a) <
           std::make_tuple(one.cellOf(points[b]), points[b].x, points[b].y, b);
  });
  EXPECT_EQ(order_one, expected);
  ASSERT_EQ(one.cell_start.size(), one.cellCount() + 1);
  for (std::size_t c = 0; c < one.cellCount(); ++c)
    for (std::uint32_t k = one.cell_start[c]; k < one.cell_start[c + 1]; ++k)
      ASSERT_EQ(one.cellOf(one.points[k]), c);
  for (const unsigned threads : {2u, 5u}) {
    CellGrid many;
    std::vector<std::uint32_t> order_many;
    ASSERT_TRUE(buildCellGrid(points, 0.0, many, order_many, threads).ok());
    EXPECT_EQ(order_many, order_one) << threads;
    EXPECT_EQ(many.cell_start, one.cell_start) << threads;
    EXPECT_EQ(many.cell_size, one.cell_size) << threads;
  }
}

TEST(CellGrid, DefaultCellSizeFollowsAreaThenLength)
{
  // 100 x 100 with 5000 points: sqrt(100 * 100 * 2 / 5000) = 2.
  EXPECT_DOUBLE_EQ(defaultCellSize(100.0, 100.0, 5000), 2.0);
  // A thin strip: the length term wins (1000 * 2 / 1000 = 2 > sqrt(2)).
  EXPECT_DOUBLE_EQ(defaultCellSize(1000.0, 1.0, 1000), 2.0);
  // No extent: a unit cell, never 0.
  EXPECT_EQ(defaultCellSize(0.0, 0.0, 10), 1.0);
  EXPECT_EQ(defaultCellSize(0.0, 0.0, 0), 1.0);
}

TEST(CellGrid, CellLargerThanTheDataIsClampedAndTinyCellIsRejected)
{
  CellGrid grid;
  std::vector<std::uint32_t> order;
  ASSERT_TRUE(buildCellGrid(SMALL, 1e6, grid, order).ok());
  EXPECT_EQ(grid.cell_size, 3.0); // the extent
  EXPECT_EQ(grid.nx, 2u);
  EXPECT_EQ(grid.ny, 1u);
  const Status s = buildCellGrid(SMALL, 1e-6, grid, order);
  EXPECT_EQ(s.code, StatusCode::INVALID_PARAMETER);
  EXPECT_NE(s.message.find("cells for 7 points (limit 4194304)"), std::string::npos)
      << s.message;
}

// ---- Convex hull

// A 2 x 2 square with its edge midpoints and two inner points, scrambled.
const std::vector<Point2> SQUARE = {{1, 1}, {2, 2}, {0, 1}, {1, 0}, {0.5, 1.5},
                                    {2, 0}, {0, 2}, {1, 2}, {0, 0}, {2, 1}};
const std::vector<Point2> SQUARE_HULL = {{0, 0}, {1, 0}, {2, 0}, {2, 1},
                                         {2, 2}, {1, 2}, {0, 2}, {0, 1}};

std::vector<Point2> hullPoints(const std::vector<Point2>& points,
                               const std::vector<VertexId>& hull)
{
  std::vector<Point2> out;
  for (const VertexId v : hull)
    out.push_back(points[v]);
  return out;
}

TEST(ConvexHull, CounterClockwiseFromTheSmallestWithCollinearPointsKept)
{
  std::vector<VertexId> hull;
  ASSERT_TRUE(convexHull(SQUARE, hull).ok());
  EXPECT_EQ(hull, (std::vector<VertexId>{8, 3, 5, 9, 1, 7, 6, 2}));
  EXPECT_EQ(hullPoints(SQUARE, hull), SQUARE_HULL);
}

TEST(ConvexHull, IndependentOfInputOrder)
{
  std::vector<Point2> points = SQUARE;
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    std::shuffle(points.begin(), points.end(), rng);
    std::vector<VertexId> hull;
    ASSERT_TRUE(convexHull(points, hull).ok());
    EXPECT_EQ(hullPoints(points, hull), SQUARE_HULL) << trial;
  }
}

TEST(ConvexHull, TooFewAndCollinearAreErrors)
{
  std::vector<VertexId> hull;
  EXPECT_EQ(convexHull({{0, 0}, {1, 1}}, hull).code, StatusCode::TOO_FEW_POINTS);
  EXPECT_EQ(convexHull({}, hull).code, StatusCode::TOO_FEW_POINTS);
  const Status s = convexHull({{0, 0}, {3, 3}, {1, 1}, {2, 2}}, hull);
  EXPECT_EQ(s.code, StatusCode::ALL_COLLINEAR);
  EXPECT_NE(s.message.find("4"), std::string::npos) << s.message;
  // One ulp off the line is a triangle.
  ASSERT_TRUE(convexHull({{0, 0}, {3, 3}, {1, std::nextafter(1.0, 2.0)}}, hull).ok());
  EXPECT_EQ(hull, (std::vector<VertexId>{0, 1, 2}));
}

/// The candidates by the rule's definition, every cell tested: the filled cells
/// within one step of their row's or their column's first or last filled cell.
std::vector<VertexId> candidatesOfEveryCell(const CellGrid& grid)
{
  const std::uint32_t nx = grid.nx, ny = grid.ny;
  const auto filled = [&grid](CellId c) {
    return grid.cell_start[c + 1] > grid.cell_start[c];
  };
  std::vector<std::uint32_t> row_first(ny, nx), row_last(ny, 0), column_first(nx, ny),
      column_last(nx, 0);
  for (std::uint32_t j = 0; j < ny; ++j)
    for (std::uint32_t i = 0; i < nx; ++i)
      if (filled(grid.cellId(i, j))) {
        row_first[j] = std::min(row_first[j], i);
        row_last[j] = i;
        column_first[i] = std::min(column_first[i], j);
        column_last[i] = j;
      }
  std::vector<VertexId> candidates;
  for (std::uint32_t j = 0; j < ny; ++j)
    for (std::uint32_t i = 0; i < nx; ++i) {
      const CellId c = grid.cellId(i, j);
      if (!filled(c) || (i >= row_first[j] + 2 && i + 2 <= row_last[j] &&
                         j >= column_first[i] + 2 && j + 2 <= column_last[i]))
        continue;
      for (std::uint32_t k = grid.cell_start[c]; k < grid.cell_start[c + 1]; ++k)
        candidates.push_back(k);
    }
  return candidates;
}

/// The hull from the grid's candidates and from every point, on distinct points; the
/// candidates those of the rule tested on every cell, in the same order.
void expectCandidatesGiveTheSameHull(std::vector<Point2> points, double cell_size,
                                     const std::string& what)
{
  std::sort(points.begin(), points.end(), lexLess);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  CellGrid grid;
  std::vector<std::uint32_t> order;
  ASSERT_TRUE(buildCellGrid(points, cell_size, grid, order).ok()) << what;
  const std::vector<VertexId> candidates = gridHullCandidates(grid);
  EXPECT_EQ(candidates, candidatesOfEveryCell(grid)) << what;
  std::vector<VertexId> all, filtered;
  const Status s_all = convexHull(grid.points, all);
  const Status s_filtered = convexHull(grid.points, filtered, &candidates);
  EXPECT_EQ(s_filtered.code, s_all.code) << what;
  EXPECT_EQ(filtered, all) << what;
}

TEST(ConvexHull, GridCandidatesGiveTheSameHull)
{
  for (const auto d : test::allDistributions())
    for (const std::size_t n : {std::size_t{40}, std::size_t{5000}}) {
      const std::vector<double> xyz = test::generatePoints(d, n, 9);
      std::vector<Point2> points;
      for (std::size_t i = 0; i < xyz.size(); i += 3)
        points.push_back({xyz[i], xyz[i + 1]});
      expectCandidatesGiveTheSameHull(
          points, 0.0, test::distributionName(d) + " " + std::to_string(n));
    }
  // Concave shapes whose rows and columns have gaps (an annulus, an L, a star, blobs
  // far apart), on fine and coarse cells: the hull's points must all be candidates.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int shape = 0; shape < 4; ++shape)
    for (const double cell : {0.0, 0.05, 0.5, 3.0}) {
      std::vector<Point2> points;
      while (points.size() < 3000) {
        const double x = 20 * unit(rng) - 10, y = 20 * unit(rng) - 10;
        const double r = std::hypot(x, y), a = std::atan2(y, x);
        const bool keep = shape == 0   ? r > 7 && r < 9
                          : shape == 1 ? x < -6 || y < -6
                          : shape == 2 ? r < 3 + 6 * std::pow(std::cos(2.5 * a), 8)
                                       : std::hypot(x - 8, y - 8) < 1.5 ||
                                             std::hypot(x + 8, y - 1) < 0.7 ||
                                             std::hypot(x - 2, y + 9) < 0.4;
        if (keep)
          points.push_back({x, y});
      }
      expectCandidatesGiveTheSameHull(points, cell,
                                      "shape " + std::to_string(shape) + " cell " +
                                          std::to_string(cell));
    }
  // Small sets on coarse cells: grids of one or a few rows or columns, columns and
  // rows of one, two or three filled cells.
  for (int trial = 0; trial < 120; ++trial) {
    std::vector<Point2> points;
    const double width = 1.0 + 4.0 * (trial % 4), height = 1.0 + 3.0 * (trial % 3);
    while (points.size() < 3 + static_cast<std::size_t>(trial % 11))
      points.push_back({width * unit(rng), height * unit(rng)});
    expectCandidatesGiveTheSameHull(points, 0.4 + 0.3 * (trial % 5),
                                    "small set " + std::to_string(trial));
  }
  // The filter does filter: on 20000 uniform points (100 x 100 cells) about the
  // perimeter's cells are left (about 8 % of the points), not a share of the area's.
  const std::vector<double> xyz =
      test::generatePoints(test::Distribution::UNIFORM, 20000, 3);
  std::vector<Point2> points;
  for (std::size_t i = 0; i < xyz.size(); i += 3)
    points.push_back({xyz[i], xyz[i + 1]});
  CellGrid grid;
  std::vector<std::uint32_t> order;
  ASSERT_TRUE(buildCellGrid(points, 0.0, grid, order).ok());
  EXPECT_LT(gridHullCandidates(grid).size(), grid.points.size() / 8);
}

// ---- Duplicate merge

struct Merged {
  CellGrid grid;
  std::vector<double> z;
  std::vector<std::uint32_t> source;
  std::vector<VertexId> slot_to_vertex;
  std::size_t folded = 0;
};

Merged merge(const std::vector<Point2>& points, const std::vector<double>& z,
             DuplicateRule rule)
{
  Merged m;
  std::vector<std::uint32_t> order;
  EXPECT_TRUE(buildCellGrid(points, 1.0, m.grid, order).ok());
  for (const std::uint32_t o : order) {
    m.z.push_back(z[o]);
    m.source.push_back(o);
  }
  m.folded = mergeDuplicates(m.grid, rule, m.z, m.source, m.slot_to_vertex);
  return m;
}

/// z and source of the vertex at XY p.
std::pair<double, std::uint32_t> vertexAt(const Merged& m, Point2 p)
{
  for (std::size_t v = 0; v < m.grid.points.size(); ++v)
    if (m.grid.points[v] == p)
      return {m.z[v], m.source[v]};
  ADD_FAILURE() << "no vertex at " << p.x << ", " << p.y;
  return {0.0, 0};
}

TEST(MergeDuplicates, EachRuleOnASmallSet)
{
  // Points 3 (z 5) and 5 (z 2) share XY (0.25, 0.5).
  const std::vector<double> z = {0, 1, 2, 5, 3, 2, 4};
  const struct {
    DuplicateRule rule;
    double z;
    std::uint32_t source;
  } cases[] = {{DuplicateRule::LOWEST_Z, 2.0, 5},
               {DuplicateRule::HIGHEST_Z, 5.0, 3},
               {DuplicateRule::MEAN_Z, 3.5, 3},
               {DuplicateRule::FIRST, 5.0, 3}};
  for (const auto& c : cases) {
    SCOPED_TRACE(duplicateRuleName(c.rule));
    const Merged m = merge(SMALL, z, c.rule);
    EXPECT_EQ(m.folded, 1u);
    // Slots 1 and 2 (inputs 3 and 5) fold into vertex 1; the rest shift down.
    EXPECT_EQ(m.slot_to_vertex, (std::vector<VertexId>{0, 1, 1, 2, 3, 4, 5}));
    EXPECT_EQ(
        m.grid.points,
        (std::vector<Point2>{
            {0.0, 0.0}, {0.25, 0.5}, {0.5, 0.25}, {1.5, 0.5}, {2.0, 1.0}, {3.0, 2.0}}));
    EXPECT_EQ(m.grid.cell_start,
              (std::vector<std::uint32_t>{0, 3, 4, 4, 4, 4, 4, 5, 5, 5, 5, 5, 6}));
    EXPECT_EQ(m.z.size(), 6u);
    EXPECT_EQ(m.source.size(), 6u);
    EXPECT_EQ(m.z[1], c.z);
    EXPECT_EQ(m.source[1], c.source);
    // Points without a twin keep their own z and source.
    EXPECT_EQ(m.z[0], 1.0);
    EXPECT_EQ(m.source[0], 1u);
    EXPECT_EQ(m.z[5], 0.0);
    EXPECT_EQ(m.source[5], 0u);
  }
}

TEST(MergeDuplicates, TiesGoToTheFirstInputPoint)
{
  // Four points at one XY: inputs 1, 2, 4 share the lowest and the highest z.
  const std::vector<Point2> points = {{0, 0}, {1, 1}, {1, 1}, {0, 1},
                                      {1, 1}, {1, 0}, {1, 1}};
  const std::vector<double> z = {0, 7, 7, 0, 7, 0, 8};
  const std::vector<double> low = {9, 3, 3, 0, 3, 0, 5};
  EXPECT_EQ(vertexAt(merge(points, z, DuplicateRule::LOWEST_Z), {1, 1}),
            std::make_pair(7.0, 1u));
  EXPECT_EQ(vertexAt(merge(points, low, DuplicateRule::HIGHEST_Z), {1, 1}),
            std::make_pair(5.0, 6u));
  const std::vector<double> high = {9, 6, 6, 0, 6, 0, 1};
  EXPECT_EQ(vertexAt(merge(points, high, DuplicateRule::HIGHEST_Z), {1, 1}),
            std::make_pair(6.0, 1u));
  EXPECT_EQ(vertexAt(merge(points, z, DuplicateRule::FIRST), {1, 1}),
            std::make_pair(7.0, 1u));
  EXPECT_EQ(vertexAt(merge(points, z, DuplicateRule::MEAN_Z), {1, 1}),
            std::make_pair(7.25, 1u));
  EXPECT_EQ(merge(points, z, DuplicateRule::LOWEST_Z).folded, 3u);
}

TEST(MergeDuplicates, InputOrderChangesOnlyWhatTheRuleSaysItDoes)
{
  // Reversing the input: lowest/highest/mean keep the same z (and lowest/highest the
  // same physical point); first keeps the point now first.
  const std::vector<Point2> points = {{0, 0}, {1, 1}, {1, 1}, {0, 1}, {1, 1}, {1, 0}};
  const std::vector<double> z = {0, 4, 2, 0, 9, 0};
  std::vector<Point2> reversed(points.rbegin(), points.rend());
  std::vector<double> reversed_z(z.rbegin(), z.rend());
  const auto back = [&](std::pair<double, std::uint32_t> v) {
    return std::make_pair(v.first,
                          static_cast<std::uint32_t>(points.size() - 1 - v.second));
  };
  for (const DuplicateRule rule : {DuplicateRule::LOWEST_Z, DuplicateRule::HIGHEST_Z,
                                   DuplicateRule::FIRST, DuplicateRule::MEAN_Z}) {
    SCOPED_TRACE(duplicateRuleName(rule));
    const auto forward = vertexAt(merge(points, z, rule), {1, 1});
    const auto backward = back(vertexAt(merge(reversed, reversed_z, rule), {1, 1}));
    if (rule == DuplicateRule::FIRST)
      continue;
    EXPECT_EQ(backward.first, forward.first);
    if (rule != DuplicateRule::MEAN_Z) {
      EXPECT_EQ(backward.second, forward.second);
    }
  }
  EXPECT_EQ(vertexAt(merge(points, z, DuplicateRule::FIRST), {1, 1}),
            std::make_pair(4.0, 1u));
  EXPECT_EQ(back(vertexAt(merge(reversed, reversed_z, DuplicateRule::FIRST), {1, 1})),
            std::make_pair(9.0, 4u));
  EXPECT_EQ(vertexAt(merge(points, z, DuplicateRule::LOWEST_Z), {1, 1}),
            std::make_pair(2.0, 2u));
  EXPECT_EQ(vertexAt(merge(points, z, DuplicateRule::HIGHEST_Z), {1, 1}),
            std::make_pair(9.0, 4u));
  EXPECT_EQ(vertexAt(merge(points, z, DuplicateRule::MEAN_Z), {1, 1}).first, 5.0);
}

TEST(MergeDuplicates, NoDuplicatesChangesNothing)
{
  const std::vector<Point2> points = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  const Merged m = merge(points, {1, 2, 3, 4}, DuplicateRule::MEAN_Z);
  EXPECT_EQ(m.folded, 0u);
  EXPECT_EQ(m.slot_to_vertex, (std::vector<VertexId>{0, 1, 2, 3}));
  EXPECT_EQ(m.source.size(), 4u);
}

} // namespace
} // namespace pcl_vts
