// Outward-triangle removal: keeps convex data whole, peels the bridges over a
// concave notch and opens data voids into holes, measured against a synthetic
// terrain with a known footprint (coverage >= 99 %, spill <= 0.5 %); never pinches a
// vertex, counts lost vertices, is deterministic; works untuned on real DEMs.
#include "../../src/core/post_pass_spacing.h"
#include "support/asc_reader.h"
#include "support/generators.h"
#include "support/mesh_shuffle.h"
#include "support/pipeline_checks.h"
#include "support/special_triangles.h"
#include "support/surface_checks.h"

#include <pcl_vts/core/boundary_loops.h>
#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/point_spacing.h>
#include <pcl_vts/core/trim_outward_triangles.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace pcl_vts {
namespace {

TriangleMesh triangulate(const std::vector<double>& xyz)
{
  const test::PipelineRun run = test::runPipeline(xyz);
  EXPECT_TRUE(run.status.ok()) << run.status.toString();
  return run.result.mesh;
}

std::size_t unusedVertices(const TriangleMesh& mesh)
{
  std::vector<bool> used(mesh.vertexCount(), false);
  for (const VertexId v : mesh.triangles)
    used[v] = true;
  std::size_t unused = 0;
  for (const bool u : used)
    unused += u ? 0 : 1;
  return unused;
}

TEST(TrimOutwardTriangles, ConvexJitteredGridLosesOnlyHullSlivers)
{
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    TriangleMesh mesh = triangulate(
        test::generatePoints(test::Distribution::JITTERED_GRID, 2500, seed));
    const double area = twiceArea(mesh);
    TrimResult result;
    ASSERT_TRUE(trimOutwardTriangles(mesh, TrimOptions{}, result).ok());
    test::expectValidSurfaceMesh(mesh);
    // The hull's long thin slivers along the straight sides bridge the tiny
    // concavities of the jittered outline; nothing else goes.
    EXPECT_GT(twiceArea(mesh), 0.98 * area);
    EXPECT_EQ(result.vertices_lost, 0u);
    BoundaryLoops loops;
    ASSERT_TRUE(findBoundaryLoops(mesh, loops).ok());
    EXPECT_EQ(loops.loops.size(), 1u);
    EXPECT_GT(result.spacing, 0.3);
  }
}

TEST(TrimOutwardTriangles, SyntheticTerrainCoverageAndSpill)
{
  const test::SyntheticTerrain terrain = test::makeSyntheticTerrain(7);
  TriangleMesh mesh = triangulate(terrain.xyz);
  const test::CoverageFigures raw = test::measureCoverage(mesh, terrain, 0.25);
  TrimResult result;
  ASSERT_TRUE(trimOutwardTriangles(mesh, TrimOptions{}, result).ok());
  test::expectValidSurfaceMesh(mesh);
  const test::CoverageFigures trimmed = test::measureCoverage(mesh, terrain, 0.25);
  std::printf("[ figures  ] untrimmed: coverage %.4f%% spill %.4f%%\n",
              100 * raw.coverage(), 100 * raw.spillRatio());
  std::printf("[ figures  ] trimmed (factor %.1f, spacing %.3f): coverage %.4f%% "
              "spill %.4f%%, %zu triangles removed, %zu vertices lost\n",
              TrimOptions{}.trim_factor, result.spacing, 100 * trimmed.coverage(),
              100 * trimmed.spillRatio(), result.triangles_removed,
              result.vertices_lost);
  EXPECT_GT(raw.spillRatio(), 0.05); // the hull bridges the notch and the voids
  EXPECT_GE(trimmed.coverage(), 0.99);
  EXPECT_LE(trimmed.spillRatio(), 0.005);
  EXPECT_EQ(unusedVertices(mesh), result.vertices_lost);

  BoundaryLoops loops;
  ASSERT_TRUE(findBoundaryLoops(mesh, loops).ok());
  EXPECT_EQ(loops.componentCount(), 1u);
  // Voids of radius 3, 6, 10, 25 opened (radius 2 may stay bridged).
  EXPECT_GE(loops.holeCount(), 4u);
  EXPECT_LE(loops.holeCount(), 5u);
}

