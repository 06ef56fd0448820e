// The lattice fast path (VtsOptions::lattice, docs/algorithm.md section 7) against
// the CGAL oracle (mirrored: the same tie-break) and against the ordinary path (fast
// path off): full grids, non-uniform spacing, NODATA holes of several shapes, sparse
// patterns, off-lattice points, duplicates, shuffled input, UTM offsets, real DEMs.
#include "support/asc_reader.h"
#include "support/mesh_shuffle.h"
#include "support/pipeline_checks.h"

#include <pcl_vts/core/vts_pipeline.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace pcl_vts {
namespace {

/// Points (xs[i], ys[j], z) for every (i, j) that keep(i, j) accepts, row-major.
std::vector<double> rasterPoints(const std::vector<double>& xs,
                                 const std::vector<double>& ys,
                                 const std::function<bool(int, int)>& keep)
{
  std::vector<double> xyz;
  for (std::size_t j = 0; j < ys.size(); ++j)
    for (std::size_t i = 0; i < xs.size(); ++i)
      if (keep(static_cast<int>(i), static_cast<int>(j)))
        xyz.insert(xyz.end(), {xs[i], ys[j], std::sin(0.3 * xs[i]) + 0.1 * ys[j]});
  return xyz;
}

std::vector<double> uniformSteps(std::size_t count, double origin, double step)
{
  std::vector<double> v(count);
  for (std::size_t k = 0; k < count; ++k)
    v[k] = origin + step * static_cast<double>(k);
  return v;
}

std::vector<double> randomSteps(std::size_t count, double origin, std::uint32_t seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> step(0.05, 3.0);
  std::vector<double> v(count);
  v[0] = origin;
  for (std::size_t k = 1; k < count; ++k)
    v[k] = v[k - 1] + step(rng);
  return v;
}

/// Position triple of every hull vertex, in hull order.
std::vector<Point2> hullPositions(const VtsResult& r)
{
  std::vector<Point2> out;
  for (const VertexId v : r.hull)
    out.push_back(r.mesh.xy[v]);
  return out;
}

/// The fast path ran, equals the ordinary path on everything but the vertex ids, and
/// passes every invariant and the CGAL comparison (when check_cgal).
void expectSameAsOrdinary(const std::vector<double>& xyz, VtsOptions options = {},
                          bool check_cgal = true)
{
  options.lattice = true;
  const test::PipelineRun fast = test::runPipeline(xyz, options);
  options.lattice = false;
  const test::PipelineRun slow = test::runPipeline(xyz, options);
  ASSERT_EQ(fast.status.code, slow.status.code) << fast.status.toString();
  if (!slow.status.ok())
    return;
  const VtsResult &f = fast.result, &s = slow.result;
  EXPECT_GT(f.diagnostics.lattice_columns, 0u) << "the fast path did not run";
  EXPECT_EQ(s.diagnostics.lattice_columns, 0u);
  ASSERT_EQ(f.mesh.vertexCount(), s.mesh.vertexCount());
  EXPECT_EQ(test::verticesByPosition(f.mesh), test::verticesByPosition(s.mesh));
  EXPECT_EQ(test::trianglesByPosition(f.mesh), test::trianglesByPosition(s.mesh));
  EXPECT_EQ(hullPositions(f), hullPositions(s));
  // The same input point represents each position, and every input maps alike.
  for (std::size_t k = 0; k < f.input_to_vertex.size(); ++k) {
    const VertexId vf = f.input_to_vertex[k], vs = s.input_to_vertex[k];
    ASSERT_EQ(vf == INVALID_ID, vs == INVALID_ID) << "input " << k;
    if (vf != INVALID_ID) {
      ASSERT_EQ(f.mesh.xy[vf], s.mesh.xy[vs]) << "input " << k;
      // Bit for bit: -0.0 == +0.0, but the written files (and the tiled path's
      // rebuilt vertices) tell them apart.
      ASSERT_EQ(std::signbit(f.mesh.xy[vf].x), std::signbit(s.mesh.xy[vs].x)) << k;
      ASSERT_EQ(std::signbit(f.mesh.xy[vf].y), std::signbit(s.mesh.xy[vs].y)) << k;
      ASSERT_EQ(f.source_index[vf], s.source_index[vs]) << "input " << k;
    }
  }
  const Diagnostics &df = f.diagnostics, &ds = s.diagnostics;
  EXPECT_EQ(df.non_finite_dropped, ds.non_finite_dropped);
  EXPECT_EQ(df.duplicates_merged, ds.duplicates_merged);
  EXPECT_EQ(df.distinct_points, ds.distinct_points);
  EXPECT_EQ(df.hull_vertices, ds.hull_vertices);
  EXPECT_EQ(df.triangles, ds.triangles);
  if (check_cgal)
    test::expectValidTriangulation(xyz, fast, options);
}

TEST(LatticeTriangulation, CellDiagonalAvoidsTheLowerLeftCorner)
{
  // A (0,0), B (1,0), C (1,1), D (0,1): the perturbation lifts A most, so the
  // diagonal is B-D. Checked on the ordinary path too, with and without shuffling.
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  for (const bool lattice : {true, false}) {
    VtsOptions options;
    options.lattice = lattice;
    const test::PipelineRun run = test::runPipeline(xyz, options);
    ASSERT_TRUE(run.status.ok()) << run.status.toString();
    const TriangleMesh& m = run.result.mesh;
    ASSERT_EQ(m.triangleCount(), 2u);
    for (std::size_t t = 0; t < 2; ++t) {
      bool has_b = false, has_d = false;
      for (int c = 0; c < 3; ++c) {
        const Point2 p = m.xy[m.triangles[3 * t + c]];
        has_b = has_b || (p.x == 1 && p.y == 0);
        has_d = has_d || (p.x == 0 && p.y == 1);
      }
      EXPECT_TRUE(has_b && has_d) << "lattice " << lattice << " triangle " << t;
    }
    EXPECT_EQ(run.result.diagnostics.lattice_columns, lattice ? 2u : 0u);
  }
  expectSameAsOrdinary(xyz);
}

TEST(LatticeTriangulation, FullGridsOfSeveralSizes)
{
  for (const auto& [w, h] : std::vector<std::array<std::size_t, 2>>{
           {2, 3}, {3, 2}, {2, 9}, {9, 2}, {5, 5}, {17, 4}, {40, 33}, {150, 120}}) {
    SCOPED_TRACE(std::to_string(w) + " x " + std::to_string(h));
    expectSameAsOrdinary(rasterPoints(uniformSteps(w, 0.0, 1.0),
                                      uniformSteps(h, 0.0, 1.0),
                                      [](int, int) { return true; }));
  }
}

TEST(LatticeTriangulation, FullGridHasNoFringeTriangle)
{
  const std::vector<double> xyz =
      rasterPoints(uniformSteps(60, 0.0, 2.0), uniformSteps(50, 0.0, 2.0),
                   [](int, int) { return true; });
  const test::PipelineRun run = test::runPipeline(xyz);
  ASSERT_TRUE(run.status.ok());
  // Every vertex, on the border too, has its star in complete cells.
  EXPECT_EQ(run.result.diagnostics.lattice_fringe_rounds, 0u);
  EXPECT_EQ(run.result.diagnostics.lattice_fringe_points, 0u);
  EXPECT_EQ(run.result.mesh.triangleCount(), 2u * 59u * 49u);
}

TEST(LatticeTriangulation, NonUniformSpacing)
{
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    SCOPED_TRACE(seed);
    const auto xs = randomSteps(45, -10.0, seed), ys = randomSteps(38, 3.0, seed + 10);
    std::mt19937 rng(seed);
    std::bernoulli_distribution missing(seed % 2 == 0 ? 0.1 : 0.0);
    std::vector<bool> keep(xs.size() * ys.size());
    for (std::size_t k = 0; k < keep.size(); ++k)
      keep[k] = !missing(rng);
    expectSameAsOrdinary(rasterPoints(xs, ys, [&](int i, int j) {
      return keep[static_cast<std::size_t>(j) * xs.size() +
                  static_cast<std::size_t>(i)];
    }));
  }
}

