// The pipeline's grid stage (buildGridStage: bands of rows, each sorted by cell,
// merged and subdivided on its own) against the reference composition it replaces
// (the finite points, buildCellGrid, mergeDuplicates, subdivideCrowdedCells,
// buildCellPyramid): the same grid, vertex sources, input-to-vertex map (left empty
// when no point was merged: the inverse of the sources), quadtrees and pyramid, bit
// for bit, for 1, 2 and 3 threads, under every duplicate rule, on
// inputs with many bands, duplicates (some -0.0 against +0.0), crowded cells and
// non-finite points; and the same errors.
#include "support/generators.h"

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/cell_pyramid.h>
#include <pcl_vts/core/cell_subdivision.h>
#include <pcl_vts/core/grid_stage.h>
#include <pcl_vts/core/merge_duplicates.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace pcl_vts {
namespace {

/// The grid stage as the pipeline built it before buildGridStage, step by step.
Status referenceStage(const std::vector<double>& xyz, double cell_size,
                      DuplicateRule rule, GridStage& stage,
                      std::vector<VertexId>& input_to_vertex)
{
  const std::size_t n = xyz.size() / 3;
  std::vector<Point2> xy;
  std::vector<double> z;
  std::vector<std::uint32_t> source;
  for (std::size_t k = 0; k < n; ++k) {
    const double x = xyz[3 * k], y = xyz[3 * k + 1], h = xyz[3 * k + 2];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(h))
      continue;
    xy.push_back({x, y});
    z.push_back(h);
    source.push_back(static_cast<std::uint32_t>(k));
  }
  CellGrid& grid = stage.grid;
  std::vector<std::uint32_t> order;
  if (Status s = buildCellGrid(xy, cell_size, grid, order); !s.ok())
    return s;
  std::vector<double> vz;
  for (const std::uint32_t o : order) {
    vz.push_back(z[o]);
    stage.source.push_back(source[o]);
  }
  std::vector<VertexId> slot_to_vertex;
  mergeDuplicates(grid, rule, vz, stage.source, slot_to_vertex);
  std::vector<std::uint32_t> old_slot;
  subdivideCrowdedCells(grid, stage.subdivision, old_slot);
  if (!old_slot.empty()) {
    std::vector<VertexId> new_id(old_slot.size());
    std::vector<std::uint32_t> moved(old_slot.size());
    for (std::size_t k = 0; k < old_slot.size(); ++k) {
      new_id[old_slot[k]] = static_cast<VertexId>(k);
      moved[k] = stage.source[old_slot[k]];
    }
    stage.source.swap(moved);
    for (VertexId& v : slot_to_vertex)
      v = new_id[v];
  }
  input_to_vertex.assign(n, INVALID_ID);
  for (std::size_t k = 0; k < order.size(); ++k)
    input_to_vertex[source[order[k]]] = slot_to_vertex[k];
  buildCellPyramid(grid, stage.pyramid);
  return Status::success();
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b)
{
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expectSameStage(const GridStage& a, const std::vector<VertexId>& a_map,
                     const GridStage& b, const std::vector<VertexId>& b_map,
                     const std::string& what)
{
  EXPECT_EQ(a.grid.origin_x, b.grid.origin_x) << what;
  EXPECT_EQ(std::signbit(a.grid.origin_x), std::signbit(b.grid.origin_x)) << what;
  EXPECT_EQ(a.grid.origin_y, b.grid.origin_y) << what;
  EXPECT_EQ(a.grid.cell_size, b.grid.cell_size) << what;
  EXPECT_EQ(a.grid.inv_cell_size, b.grid.inv_cell_size) << what;
  EXPECT_EQ(a.grid.nx, b.grid.nx) << what;
  EXPECT_EQ(a.grid.ny, b.grid.ny) << what;
  EXPECT_EQ(a.grid.slack, b.grid.slack) << what;
  EXPECT_TRUE(a.grid.cell_start == b.grid.cell_start) << what;
  EXPECT_TRUE(sameBits(a.grid.points, b.grid.points)) << what; // -0.0 kept apart
  EXPECT_TRUE(a.source == b.source) << what;
  // buildGridStage leaves the map empty when no point was merged: it is then the
  // inverse of the sources.
  std::size_t finite = 0;
  for (const VertexId v : b_map)
    finite += v != INVALID_ID ? 1 : 0;
  EXPECT_EQ(a_map.empty(), finite == b.grid.points.size()) << what;
  std::vector<VertexId> inverse;
  if (a_map.empty()) {
    inverse.assign(b_map.size(), INVALID_ID);
    for (std::size_t v = 0; v < a.source.size(); ++v)
      inverse[a.source[v]] = static_cast<VertexId>(v);
  }
  EXPECT_TRUE((a_map.empty() ? inverse : a_map) == b_map) << what;
  EXPECT_TRUE(a.subdivision.root == b.subdivision.root) << what;
  ASSERT_EQ(a.subdivision.nodes.size(), b.subdivision.nodes.size()) << what;
  for (std::size_t k = 0; k < a.subdivision.nodes.size(); ++k) {
    const SubCell& p = a.subdivision.nodes[k];
    const SubCell& q = b.subdivision.nodes[k];
    ASSERT_TRUE(p.x0 == q.x0 && p.y0 == q.y0 && p.x1 == q.x1 && p.y1 == q.y1 &&
                p.begin == q.begin && p.end == q.end && p.first_child == q.first_child)
        << what << "node " << k;
  }
  ASSERT_EQ(a.pyramid.levels.size(), b.pyramid.levels.size()) << what;
  for (std::size_t l = 0; l < a.pyramid.levels.size(); ++l) {
    EXPECT_EQ(a.pyramid.levels[l].nx, b.pyramid.levels[l].nx) << what << l;
    EXPECT_EQ(a.pyramid.levels[l].ny, b.pyramid.levels[l].ny) << what << l;
    EXPECT_TRUE(a.pyramid.levels[l].occupied == b.pyramid.levels[l].occupied)
        << what << l;
  }
}

/// Clusters (crowded cells) in a sparse field, 1 point in 4 repeated elsewhere in
/// the input with another z (some with the same z, some at -0.0 against +0.0), a few
/// non-finite points: over 196608 points, so that 3 threads get a share each and
/// there are dozens of bands.
std::vector<double> hardInput(std::size_t n, std::uint64_t seed)
{
  std::vector<double> xyz =
      test::generatePoints(test::Distribution::CLUSTERED, n, seed);
  const std::vector<double> dense =
      test::generatePoints(test::Distribution::UNIFORM, n / 8, seed + 1);
  for (std::size_t k = 0; k < dense.size(); k += 3) { // a 1 x 1 patch: quadtrees
    xyz.push_back(500.0 + dense[k] * 1e-3);
    xyz.push_back(500.0 + dense[k + 1] * 1e-3);
    xyz.push_back(dense[k + 2]);
  }
  std::mt19937_64 rng(seed);
  const std::size_t count = xyz.size() / 3;
  for (std::size_t d = 0; d < count / 4; ++d) {
    const std::size_t from = rng() % count, to = rng() % count;
    xyz[3 * to] = xyz[3 * from];
    xyz[3 * to + 1] = xyz[3 * from + 1];
    if (d % 3 == 0)
      xyz[3 * to + 2] = xyz[3 * from + 2]; // a tie in z: the smaller index wins
  }
  // Signed zeros on one exact duplicate column (x = 0 and -0).
  for (std::size_t d = 0; d < 40; ++d) {
    const std::size_t k = rng() % count;
    xyz[3 * k] = d % 2 == 0 ? 0.0 : -0.0;
    xyz[3 * k + 1] = static_cast<double>(d % 7);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (std::size_t d = 0; d < 10; ++d)
    xyz[3 * (rng() % count) + d % 3] = d % 2 == 0 ? nan : -inf;
  return xyz;
}

TEST(GridStage, SameAsTheReferenceForEveryRuleAndThreadCount)
{
  const std::vector<double> xyz = hardInput(200000, 17);
  const std::size_t n = xyz.size() / 3;
  for (const DuplicateRule rule : {DuplicateRule::LOWEST_Z, DuplicateRule::HIGHEST_Z,
                                   DuplicateRule::MEAN_Z, DuplicateRule::FIRST}) {
    GridStage expected;
    std::vector<VertexId> expected_map;
    ASSERT_TRUE(referenceStage(xyz, 0.0, rule, expected, expected_map).ok());
    ASSERT_TRUE(expected.subdivision.any()); // the input does have crowded cells
    ASSERT_LT(expected.grid.points.size() + 1000, n); // and many duplicates
    for (const unsigned threads : {1u, 2u, 3u}) {
      GridStage stage;
      std::vector<VertexId> map;
      Diagnostics diag;
      ASSERT_TRUE(
          buildGridStage(xyz.data(), n, 0.0, rule, threads, stage, map, diag).ok());
      const std::string what = std::string(duplicateRuleName(rule)) + " threads " +
                               std::to_string(threads) + " ";
      expectSameStage(stage, map, expected, expected_map, what);
      std::size_t finite = 0;
      for (const VertexId v : expected_map)
        finite += v != INVALID_ID ? 1 : 0;
      EXPECT_EQ(diag.non_finite_dropped, n - finite) << what;
      EXPECT_EQ(diag.distinct_points, expected.grid.points.size()) << what;
      EXPECT_EQ(diag.duplicates_merged, finite - expected.grid.points.size()) << what;
      EXPECT_EQ(diag.cells, expected.grid.cellCount()) << what;
      EXPECT_EQ(diag.cell_size, expected.grid.cell_size) << what;
    }
  }
}

TEST(GridStage, SameAsTheReferenceOnOtherShapesAndCellSizes)
{
  const struct {
    test::Distribution distribution;
    std::size_t n;
    double cell_size;
  } cases[] = {
      {test::Distribution::UNIFORM, 150000, 0.0},
      {test::Distribution::JITTERED_GRID, 150000, 0.0},
      {test::Distribution::EXACT_GRID, 100000, 0.0},
      {test::Distribution::THIN_STRIP, 150000, 0.0}, // rows wider than a band
      {test::Distribution::DUPLICATES, 150000, 0.0},
      {test::Distribution::CLUSTERED, 150000, 25.0}, // crowded cells, asked size
      {test::Distribution::UTM_OFFSET, 100000, 0.0},
      {test::Distribution::FLOAT_ROUNDED, 100000, 0.0},
      {test::Distribution::UNIFORM, 20000, 2.0}, // one band's points, many bands' cells
      {test::Distribution::DUPLICATES, 20000, 0.0}, // one band
      {test::Distribution::THREE_POINTS, 3, 0.0},
      {test::Distribution::COLLINEAR, 1000, 0.0},
  };
  for (const auto& c : cases) {
    const std::vector<double> xyz = test::generatePoints(c.distribution, c.n, 5);
    const std::size_t n = xyz.size() / 3;
    GridStage expected;
    std::vector<VertexId> expected_map;
    ASSERT_TRUE(referenceStage(xyz, c.cell_size, DuplicateRule::LOWEST_Z, expected,
                               expected_map)
                    .ok());
    for (const unsigned threads : {1u, 3u}) {
      GridStage stage;
      std::vector<VertexId> map;
      Diagnostics diag;
      ASSERT_TRUE(buildGridStage(xyz.data(), n, c.cell_size, DuplicateRule::LOWEST_Z,
                                 threads, stage, map, diag)
                      .ok());
      expectSameStage(stage, map, expected, expected_map,
                      test::distributionName(c.distribution) + " threads " +
                          std::to_string(threads) + " ");
    }
  }
}

/// An input of one band (sorted straight from the input, no scatter into bands), every
/// point finite (the first pass's branch-free loop), half of the XY given twice as by
/// two passes over the same ground (another z, the same z one time in five: cells of
/// two equal points take their own path) and -0.0 against +0.0 at the smallest x, in
/// either order: the reference's stage for every rule and thread count, and the same
/// stage from the overload that builds no per-input map.
TEST(GridStage, OneBandOfPairsWithAndWithoutTheMap)
{
  for (const bool negative_first : {true, false}) {
    std::mt19937_64 rng(negative_first ? 3 : 4);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const std::size_t distinct = 12000;
    std::vector<double> xyz;
    for (std::size_t k = 0; k < distinct; ++k) {
      const double x = k == 0   ? (negative_first ? -0.0 : 0.0)
                       : k == 1 ? (negative_first ? 0.0 : -0.0)
                                : 1.0 + 100.0 * unit(rng);
      xyz.insert(xyz.end(), {x, 100.0 * unit(rng), unit(rng)});
    }
    for (std::size_t k = 2; k < distinct; k += 2) // the zeros once: the first one wins
      xyz.insert(xyz.end(), {xyz[3 * k], xyz[3 * k + 1],
                             k % 10 == 0 ? xyz[3 * k + 2] : unit(rng)});
    const std::size_t n = xyz.size() / 3;
    for (const DuplicateRule rule : {DuplicateRule::LOWEST_Z, DuplicateRule::HIGHEST_Z,
                                     DuplicateRule::MEAN_Z, DuplicateRule::FIRST}) {
      GridStage expected;
      std::vector<VertexId> expected_map;
      ASSERT_TRUE(referenceStage(xyz, 0.0, rule, expected, expected_map).ok());
      ASSERT_EQ(expected.grid.points.size(), distinct);
      ASSERT_EQ(expected.grid.origin_x, 0.0);
      ASSERT_EQ(std::signbit(expected.grid.origin_x), negative_first);
      for (const unsigned threads : {1u, 2u, 3u}) {
        const std::string what = std::string(duplicateRuleName(rule)) + " threads " +
                                 std::to_string(threads) +
                                 (negative_first ? " -0 first " : " +0 first ");
        GridStage stage;
        std::vector<VertexId> map;
        Diagnostics diag;
        ASSERT_TRUE(
            buildGridStage(xyz.data(), n, 0.0, rule, threads, stage, map, diag).ok());
        expectSameStage(stage, map, expected, expected_map, what);
        GridStage without;
        Diagnostics without_diag;
        ASSERT_TRUE(buildGridStage(xyz.data(), n, 0.0, rule, threads, without, nullptr,
                                   without_diag)
                        .ok());
        expectSameStage(without, map, expected, expected_map, what + "no map ");
        EXPECT_EQ(without_diag.duplicates_merged, diag.duplicates_merged) << what;
      }
    }
  }
}

/// The grid stage guesses from every 64th point whether the automatic cell size stays
/// and then lets the band sort count the occupied cells. Here that sample is uniform
/// while the other points pile up in a small patch: the count refines the size after
/// all, and the stage must build the grid again at the refined size (the reference's).
TEST(GridStage, SameAsTheReferenceWhenTheSampleMisleads)
{
  const std::size_t n = 80000; // above 2^16 points: the size may be refined
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> xyz;
  for (std::size_t k = 0; k < n; ++k) {
    const bool sampled = k % 64 == 0;
    const double x = sampled ? 1000.0 * unit(rng) : 400.0 + 20.0 * unit(rng);
    const double y = sampled ? 1000.0 * unit(rng) : 600.0 + 20.0 * unit(rng);
    xyz.insert(xyz.end(), {x, y, unit(rng)});
  }
  xyz[0] = xyz[1] = 0.0; // the bounding box: 1000 x 1000
  xyz[3 * 64] = xyz[3 * 64 + 1] = 1000.0;
  GridStage expected;
  std::vector<VertexId> expected_map;
  ASSERT_TRUE(
      referenceStage(xyz, 0.0, DuplicateRule::LOWEST_Z, expected, expected_map).ok());
  ASSERT_LT(expected.grid.cell_size,
            0.9 * defaultCellSize(1000.0, 1000.0, n)); // refined
  for (const unsigned threads : {1u, 2u}) {
    GridStage stage;
    std::vector<VertexId> map;
    Diagnostics diag;
    ASSERT_TRUE(buildGridStage(xyz.data(), n, 0.0, DuplicateRule::LOWEST_Z, threads,
                               stage, map, diag)
                    .ok());
    expectSameStage(stage, map, expected, expected_map,
                    "threads " + std::to_string(threads) + " ");
  }
}

TEST(GridStage, ErrorsNameTheFirstBadPoint)
{
  GridStage stage;
  std::vector<VertexId> map;
  Diagnostics diag;
  std::vector<double> xyz =
      test::generatePoints(test::Distribution::UNIFORM, 200000, 3);
  const std::size_t n = xyz.size() / 3;
  xyz[3 * 150000 + 1] = 2e60; // the first out of range, in the third thread's share
  xyz[3 * 190000] = -5e61;
  xyz[3 * 100000] = std::numeric_limits<double>::quiet_NaN(); // dropped, not an error
  xyz[3 * 100001 + 1] = 7e70; // non-finite z: dropped too
  xyz[3 * 100001 + 2] = std::numeric_limits<double>::infinity();
  for (const unsigned threads : {1u, 3u}) {
    const Status s = buildGridStage(xyz.data(), n, 0.0, DuplicateRule::LOWEST_Z,
                                    threads, stage, map, diag);
    EXPECT_EQ(s.code, StatusCode::COORDINATE_RANGE) << threads;
    EXPECT_NE(s.message.find("point 150000 has XY"), std::string::npos) << s.message;
  }
  EXPECT_EQ(
      buildGridStage(nullptr, 0, 0.0, DuplicateRule::LOWEST_Z, 2, stage, map, diag)
          .code,
      StatusCode::EMPTY_INPUT);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> none = {nan, 0, 0, 1, nan, 0};
  const Status empty =
      buildGridStage(none.data(), 2, 0.0, DuplicateRule::LOWEST_Z, 1, stage, map, diag);
  EXPECT_EQ(empty.code, StatusCode::EMPTY_INPUT);
  EXPECT_NE(empty.message.find("none of the 2 input points"), std::string::npos);
  const std::vector<double> tiny = {0, 0, 0, 1e-90, 0, 0, 0, 1e-90, 0};
  EXPECT_EQ(
      buildGridStage(tiny.data(), 3, 0.0, DuplicateRule::LOWEST_Z, 1, stage, map, diag)
          .code,
      StatusCode::COORDINATE_RANGE);
  const std::vector<double> square = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  EXPECT_EQ(buildGridStage(square.data(), 4, 1e-6, DuplicateRule::LOWEST_Z, 1, stage,
                           map, diag)
                .code,
            StatusCode::INVALID_PARAMETER);
}

/// compactCellStarts: on a sparse (clustered) grid every cell's start read through
/// the compact form equals the flat offsets; a dense grid, or a sparse one with a
/// cell over 255 points, keeps its flat offsets.
TEST(GridStage, CompactCellStartsKeepEveryOffset)
{
  const std::size_t n = 70000; // above 2^16: clustered input's cells are refined
  const auto build = [](const std::vector<double>& xyz, GridStage& stage) {
    std::vector<VertexId> map;
    Diagnostics diag;
    ASSERT_TRUE(buildGridStage(xyz.data(), xyz.size() / 3, 0.0, DuplicateRule::LOWEST_Z,
                               1, stage, map, diag)
                    .ok());
  };
  std::vector<double> xyz = test::generatePoints(test::Distribution::CLUSTERED, n, 7);
  GridStage stage;
  build(xyz, stage);
  const CellGrid& flat = stage.grid;
  ASSERT_GT(flat.cellCount(), 2 * flat.points.size()); // sparse: compacted
  CellGrid compact = flat;
  compactCellStarts(compact);
  ASSERT_TRUE(compact.cell_start.empty());
  EXPECT_LT(compact.block_start.size() * 4 + compact.cell_offset.size(),
            flat.cell_start.size() * 2);
  for (std::size_t c = 0; c <= flat.cellCount(); ++c) {
    ASSERT_EQ(compact.start(c), flat.cell_start[c]) << c;
    ASSERT_EQ(flat.start(c), flat.cell_start[c]) << c;
  }

  // A dense grid stays flat.
  GridStage dense;
  build(test::generatePoints(test::Distribution::JITTERED_GRID, n, 7), dense);
  CellGrid kept = dense.grid;
  compactCellStarts(kept);
  EXPECT_TRUE(kept.cell_start == dense.grid.cell_start);
  EXPECT_TRUE(kept.block_start.empty());

  // 300 distinct points in one cell: its block's offsets exceed a byte, stays flat.
  for (std::size_t k = 0; k < 300; ++k) {
    xyz.push_back(xyz[0] + 1e-9 * static_cast<double>(k));
    xyz.push_back(xyz[1]);
    xyz.push_back(0.0);
  }
  GridStage crowded;
  build(xyz, crowded);
  ASSERT_GT(crowded.grid.cellCount(), 2 * crowded.grid.points.size());
  CellGrid still = crowded.grid;
  compactCellStarts(still);
  EXPECT_TRUE(still.cell_start == crowded.grid.cell_start);
}

} // namespace
} // namespace pcl_vts