TEST(TrimOutwardTriangles, WithoutOpenVoidsOnlyTheOutlineIsPeeled)
{
  const test::SyntheticTerrain terrain = test::makeSyntheticTerrain(7);
  TriangleMesh mesh = triangulate(terrain.xyz);
  TrimOptions options;
  options.open_voids = false;
  TrimResult result;
  ASSERT_TRUE(trimOutwardTriangles(mesh, options, result).ok());
  test::expectValidSurfaceMesh(mesh);
  BoundaryLoops loops;
  ASSERT_TRUE(findBoundaryLoops(mesh, loops).ok());
  EXPECT_EQ(loops.holeCount(), 0u);
  // The notch is gone: its centre is not covered any more.
  test::SyntheticTerrain notch_only = terrain;
  notch_only.voids.clear();
  const test::CoverageFigures f = test::measureCoverage(mesh, notch_only, 0.5);
  EXPECT_LE(f.spillRatio(), 0.005);
  EXPECT_GT(result.triangles_removed, 0u);
}

TEST(TrimOutwardTriangles, IsDeterministic)
{
  const test::SyntheticTerrain terrain = test::makeSyntheticTerrain(11);
  const TriangleMesh input = triangulate(terrain.xyz);
  TriangleMesh a = input, b = input;
  TrimResult ra, rb;
  ASSERT_TRUE(trimOutwardTriangles(a, TrimOptions{}, ra).ok());
  ASSERT_TRUE(trimOutwardTriangles(b, TrimOptions{}, rb).ok());
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.halfedges, b.halfedges);
  EXPECT_EQ(ra.triangles_removed, rb.triangles_removed);
  // Trimming again removes almost nothing: the peel ran until nothing changed; only
  // the spacing re-measured at the new rim (its long edges gone) is a little shorter.
  TrimResult again;
  ASSERT_TRUE(trimOutwardTriangles(a, TrimOptions{}, again).ok());
  EXPECT_LE(again.triangles_removed, a.triangleCount() / 1000);
}

TEST(TrimOutwardTriangles, AggressiveFactorNeverPinchesAVertex)
{
  for (const auto distribution :
       {test::Distribution::UNIFORM, test::Distribution::CLUSTERED,
        test::Distribution::BIG_VOIDS, test::Distribution::JITTERED_GRID}) {
    for (const double factor : {1.2, 1.6, 2.5}) {
      SCOPED_TRACE(test::distributionName(distribution) + " factor " +
                   std::to_string(factor));
      TriangleMesh mesh = triangulate(test::generatePoints(distribution, 3000, 5));
      TrimOptions options;
      options.trim_factor = factor;
      TrimResult result;
      ASSERT_TRUE(trimOutwardTriangles(mesh, options, result).ok());
      test::expectValidSurfaceMesh(mesh);
      EXPECT_EQ(unusedVertices(mesh), result.vertices_lost);
      EXPECT_GT(result.triangles_removed, 0u);
    }
  }
}

// The tiled path trims a sub-mesh whose ids differ from the in-memory mesh's: the
// peel and the pinch repair must depend on positions only.
TEST(TrimOutwardTriangles, DependsOnPositionsNotOnIds)
{
  std::size_t repaired = 0;
  for (const auto distribution :
       {test::Distribution::CLUSTERED, test::Distribution::BIG_VOIDS,
        test::Distribution::JITTERED_GRID}) {
    for (const double factor : {1.2, 1.6, 3.0}) {
      SCOPED_TRACE(test::distributionName(distribution) + " factor " +
                   std::to_string(factor));
      const TriangleMesh input =
          triangulate(test::generatePoints(distribution, 3000, 9));
      // Same triangles: vertex ids shuffled, triangles shuffled, corners rotated.
      TriangleMesh shuffled = test::shuffledIds(input, 17);
      TriangleMesh a = input;
      TrimOptions options;
      options.trim_factor = factor;
      TrimResult ra, rb;
      ASSERT_TRUE(trimOutwardTriangles(a, options, ra).ok());
      ASSERT_TRUE(trimOutwardTriangles(shuffled, options, rb).ok());
      EXPECT_EQ(ra.triangles_removed, rb.triangles_removed);
      EXPECT_EQ(ra.kept_to_stay_manifold, rb.kept_to_stay_manifold);
      EXPECT_EQ(test::trianglesByPosition(a), test::trianglesByPosition(shuffled));
      repaired += ra.kept_to_stay_manifold;
    }
  }
  EXPECT_GT(repaired, 0u); // the pinch repair ran
}