TEST(LatticeTriangulation, IsolatedGapsOnUnevenSpacing)
{
  // One missing position with its eight neighbours present: its six triangles come
  // without a search (four corner triangles, the rest split by the perturbed
  // in-circle test: cocircular on even steps, not on random ones), next to the border
  // too; gaps two apart in a row form larger pieces, which take the general path.
  const std::vector<std::pair<std::vector<double>, std::vector<double>>> lattices = {
      {uniformSteps(31, 0.0, 1.0), uniformSteps(27, 0.0, 1.0)},
      {uniformSteps(31, 0.0, 2.0), uniformSteps(27, 5.0, 0.5)},
      {randomSteps(31, -4.0, 7), randomSteps(27, 2.0, 8)}};
  for (std::size_t k = 0; k < lattices.size(); ++k) {
    SCOPED_TRACE(k);
    const auto& [xs, ys] = lattices[k];
    expectSameAsOrdinary(rasterPoints(xs, ys, [](int i, int j) {
      return !((i % 4 == 1 && j % 4 == 1) || (i == 20 && j == 22));
    }));
  }
}

TEST(LatticeTriangulation, NodataHolesOfSeveralShapes)
{
  const auto xs = uniformSteps(70, 0.0, 1.0), ys = uniformSteps(60, 0.0, 1.0);
  const std::vector<std::pair<const char*, std::function<bool(int, int)>>> cases = {
      {"single cells", [](int i, int j) { return (i * 7 + j * 13) % 29 != 0; }},
      {"big void",
       [](int i, int j) {
         return (i - 35) * (i - 35) + (j - 30) * (j - 30) > 18 * 18;
       }},
      {"void touching the border",
       [](int i, int j) { return !(i < 20 && j > 25 && j < 45) && i + j > 8; }},
      {"corner cut and notch",
       [](int i, int j) { return i + j < 110 && !(i > 30 && i < 33 && j < 40); }},
      {"checkerboard block",
       [](int i, int j) {
         return !(i > 10 && i < 40 && j > 10 && j < 30) || (i + j) % 2 == 0;
       }},
      {"sparse diagonal stripes", [](int i, int j) { return (i + 2 * j) % 5 != 0; }},
      {"two points per cell row missing",
       [](int i, int j) { return !(j % 9 == 4 && i % 3 != 0); }},
      {"random 40 percent", [](int i, int j) {
         return std::hash<int>{}(i * 1000 + j) * 2654435761u % 100 >= 40;
       }}};
  for (const auto& [name, keep] : cases) {
    SCOPED_TRACE(name);
    expectSameAsOrdinary(rasterPoints(xs, ys, keep));
  }
}