TEST(TrimOutwardTriangles, MaxEdgeIsAnAbsoluteLimit)
{
  TriangleMesh mesh =
      triangulate(test::generatePoints(test::Distribution::JITTERED_GRID, 2500, 4));
  TrimOptions options;
  options.trim_factor = 1000.0;
  options.max_edge = 1.2; // shorter than many lattice diagonals
  TrimResult result;
  ASSERT_TRUE(trimOutwardTriangles(mesh, options, result).ok());
  test::expectValidSurfaceMesh(mesh);
  EXPECT_GT(result.triangles_removed, 0u);
  for (std::size_t e = 0; e < mesh.triangles.size(); ++e) {
    const Point2& a = mesh.xy[mesh.triangles[e]];
    const Point2& b = mesh.xy[mesh.triangles[nextHalfedge(e)]];
    // Survivors with a long edge were kept only to stay manifold.
    if (std::hypot(a.x - b.x, a.y - b.y) > 1.2) {
      EXPECT_GT(result.kept_to_stay_manifold, 0u);
    }
  }
}

// The triangles that survive the definition's trim: every triangle classified
// against the largest local spacing of its corners (measurePointSpacing), then the
// peel; the survivors' corners in their order.
std::vector<VertexId> definitionsSurvivors(const TriangleMesh& input,
                                           const TrimOptions& options)
{
  const PointSpacing spacing = measurePointSpacing(input);
  std::vector<std::uint8_t> flags(input.triangleCount(), 0);
  for (TriangleId t = 0; t < input.triangleCount(); ++t) {
    double largest = 0.0;
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
      largest = std::max(largest, spacing.local[input.triangles[e]]);
    const TriangleSize size = classifyTriangle(
        input.xy[input.triangles[3 * t]], input.xy[input.triangles[3 * t + 1]],
        input.xy[input.triangles[3 * t + 2]], largest, options);
    flags[t] = static_cast<std::uint8_t>((size.oversized ? OVERSIZED : 0) |
                                         (size.void_seed ? VOID_SEED : 0));
  }
  std::vector<bool> removed;
  peelOutwardTriangles(input, flags, options.open_voids, removed);
  std::vector<VertexId> survivors;
  for (TriangleId t = 0; t < input.triangleCount(); ++t)
    if (!removed[t])
      for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
        survivors.push_back(input.triangles[e]);
  return survivors;
}

// The vertex clearance (classifyTriangles: a triangle with a corner whose every
// triangle is within trim_factor times its ring bound is kept without a test of
// its own) never spares an oversized triangle: the trim equals the definition's on
// a dense grid with one far point (a fan of huge triangles whose other corners are
// dense: a corner cleared from its small triangles alone would keep them) and with
// a hole (huge triangles inside), with a max_edge, and on a lattice with a hole of
// one point at the factor where its largest triangle is exactly at the limit (kept)
// and the double just below (removed).
TEST(TrimOutwardTriangles, VertexClearanceNeverSparesAnOversizedTriangle)
{
  auto grid = [](bool jitter, double hole_radius, bool far_point) {
    std::vector<double> xyz;
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i) {
        const double x = i + (jitter ? 0.25 * std::sin(7.0 * i + 3.0 * j) : 0.0);
        const double y = j + (jitter ? 0.25 * std::cos(5.0 * i - 11.0 * j) : 0.0);
        if (std::hypot(x - 11.0, y - 11.0) < hole_radius)
          continue;
        xyz.insert(xyz.end(), {x, y, 0.0});
      }
    if (far_point)
      xyz.insert(xyz.end(), {11.3, 200.0, 0.0});
    return xyz;
  };
  auto check = [](const TriangleMesh& input, double factor, double max_edge) {
    TrimOptions options;
    options.trim_factor = factor;
    options.max_edge = max_edge;
    TriangleMesh mesh = input;
    TrimResult result;
    EXPECT_TRUE(trimOutwardTriangles(mesh, options, result).ok());
    EXPECT_EQ(mesh.triangles, definitionsSurvivors(input, options));
    return result;
  };
  const TriangleMesh far = triangulate(grid(true, 0.0, true));
  EXPECT_EQ(check(far, 3.0, 0.0).vertices_lost, 1u); // the far point's fan goes
  check(far, 1.5, 0.0);
  const TriangleMesh hole = triangulate(grid(true, 4.0, false));
  EXPECT_GT(check(hole, 3.0, 0.0).triangles_removed, 20u);
  check(hole, 3.0, 1.3);
  // The smallest factor at which no triangle is oversized: classifyTriangle's own
  // limit per triangle, the largest over the mesh.
  const TriangleMesh lattice = triangulate(grid(false, 0.5, false));
  const PointSpacing spacing = measurePointSpacing(lattice);
  double limit = 1.0;
  for (TriangleId t = 0; t < lattice.triangleCount(); ++t) {
    double scale = 0.0;
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
      scale = std::max(scale, spacing.local[lattice.triangles[e]]);
    auto oversized = [&](double factor) {
      TrimOptions options;
      options.trim_factor = factor;
      return classifyTriangle(lattice.xy[lattice.triangles[3 * t]],
                              lattice.xy[lattice.triangles[3 * t + 1]],
                              lattice.xy[lattice.triangles[3 * t + 2]], scale, options)
          .oversized;
    };
    if (!oversized(limit))
      continue;
    while (oversized(limit))
      limit = std::nextafter(2.0 * limit, HUGE_VAL);
    for (double step = limit / 2; step > 0 && limit - step > 1.0; step /= 2)
      if (!oversized(limit - step))
        limit -= step;
    while (!oversized(std::nextafter(limit, 0.0)))
      limit = std::nextafter(limit, 0.0);
  }
  ASSERT_GT(limit, 1.0);
  EXPECT_EQ(check(lattice, limit, 0.0).triangles_removed, 0u);
  EXPECT_GT(check(lattice, std::nextafter(limit, 0.0), 0.0).triangles_removed, 0u);
}

// The rows' scatter takes two triangles' needs at once (Clearance::roundedUpNeeds,
// SSE2 lanes): each lane must give the scalar roundedUp(need) bit for bit, in either
// lane, on ordinary, obtuse (the circumradius past the longest edge), degenerate,
// tiny, huge and non-finite triangles, against several edge limits.
TEST(TrimOutwardTriangles, ClearanceNeedsInLanesEqualTheScalarOnes)
{
  using detail::Clearance;
  std::mt19937_64 random(15);
  constexpr double INF = std::numeric_limits<double>::infinity();
  auto bits = [](const Point2(&p)[3], double limit2) {
    return Clearance::roundedUp(Clearance::need(p[0], p[1], p[2], limit2));
  };
  std::size_t radius_taken = 0, infinite = 0, finite = 0;
  for (int round = 0; round < 200000; ++round) {
    Point2 t0[3], t1[3];
    test::specialTriangle(random, round % test::SPECIAL_TRIANGLE_KINDS, t0);
    test::specialTriangle(
        random, static_cast<int>(random() % test::SPECIAL_TRIANGLE_KINDS), t1);
    const double limits[] = {INF, 1e-40, 1.0, 1e20,
                             Clearance::need(t0[0], t0[1], t0[2], INF)};
    const double limit2 = limits[random() % std::size(limits)];
    const std::uint32_t want0 = bits(t0, limit2), want1 = bits(t1, limit2);
    const std::uint64_t both =
        Clearance::roundedUpNeeds(t0[0], t0[1], t0[2], t1[0], t1[1], t1[2], limit2);
    ASSERT_EQ(static_cast<std::uint32_t>(both), want0) << round;
    ASSERT_EQ(static_cast<std::uint32_t>(both >> 32), want1) << round;
    const std::uint64_t swapped =
        Clearance::roundedUpNeeds(t1[0], t1[1], t1[2], t0[0], t0[1], t0[2], limit2);
    ASSERT_EQ(swapped, std::uint64_t{want1} | std::uint64_t{want0} << 32) << round;
    const double need = Clearance::need(t0[0], t0[1], t0[2], INF);
    if (need == INF)
      ++infinite;
    else {
      ++finite;
      const double ab = std::pow(t0[0].x - t0[1].x, 2) + std::pow(t0[0].y - t0[1].y, 2);
      const double bc = std::pow(t0[1].x - t0[2].x, 2) + std::pow(t0[1].y - t0[2].y, 2);
      const double ca = std::pow(t0[2].x - t0[0].x, 2) + std::pow(t0[2].y - t0[0].y, 2);
      radius_taken += need > 1.000001 * std::max({ab, bc, ca}) ? 1 : 0;
    }
  }
  // Each case seen: figures past the range, the longest edge, the circumradius.
  EXPECT_GT(infinite, 1000u);
  EXPECT_GT(finite, 1000u);
  EXPECT_GT(radius_taken, 1000u);
}