TEST(LatticeTriangulation, NarrowRingsNeedMoreRoundsNotOtherTriangles)
{
  // Ring 0 leaves S too thin for some candidates: their circumdisks hold points
  // outside S, which join S for another round. The triangles stay the same for every
  // ring.
  const auto xs = randomSteps(40, 0.0, 7), ys = uniformSteps(36, 0.0, 1.0);
  const std::vector<std::function<bool(int, int)>> shapes = {
      [](int, int) { return true; },
      [](int i, int j) { return (i - 20) * (i - 20) + 3 * (j - 18) * (j - 18) > 150; },
      [](int i, int j) {
        return !(j > 5 && j < 30 && i > 2 * j - 20 && i < 2 * j - 12);
      },
      [](int i, int j) { return (i * 5 + j * 3) % 17 != 0 && i + j > 6; }};
  std::size_t most_rounds = 0;
  for (const std::uint32_t ring : {0u, 1u, 3u})
    for (std::size_t k = 0; k < shapes.size(); ++k) {
      SCOPED_TRACE("ring " + std::to_string(ring) + " shape " + std::to_string(k));
      VtsOptions options;
      options.lattice_ring = ring;
      options.lattice_one_window = false; // the pieces' rounds
      const auto xyz = rasterPoints(xs, ys, shapes[k]);
      expectSameAsOrdinary(xyz, options);
      most_rounds = std::max(
          most_rounds,
          test::runPipeline(xyz, options).result.diagnostics.lattice_fringe_rounds);
    }
  EXPECT_GT(most_rounds, 1u); // the disk check rejected something
}