// The trim's shortcuts (the ring-minimum bound, the root-free clearance, the medians
// of short rows) against the definition: every triangle classified against the
// largest local spacing of its corners (measurePointSpacing), then the peel; the
// survivors in their order. Also far from the origin, tiny and huge scales, a
// max_edge, other factors.
// ringLowerBounds with the clearance, as the trim calls it (SSE2 lanes for rows of up
// to 8 entries when no own median is NaN, the vertices settled two at a time): every
// vertex's bit is the scalar test of its ringLowerBound, an uncleared vertex keeps
// ringLowerBound's figure bit for bit and is listed when it has a row, and the
// histogram gives the global median; at fixed factors and at the exact factors where
// some vertices become cleared (a settle with other roundings flips them). With NaN
// own medians (the lanes' min and max would drop them) the bounds around them stay
// NaN and those vertices uncleared.
TEST(TrimOutwardTriangles, RingBoundsAndClearanceEqualTheScalarOnes)
{
  using detail::Clearance;
  auto bits_of = [](double x) {
    std::uint64_t b = 0;
    std::memcpy(&b, &x, sizeof b);
    return b;
  };
  for (const test::Distribution distribution :
       {test::Distribution::JITTERED_GRID, test::Distribution::BIG_VOIDS})
    for (const bool with_nan : {false, true}) {
      const TriangleMesh mesh =
          triangulate(test::generatePoints(distribution, 6000, 5));
      detail::VertexRows rows;
      std::vector<double> need;
      ASSERT_TRUE(
          rows.build(mesh, nullptr, &need, std::numeric_limits<double>::infinity()));
      std::vector<double> own = detail::ownMedians(mesh, rows, 1);
      const std::size_t n = own.size();
      if (with_nan)
        for (std::size_t v = 17; v < n; v += 101)
          own[v] = std::numeric_limits<double>::quiet_NaN();
      // ownMedians' stats over the vertices with a row, NaN included.
      detail::OwnStats stats;
      for (std::size_t v = 0; v < n; ++v)
        if (rows.begin(v) != rows.end(v)) {
          stats.low = std::min(stats.low, bits_of(own[v]));
          stats.high = std::max(stats.high, bits_of(own[v]));
          ++stats.count;
        }
      auto clears = [&](std::size_t v, double factor) {
        const double limit = factor * detail::ringLowerBound(rows, own, v);
        const double v_need = Clearance::slotNeed(Clearance::slot(need[v]));
        return (limit >= Clearance::LOW) & (limit <= Clearance::HIGH) &
               (v_need <= limit * limit * Clearance::MARGIN);
      };
      std::vector<double> factors = {1.0, 2.0, 3.0, 8.0};
      // The least factor clearing v (the test is monotone in it below 1e60).
      for (const std::size_t v : {101, 2002, 3003, 4004, 5005}) {
        if (!clears(v, 100.0))
          continue;
        double factor = 100.0;
        for (double step = 50.0; step > 0.0 && factor - step > 0.0; step /= 2)
          if (clears(v, factor - step))
            factor -= step;
        while (clears(v, std::nextafter(factor, 0.0)))
          factor = std::nextafter(factor, 0.0);
        ASSERT_TRUE(clears(v, factor));
        factors.push_back(factor);
      }
      if (!with_nan) {
        EXPECT_EQ(factors.size(), 9u);
      }
      for (const double factor : factors) {
        SCOPED_TRACE(test::distributionName(distribution) + " factor " +
                     std::to_string(factor) + (with_nan ? " with NaN" : ""));
        detail::ClearedVertices cleared;
        cleared.trim_factor = factor;
        std::vector<double> bound = need;
        detail::MedianSelection histogram;
        detail::ringLowerBounds(rows, own, stats, 1, bound, &histogram, &cleared);
        std::size_t uncleared = 0, listed = 0;
        for (std::size_t v = 0; v < n; ++v) {
          const bool clear = clears(v, factor);
          const bool bit = ((cleared.bits[v / 64] >> (v % 64)) & 1u) != 0;
          ASSERT_EQ(bit, clear) << "vertex " << v;
          if (clear)
            continue;
          ++uncleared;
          EXPECT_EQ(bits_of(bound[v]), bits_of(detail::ringLowerBound(rows, own, v)))
              << "vertex " << v;
          if (rows.begin(v) == rows.end(v))
            continue;
          ASSERT_LT(listed, cleared.uncleared.size());
          EXPECT_EQ(cleared.uncleared[listed].first, v);
          ++listed;
        }
        EXPECT_EQ(listed, cleared.uncleared.size());
        EXPECT_GT(uncleared, 0u); // the hull's vertices at least
        if (factor >= 2.0) {
          EXPECT_LT(uncleared, n / 2); // most vertices are cleared
        }
        if (!with_nan) {
          EXPECT_EQ(detail::medianOverRows(own, rows, stats, histogram),
                    detail::medianOverRows(own, rows));
        }
      }
    }
}

// ownMedians (four vertices at a time in AVX2 lanes where the CPU has it, two in SSE2
// lanes for the rest, rows of 1-12 entries by size; longer and wide rows, and lanes
// with a NaN square, apart): every vertex's figure is its row's median length bit for
// bit (the lengths to its entries in row order, the one of index size / 2 by
// nth_element; 0 for an empty row), on jittered, uniform, clustered and big-voids
// meshes, and with points moved to NaN after the triangulation.
TEST(TrimOutwardTriangles, OwnMediansAreTheRowsMedianLengths)
{
  auto bits_of = [](double x) {
    std::uint64_t b = 0;
    std::memcpy(&b, &x, sizeof b);
    return b;
  };
  for (const test::Distribution distribution :
       {test::Distribution::JITTERED_GRID, test::Distribution::UNIFORM,
        test::Distribution::CLUSTERED, test::Distribution::BIG_VOIDS})
    for (const bool with_nan : {false, true}) {
      SCOPED_TRACE(test::distributionName(distribution) +
                   (with_nan ? " with NaN" : ""));
      TriangleMesh mesh = triangulate(test::generatePoints(distribution, 6000, 3));
      const std::size_t n = mesh.vertexCount();
      if (with_nan)
        for (std::size_t v = 11; v < n; v += 97)
          mesh.xy[v].x = std::numeric_limits<double>::quiet_NaN();
      detail::VertexRows rows;
      ASSERT_TRUE(rows.build(mesh));
      std::vector<double> expected(n, 0.0), lengths;
      std::size_t sizes_seen = 0;
      for (std::size_t v = 0; v < n; ++v) {
        lengths.clear();
        for (std::size_t k = rows.begin(v); k < rows.end(v); ++k) {
          const Point2& q = mesh.xy[rows.entry(v, k)];
          const double dx = mesh.xy[v].x - q.x, dy = mesh.xy[v].y - q.y;
          lengths.push_back(std::sqrt(dx * dx + dy * dy));
        }
        sizes_seen |= std::size_t{1} << std::min<std::size_t>(lengths.size(), 20);
        if (lengths.empty())
          continue;
        const auto mid =
            lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
        std::nth_element(lengths.begin(), mid, lengths.end());
        expected[v] = *mid;
      }
      EXPECT_EQ(sizes_seen & 0x7f8u, 0x7f8u); // rows of 3 to 10 entries at least
      const std::vector<double> own = detail::ownMedians(mesh, rows, 1);
      ASSERT_EQ(own.size(), n);
      for (std::size_t v = 0; v < n; ++v)
        ASSERT_EQ(bits_of(own[v]), bits_of(expected[v])) << "vertex " << v;
    }
}