TEST(LatticeTriangulation, TinyRastersMostlyNodata)
{
  // Small DEMs whose points are mostly fringe (a gully, scattered pixels, a thin
  // diagonal band, a mask with one-pixel bridges): the fringe's pieces in one window
  // and piece by piece.
  const auto xs = uniformSteps(23, 559705.5, 3.0),
             ys = uniformSteps(19, 4380221.5, 3.0);
  const std::vector<std::pair<const char*, std::function<bool(int, int)>>> cases = {
      {"gully",
       [](int i, int j) { return std::abs(i - 6 - (j * j) / 24) <= 2 + (j % 3 == 0); }},
      {"random 75 percent nodata",
       [](int i, int j) {
         const std::uint32_t h = (static_cast<std::uint32_t>(i) * 73856093u ^
                                  static_cast<std::uint32_t>(j) * 19349663u) *
                                 2654435761u;
         return (h >> 16) % 100 >= 75;
       }},
      {"thin diagonal band", [](int i, int j) { return std::abs(2 * i - 3 * j) <= 5; }},
      {"blobs and bridges", [](int i, int j) {
         return (i - 5) * (i - 5) + (j - 5) * (j - 5) <= 12 ||
                (i - 16) * (i - 16) + (j - 12) * (j - 12) <= 16 ||
                (j == 8 && i > 5 && i < 16) || (i == 20 && j % 4 != 1);
       }}};
  for (const auto& [name, keep] : cases)
    for (const bool one_window : {true, false}) {
      SCOPED_TRACE(std::string(name) + (one_window ? ", one window" : ", by piece"));
      VtsOptions options;
      options.lattice_one_window = one_window;
      const auto xyz = rasterPoints(xs, ys, keep);
      expectSameAsOrdinary(xyz, options);
      // The window proved the fringe (its count closed up), or it did not run.
      const Diagnostics d = test::runPipeline(xyz, options).result.diagnostics;
      EXPECT_EQ(d.lattice_fringe_window > 0, one_window);
    }
}

TEST(LatticeTriangulation, FlatHullTrianglesBeyondTheWindow)
{
  // One full row and the last point of the next: the fan from that point has
  // circles of radius up to width^2 / 2, beyond the one window's super triangle at
  // its first width (150), and at its second too (3000): the window is done again
  // wider, then the pieces one by one. The same triangles all the same.
  for (const int width : {150, 3000}) {
    SCOPED_TRACE(width);
    const auto xs = uniformSteps(static_cast<std::size_t>(width) + 1, 0.0, 1.0),
               ys = uniformSteps(3, 0.0, 1.0);
    const auto xyz = rasterPoints(
        xs, ys, [width](int i, int j) { return j == 0 || (j == 1 && i == width); });
    expectSameAsOrdinary(xyz);
    // Proven in the wider window, or piece by piece.
    EXPECT_EQ(test::runPipeline(xyz).result.diagnostics.lattice_fringe_window,
              width == 150 ? static_cast<std::size_t>(width) : 0u);
  }
}

TEST(LatticeTriangulation, OffLatticePointsAddColumnsOrFallBack)
{
  auto xyz = rasterPoints(
      uniformSteps(30, 0.0, 1.0), uniformSteps(25, 0.0, 1.0),
      [](int i, int j) { return (i - 12) * (i - 12) + (j - 12) * (j - 12) > 9; });
  // A few points off the lattice: each adds a column and a row, still a lattice.
  for (const auto& p :
       std::vector<std::array<double, 2>>{{12.25, 11.5}, {3.5, 20.75}, {29.9, 0.1}})
    xyz.insert(xyz.end(), {p[0], p[1], 1.0});
  expectSameAsOrdinary(xyz);
  // Jittered: not a lattice, the ordinary path runs.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  for (std::size_t k = 0; k < xyz.size(); k += 3) {
    xyz[k] += jitter(rng);
    xyz[k + 1] += jitter(rng);
  }
  const test::PipelineRun run = test::runPipeline(xyz);
  ASSERT_TRUE(run.status.ok());
  EXPECT_EQ(run.result.diagnostics.lattice_columns, 0u);
}

TEST(LatticeTriangulation, DuplicatesAndNonFiniteFollowTheRule)
{
  auto xyz = rasterPoints(uniformSteps(12, 0.0, 1.0), uniformSteps(9, 0.0, 1.0),
                          [](int i, int j) { return i != 5 || j != 4; });
  const std::size_t base = xyz.size() / 3;
  for (std::size_t k = 0; k < base; k += 3) // duplicates above, below, equal, -0
    xyz.insert(xyz.end(),
               {xyz[3 * k] == 0 ? -0.0 : xyz[3 * k], xyz[3 * k + 1],
                xyz[3 * k + 2] + (k % 2 == 0 ? 1.0 : -1.0) * (k % 7 == 0 ? 0 : 1)});
  xyz.insert(xyz.end(), {std::nan(""), 1.0, 1.0, 2.0, INFINITY, 0.0, 3.0, 3.0, NAN});
  for (const DuplicateRule rule : {DuplicateRule::LOWEST_Z, DuplicateRule::HIGHEST_Z,
                                   DuplicateRule::MEAN_Z, DuplicateRule::FIRST}) {
    SCOPED_TRACE(duplicateRuleName(rule));
    VtsOptions options;
    options.duplicate_rule = rule;
    expectSameAsOrdinary(xyz, options);
  }
}