TEST(TrimOutwardTriangles, EqualsThePeelOfTheDefinitionsClassification)
{
  struct Case {
    test::Distribution distribution;
    double scale;
    TrimOptions options;
  };
  TrimOptions tight;
  tight.trim_factor = 1.5;
  TrimOptions edge;
  edge.max_edge = 1.1;
  TrimOptions closed;
  closed.open_voids = false;
  const std::vector<Case> cases = {
      {test::Distribution::JITTERED_GRID, 1.0, TrimOptions{}},
      {test::Distribution::JITTERED_GRID, 1.0, tight},
      {test::Distribution::JITTERED_GRID, 1.0, edge},
      {test::Distribution::BIG_VOIDS, 1.0, TrimOptions{}},
      {test::Distribution::BIG_VOIDS, 1.0, closed},
      {test::Distribution::CLUSTERED, 1.0, TrimOptions{}},
      {test::Distribution::UNIFORM, 1e-70, TrimOptions{}},
      {test::Distribution::UNIFORM, 1e55, tight},
      {test::Distribution::UTM_OFFSET, 1.0, TrimOptions{}},
      {test::Distribution::ANISOTROPIC, 1.0, TrimOptions{}},
      {test::Distribution::EXACT_GRID, 1.0, TrimOptions{}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(test::distributionName(c.distribution) + " x" +
                 std::to_string(c.scale));
    std::vector<double> xyz = test::generatePoints(c.distribution, 3000, 7);
    for (double& value : xyz)
      value *= c.scale;
    const TriangleMesh input = triangulate(xyz);
    TriangleMesh mesh = input;
    TrimResult result;
    ASSERT_TRUE(trimOutwardTriangles(mesh, c.options, result).ok());
    EXPECT_EQ(mesh.triangles, definitionsSurvivors(input, c.options));
    EXPECT_EQ(result.spacing, measurePointSpacing(input).global_median);
  }
}

TEST(TrimOutwardTriangles, InvalidOptionsAreRejected)
{
  TriangleMesh mesh =
      triangulate(test::generatePoints(test::Distribution::UNIFORM, 100, 1));
  const TriangleMesh copy = mesh;
  TrimResult result;
  for (const double factor : {1.0, 0.5, -2.0, std::nan(""), HUGE_VAL}) {
    TrimOptions options;
    options.trim_factor = factor;
    const Status status = trimOutwardTriangles(mesh, options, result);
    EXPECT_EQ(status.code, StatusCode::INVALID_PARAMETER);
    EXPECT_NE(status.message.find("trim_factor"), std::string::npos) << status.message;
  }
  TrimOptions options;
  options.max_edge = -1.0;
  const Status status = trimOutwardTriangles(mesh, options, result);
  EXPECT_EQ(status.code, StatusCode::INVALID_PARAMETER);
  EXPECT_NE(status.message.find("max_edge = -1"), std::string::npos) << status.message;
  EXPECT_EQ(mesh.triangles, copy.triangles);
}

TEST(TrimOutwardTriangles, LoneTriangleIsPeeledAndItsVerticesCountedLost)
{
  // A long thin triangle alone, over the absolute edge limit.
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {10, 0}, {0, 1}};
  mesh.z = {0, 0, 0};
  mesh.triangles = {0, 1, 2};
  ASSERT_TRUE(mesh.rebuildHalfedges());
  TrimOptions options;
  options.max_edge = 5.0;
  TrimResult result;
  ASSERT_TRUE(trimOutwardTriangles(mesh, options, result).ok());
  EXPECT_EQ(result.triangles_removed, 1u);
  EXPECT_EQ(result.vertices_lost, 3u);
  EXPECT_EQ(mesh.triangleCount(), 0u);
  EXPECT_EQ(mesh.vertexCount(), 3u); // vertex ids stay valid
}