TEST(LatticeTriangulation, RowsInOrderOrFallBack)
{
  // Rows from the top, as the raster readers give them: one run of points per row,
  // x increasing (the second read writes the vertices directly), then the same rows
  // with a NaN inside a row (dropped, the same reading), broken so that the general
  // reading decides (a row's points reversed, a duplicate (0, 0) at the end of the
  // last row), or with the rows mixed.
  const std::vector<double> xs = uniformSteps(23, 0.0, 1.0),
                            ys = uniformSteps(17, 0.0, 1.0);
  std::vector<double> top_down;
  for (std::size_t r = ys.size(); r-- > 0;)
    for (std::size_t i = 0; i < xs.size(); ++i)
      if ((i * 7 + r * 3) % 11 != 0)
        top_down.insert(top_down.end(),
                        {xs[i], ys[r], std::cos(0.2 * xs[i]) + 0.1 * ys[r]});
  const std::size_t row = 3 * 20; // inside the first rows
  auto with_nan = top_down;
  with_nan[row + 2] = std::nan("");
  auto reversed = top_down;
  for (std::size_t a = 1, b = 9; a < b; ++a, --b) // points 1 to 9 of the top row
    std::swap_ranges(reversed.begin() + 3 * a, reversed.begin() + 3 * a + 3,
                     reversed.begin() + 3 * b);
  auto duplicate = top_down;
  duplicate.insert(duplicate.end(), {0.0, 0.0, -1.0, 0.0, 0.0, 2.0});
  auto mixed = top_down;
  std::rotate(mixed.begin(), mixed.begin() + 3 * 100, mixed.end());
  for (const auto* xyz : {&top_down, &with_nan, &reversed, &duplicate, &mixed})
    for (const DuplicateRule rule :
         {DuplicateRule::LOWEST_Z, DuplicateRule::MEAN_Z, DuplicateRule::FIRST}) {
      SCOPED_TRACE(duplicateRuleName(rule));
      VtsOptions options;
      options.duplicate_rule = rule;
      expectSameAsOrdinary(*xyz, options);
      options.input_map = false;
      expectSameAsOrdinary(*xyz, options, false);
    }
}

TEST(LatticeTriangulation, NonFiniteOrHugeCoordinateInsideRows)
{
  // Rows from the top with one point broken inside a row: its x the lattice's next
  // value (read without a lookup) and its y NaN, +inf or beyond the trusted range
  // (1e61), or its x so and its y the row's, or its z infinite. Non-finite points are
  // dropped whole (neither coordinate joins the lattice); a coordinate beyond the
  // range is the ordinary path's error.
  const std::vector<double> xs = uniformSteps(15, 0.0, 1.0),
                            ys = uniformSteps(11, 0.0, 1.0);
  std::vector<double> top_down;
  for (std::size_t r = ys.size(); r-- > 0;)
    for (const double x : xs)
      top_down.insert(top_down.end(), {x, ys[r], std::sin(0.4 * x) + 0.2 * ys[r]});
  const std::size_t k = 3 * (2 * xs.size() + 6); // inside the third row
  for (unsigned c = 0; c < 3; ++c)
    for (const double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL, 1e61, -1e61}) {
      SCOPED_TRACE(std::to_string(c) + " " + std::to_string(bad));
      auto xyz = top_down;
      xyz[k + c] = bad;
      VtsOptions options;
      expectSameAsOrdinary(xyz, options);
      options.input_map = false;
      expectSameAsOrdinary(xyz, options, false);
    }
}