struct DemCase {
  const char* path;
  double max_spill; ///< mesh area over NODATA cells / valid area
};

class TrimRealDem : public ::testing::TestWithParam<DemCase> {};

TEST_P(TrimRealDem, DefaultsFollowTheOutline)
{
  const std::string path = std::string(PCL_VTS_SHARED_DATA_DIR) + "/" + GetParam().path;
  if (!std::ifstream(path).good())
    GTEST_SKIP() << "shared data file not found: " << path;
  test::AsciiGrid grid;
  ASSERT_TRUE(test::readAsciiGrid(path, grid));
  TriangleMesh mesh = triangulate(grid.xyz);
  const double hull_area = twiceArea(mesh) / 2;
  TrimResult result;
  ASSERT_TRUE(trimOutwardTriangles(mesh, TrimOptions{}, result).ok());
  test::expectValidSurfaceMesh(mesh);
  EXPECT_EQ(unusedVertices(mesh), result.vertices_lost);
  // Valid cells as a mask; sample each triangle area on a quarter-cell raster.
  const double cs = grid.cellsize;
  std::vector<bool> valid(grid.ncols * grid.nrows, false);
  for (std::size_t k = 0; k < grid.xyz.size(); k += 3) {
    const auto c = static_cast<std::size_t>((grid.xyz[k] - grid.xll) / cs);
    const auto r = static_cast<std::size_t>((grid.xyz[k + 1] - grid.yll) / cs);
    valid[r * grid.ncols + c] = true;
  }
  double spill = 0.0;
  test::forEachCoveredSample(mesh, 0, cs / 4, [&](double x, double y, std::size_t) {
    const auto c = static_cast<std::size_t>((x - grid.xll) / cs);
    const auto r = static_cast<std::size_t>((y - grid.yll) / cs);
    if (c >= grid.ncols || r >= grid.nrows || !valid[r * grid.ncols + c])
      spill += cs * cs / 16;
  });
  const double mesh_area = twiceArea(mesh) / 2;
  const double valid_area = static_cast<double>(grid.xyz.size() / 3) * cs * cs;
  std::printf(
      "[ figures  ] %s: valid cells %.0f, hull %.0f, trimmed %.0f (area units), "
      "spill over NODATA %.3f%%, %zu triangles removed, %zu vertices lost\n",
      GetParam().path, valid_area, hull_area, mesh_area, 100 * spill / valid_area,
      result.triangles_removed, result.vertices_lost);
  EXPECT_LE(spill, valid_area * GetParam().max_spill);
  EXPECT_GT(mesh_area, valid_area * 0.85); // a half-cell rim is outside the centres
}

const DemCase DEMS[] = {
    {"dem/landlab/west_bijou_gully.asc", 0.02},
    {"dem/landlab/hugo_site.asc", 0.02},
    {"dem/landlab/zSW3.asc", 0.02},
};

INSTANTIATE_TEST_SUITE_P(SharedData, TrimRealDem, ::testing::ValuesIn(DEMS),
                         [](const ::testing::TestParamInfo<DemCase>& param_info) {
                           std::string name = param_info.param.path;
                           name = name.substr(name.rfind('/') + 1);
                           return name.substr(0, name.find('.'));
                         });

} // namespace
} // namespace pcl_vts