TEST(LatticeTriangulation, InputOrderAndThreadsDoNotChangeTheArrays)
{
  const auto xyz =
      rasterPoints(uniformSteps(80, 0.0, 0.5), uniformSteps(70, 0.0, 0.5),
                   [](int i, int j) { return (i / 9 + j / 7) % 4 != 0 || i % 3 == 0; });
  const test::PipelineRun reference = test::runPipeline(xyz);
  ASSERT_TRUE(reference.status.ok());
  std::vector<std::size_t> order(xyz.size() / 3);
  for (std::size_t k = 0; k < order.size(); ++k)
    order[k] = k;
  std::shuffle(order.begin(), order.end(), std::mt19937(3));
  std::vector<double> shuffled;
  for (const std::size_t k : order)
    shuffled.insert(shuffled.end(), xyz.begin() + 3 * k, xyz.begin() + 3 * k + 3);
  VtsOptions two;
  two.threads = 2;
  for (const auto& [input, options] :
       std::vector<std::pair<const std::vector<double>*, VtsOptions>>{
           {&shuffled, VtsOptions{}}, {&xyz, two}}) {
    const test::PipelineRun run = test::runPipeline(*input, options);
    ASSERT_TRUE(run.status.ok());
    EXPECT_EQ(run.result.mesh.xy, reference.result.mesh.xy);
    EXPECT_EQ(run.result.mesh.z, reference.result.mesh.z);
    EXPECT_EQ(run.result.mesh.triangles, reference.result.mesh.triangles);
    EXPECT_EQ(run.result.mesh.halfedges, reference.result.mesh.halfedges);
    EXPECT_EQ(run.result.hull, reference.result.hull);
  }
  expectSameAsOrdinary(shuffled);
}

TEST(LatticeTriangulation, UtmOffsets)
{
  expectSameAsOrdinary(
      rasterPoints(uniformSteps(50, 512345.25, 0.5), uniformSteps(40, 5412345.75, 0.5),
                   [](int i, int j) {
                     return (i - 20) * (i - 20) + (j - 25) * (j - 25) > 30 && j > i / 4;
                   }));
}

TEST(LatticeTriangulation, PostPassesGiveTheSameMesh)
{
  const auto xyz = rasterPoints(
      uniformSteps(60, 0.0, 1.0), uniformSteps(50, 0.0, 1.0), [](int i, int j) {
        return (i - 30) * (i - 30) + (j - 25) * (j - 25) > 16 && i + j > 12;
      });
  VtsOptions options;
  options.reconstruction = ReconstructionOptions{};
  const test::PipelineRun fast = test::runPipeline(xyz, options);
  options.lattice = false;
  const test::PipelineRun slow = test::runPipeline(xyz, options);
  ASSERT_TRUE(fast.status.ok() && slow.status.ok());
  EXPECT_GT(fast.result.reconstruction.fill.holes_filled, 0u);
  EXPECT_EQ(test::verticesByPosition(fast.result.mesh),
            test::verticesByPosition(slow.result.mesh));
  EXPECT_EQ(test::trianglesByPosition(fast.result.mesh),
            test::trianglesByPosition(slow.result.mesh));
}

TEST(LatticeTriangulation, RealDems)
{
  const char* files[] = {"dem/landlab/west_bijou_gully.asc",
                         "dem/landlab/hugo_site.asc",
                         "dem/landlab/zSW3.asc",
                         "dem/landlab/pre_runout_DEM.asc",
                         "dem/landlab/SRTMGL3_boulder_40.09_-105.55.asc",
                         "dem/topotoolbox/exampleDEM_orkhon.asc",
                         "dem/pysheds/dem.derived.asc",
                         "dem/topotoolbox/srtm_bigtujunga30m_utm11.derived.asc"};
  std::size_t read = 0;
  for (const char* file : files) {
    const std::string path = std::string(PCL_VTS_SHARED_DATA_DIR) + "/" + file;
    SCOPED_TRACE(path);
    if (!std::ifstream(path).good())
      continue;
    ++read;
    test::AsciiGrid grid;
    std::string error;
    ASSERT_TRUE(test::readAsciiGrid(path, grid, &error)) << error;
    // CGAL and the invariants below 200k points (the others: the ordinary path only).
    expectSameAsOrdinary(grid.xyz, VtsOptions{}, grid.xyz.size() / 3 < 200000);
  }
  if (read == 0)
    GTEST_SKIP() << "shared data not found in " << PCL_VTS_SHARED_DATA_DIR;
}

} // namespace
} // namespace pcl_vts
