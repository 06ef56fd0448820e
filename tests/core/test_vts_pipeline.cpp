// Property tests of runVtsPipeline: over generators x sizes x seeds, the output must
// satisfy every invariant of a Delaunay triangulation of the convex hull (checked with
// exact predicates) and equal CGAL's triangulation; with cocircular ties it must equal
// the unique triangulation of the symbolically perturbed set, which CGAL computes too
// once the points are mirrored through the origin (see cgal_oracle.h).
#include "support/cgal_oracle.h"
#include "support/generators.h"
#include "support/pipeline_checks.h"

#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/predicates.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace pcl_vts {
namespace {

using test::Distribution;
using test::expectValidTriangulation;
using test::IndexTriangle;
using test::PipelineRun;
using test::runPipeline;
using test::trianglesByPosition;

constexpr double QUIET_NAN = std::numeric_limits<double>::quiet_NaN();
constexpr double INF = std::numeric_limits<double>::infinity();

// ---- Property tests over generators x sizes x seeds ---------------------------------

struct PipelineCase {
  Distribution distribution;
  std::size_t n;
  std::uint64_t seed;
};

std::vector<PipelineCase> pipelineCases()
{
  std::vector<PipelineCase> cases;
  for (const Distribution d : test::allDistributions()) {
    for (std::uint64_t seed = 1; seed <= 16; ++seed)
      cases.push_back({d, 30, seed});
    for (std::uint64_t seed = 1; seed <= 8; ++seed)
      cases.push_back({d, 300, seed});
    for (std::uint64_t seed = 1; seed <= 2; ++seed)
      cases.push_back({d, 3000, seed});
    cases.push_back({d, 20000, 1});
  }
  for (const Distribution d : {Distribution::UNIFORM, Distribution::JITTERED_GRID,
                               Distribution::EXACT_GRID, Distribution::CLUSTERED})
    cases.push_back({d, 200000, 1});
  return cases;
}

class VtsPipelineProperty : public ::testing::TestWithParam<PipelineCase> {};

/// Distributions whose Delaunay triangulation must contain 4 cocircular points, and
/// those where ties have probability zero: checks that both oracle paths run.
bool mustHaveTies(Distribution d)
{
  // Not CONCENTRIC_RINGS: with 30 points it is the centre and one ring, a fan.
  return d == Distribution::EXACT_GRID || d == Distribution::CIRCLE ||
         d == Distribution::ANISOTROPIC;
}

bool cannotHaveTies(Distribution d)
{
  return d == Distribution::UNIFORM || d == Distribution::CLUSTERED ||
         d == Distribution::JITTERED_GRID || d == Distribution::BIG_VOIDS ||
         d == Distribution::THIN_STRIP;
}

TEST_P(VtsPipelineProperty, DelaunayOfTheHullAndEqualToCgal)
{
  const PipelineCase& pc = GetParam();
  std::ostringstream trace;
  trace << test::distributionName(pc.distribution) << " n=" << pc.n
        << " seed=" << pc.seed;
  SCOPED_TRACE(trace.str());
  const std::vector<double> xyz = test::generatePoints(pc.distribution, pc.n, pc.seed);
  const PipelineRun run = runPipeline(xyz);
  const StatusCode expected = test::expectedStatusCode(xyz);
  ASSERT_EQ(run.status.code, expected) << run.status.toString();
  if (expected != StatusCode::OK) {
    EXPECT_TRUE(run.result.mesh.triangles.empty());
    return;
  }
  const test::ValidationSummary summary = expectValidTriangulation(xyz, run);
  if (mustHaveTies(pc.distribution)) {
    EXPECT_TRUE(summary.cocircular_ties);
  }
  if (cannotHaveTies(pc.distribution)) {
    EXPECT_FALSE(summary.cocircular_ties);
  }
  // Strips one column wide: nearly every triangle sits on a strip border.
  VtsOptions narrow;
  narrow.strip_columns = 1;
  const PipelineRun strips = runPipeline(xyz, narrow);
  ASSERT_TRUE(strips.status.ok()) << strips.status.toString();
  expectValidTriangulation(xyz, strips);
}

INSTANTIATE_TEST_SUITE_P(Generators, VtsPipelineProperty,
                         ::testing::ValuesIn(pipelineCases()),
                         [](const ::testing::TestParamInfo<PipelineCase>& param_info) {
                           return test::distributionName(
                                      param_info.param.distribution) +
                                  "_n" + std::to_string(param_info.param.n) + "_seed" +
                                  std::to_string(param_info.param.seed);
                         });

// ---- Determinism and tie-break ------------------------------------------------------

TEST(VtsPipeline, DeterministicOnTheSameInput)
{
  for (const Distribution d :
       {Distribution::UNIFORM, Distribution::EXACT_GRID, Distribution::FLOAT_ROUNDED}) {
    SCOPED_TRACE(test::distributionName(d));
    const std::vector<double> xyz = test::generatePoints(d, 5000, 7);
    const PipelineRun a = runPipeline(xyz), b = runPipeline(xyz);
    ASSERT_TRUE(a.status.ok()) << a.status.toString();
    ASSERT_TRUE(b.status.ok()) << b.status.toString();
    EXPECT_EQ(a.result.mesh.triangles, b.result.mesh.triangles);
    EXPECT_EQ(a.result.mesh.halfedges, b.result.mesh.halfedges);
    EXPECT_EQ(a.result.hull, b.result.hull);
    EXPECT_EQ(a.result.source_index, b.result.source_index);
  }
}

TEST(VtsPipeline, IndependentOfInputOrderUnderTies)
{
  for (const Distribution d :
       {Distribution::EXACT_GRID, Distribution::CIRCLE, Distribution::CONCENTRIC_RINGS,
        Distribution::ANISOTROPIC, Distribution::ROTATED_LATTICE,
        Distribution::FLOAT_ROUNDED, Distribution::DUPLICATES}) {
    SCOPED_TRACE(test::distributionName(d));
    std::vector<double> xyz = test::generatePoints(d, 2000, 3);
    const PipelineRun first = runPipeline(xyz);
    ASSERT_TRUE(first.status.ok()) << first.status.toString();
    const std::vector<IndexTriangle> reference = trianglesByPosition(first.result.mesh);
    std::mt19937_64 rng(99);
    for (int shuffle = 0; shuffle < 3; ++shuffle) {
      // Shuffle whole points; duplicates may now keep another z, not another XY.
      std::vector<std::size_t> perm(xyz.size() / 3);
      std::iota(perm.begin(), perm.end(), std::size_t{0});
      std::shuffle(perm.begin(), perm.end(), rng);
      std::vector<double> shuffled;
      shuffled.reserve(xyz.size());
      for (const std::size_t i : perm)
        shuffled.insert(shuffled.end(), xyz.begin() + 3 * i, xyz.begin() + 3 * i + 3);
      const PipelineRun again = runPipeline(shuffled);
      ASSERT_TRUE(again.status.ok()) << again.status.toString();
      EXPECT_TRUE(trianglesByPosition(again.result.mesh) == reference)
          << "shuffle " << shuffle;
    }
  }
}

TEST(VtsPipeline, CellSizeDoesNotChangeTheTriangulation)
{
  for (const Distribution d : {Distribution::UNIFORM, Distribution::EXACT_GRID,
                               Distribution::CLUSTERED, Distribution::THIN_STRIP}) {
    SCOPED_TRACE(test::distributionName(d));
    const std::vector<double> xyz = test::generatePoints(d, 2000, 5);
    VtsOptions grid_path; // EXACT_GRID would take the lattice path, which has no cell
    grid_path.lattice = false;
    const PipelineRun automatic = runPipeline(xyz, grid_path);
    ASSERT_TRUE(automatic.status.ok()) << automatic.status.toString();
    const double cell = automatic.result.diagnostics.cell_size;
    ASSERT_GT(cell, 0.0);
    for (const double factor : {0.25, 4.0, 1e6}) {
      VtsOptions options = grid_path;
      options.cell_size = cell * factor;
      const PipelineRun run = runPipeline(xyz, options);
      ASSERT_TRUE(run.status.ok())
          << "cell_size x" << factor << ": " << run.status.toString();
      // A cell larger than the data's XY extent is clamped to that extent.
      if (factor < 1.0) {
        EXPECT_EQ(run.result.diagnostics.cell_size, options.cell_size);
      } else {
        EXPECT_LE(run.result.diagnostics.cell_size, options.cell_size);
      }
      EXPECT_TRUE(trianglesByPosition(run.result.mesh) ==
                  trianglesByPosition(automatic.result.mesh))
          << "cell_size x" << factor;
    }
  }
}

TEST(VtsPipeline, SquareOfFourPointsTakesTheTieBreakDiagonal)
{
  // The unit square is the smallest tie. Under the perturbation the smallest point
  // (0, 0) is lifted most, so it is "outside" and the diagonal avoids it: (1,0)-(0,1).
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const PipelineRun run = runPipeline(xyz);
  expectValidTriangulation(xyz, run);
  ASSERT_EQ(run.result.mesh.triangleCount(), 2u);
  const bool uses_00 =
      std::count(run.result.mesh.triangles.begin(), run.result.mesh.triangles.end(),
                 run.result.input_to_vertex[0]) == 2;
  EXPECT_FALSE(uses_00);
  EXPECT_EQ(incirclePerturbed({1, 0}, {1, 1}, {0, 1}, {0, 0}), Sign::NEGATIVE);
}

// ---- Conditioning: duplicates, non-finite values -----------------------------------

/// Four positions, each given several times with distinct z, in scrambled order.
std::vector<double> duplicateInput()
{
  return {
      0, 0, 5,  // 0: (0,0)
      4, 0, 2,  // 1: (4,0)
      0, 0, 3,  // 2: (0,0)
      4, 4, 7,  // 3: (4,4)
      0, 4, 1,  // 4: (0,4)
      0, 0, 9,  // 5: (0,0)
      4, 0, -1, // 6: (4,0)
      2, 2, 0,  // 7: (2,2), unique
      4, 4, 6,  // 8: (4,4)
      0, 4, 8,  // 9: (0,4)
  };
}

TEST(VtsPipeline, DuplicatesFollowTheRule)
{
  const std::vector<double> xyz = duplicateInput();
  struct Expected {
    DuplicateRule rule;
    // (0,0), (4,0), (4,4), (0,4): z and source per rule.
    double z[4];
    std::uint32_t source[4];
  };
  const Expected table[] = {
      {DuplicateRule::LOWEST_Z, {3, -1, 6, 1}, {2, 6, 8, 4}},
      {DuplicateRule::HIGHEST_Z, {9, 2, 7, 8}, {5, 1, 3, 9}},
      {DuplicateRule::MEAN_Z, {17.0 / 3.0, 0.5, 6.5, 4.5}, {0, 1, 3, 4}},
      {DuplicateRule::FIRST, {5, 2, 7, 1}, {0, 1, 3, 4}},
  };
  const std::uint32_t first_of[4] = {0, 1, 3, 4};
  for (const Expected& e : table) {
    SCOPED_TRACE(duplicateRuleName(e.rule));
    VtsOptions options;
    options.duplicate_rule = e.rule;
    const PipelineRun run = runPipeline(xyz, options);
    expectValidTriangulation(xyz, run, options);
    ASSERT_TRUE(run.status.ok());
    EXPECT_EQ(run.result.diagnostics.duplicates_merged, 5u);
    EXPECT_EQ(run.result.mesh.vertexCount(), 5u);
    for (int k = 0; k < 4; ++k) {
      const VertexId v = run.result.input_to_vertex[first_of[k]];
      EXPECT_DOUBLE_EQ(run.result.mesh.z[v], e.z[k]) << "position " << k;
      EXPECT_EQ(run.result.source_index[v], e.source[k]) << "position " << k;
    }
    const VertexId centre = run.result.input_to_vertex[7];
    EXPECT_EQ(run.result.mesh.z[centre], 0.0);
    EXPECT_EQ(run.result.source_index[centre], 7u);
  }
}

// input_map off leaves input_to_vertex empty and every other byte of the result as
// it was: with and without merged duplicates, under every rule, on the grid and the
// lattice path, with -0.0 heights (the mean of one point is +0.0).
TEST(VtsPipeline, WithoutTheInputMapTheResultIsTheSame)
{
  std::vector<double> scattered = test::generatePoints(Distribution::UNIFORM, 3000, 5);
  for (std::size_t k = 0; k < scattered.size() / 3; k += 7)
    scattered[3 * k + 2] = -0.0;
  std::vector<double> raster; // a lattice with -0.0 heights and a missing cell
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i)
      if (i != 17 || j != 23)
        raster.insert(raster.end(),
                      {double(i), double(j), (i + j) % 5 == 0 ? -0.0 : 0.5 * i});
  const std::vector<std::pair<const char*, std::vector<double>>> inputs = {
      {"scattered", scattered}, {"duplicates", duplicateInput()}, {"raster", raster}};
  const auto bits = [](const std::vector<double>& v) {
    std::vector<std::uint64_t> b(v.size());
    std::memcpy(b.data(), v.data(), v.size() * sizeof(double));
    return b;
  };
  for (const auto& [name, xyz] : inputs)
    for (DuplicateRule rule : {DuplicateRule::LOWEST_Z, DuplicateRule::HIGHEST_Z,
                               DuplicateRule::MEAN_Z, DuplicateRule::FIRST}) {
      SCOPED_TRACE(std::string(name) + ", " + duplicateRuleName(rule));
      VtsOptions options;
      options.duplicate_rule = rule;
      const PipelineRun with = runPipeline(xyz, options);
      options.input_map = false;
      const PipelineRun without = runPipeline(xyz, options);
      ASSERT_TRUE(with.status.ok());
      ASSERT_TRUE(without.status.ok());
      EXPECT_EQ(with.result.input_to_vertex.size(), xyz.size() / 3);
      EXPECT_TRUE(without.result.input_to_vertex.empty());
      EXPECT_EQ(with.result.mesh.triangles, without.result.mesh.triangles);
      EXPECT_EQ(with.result.mesh.halfedges, without.result.mesh.halfedges);
      EXPECT_EQ(with.result.source_index, without.result.source_index);
      EXPECT_EQ(with.result.hull, without.result.hull);
      EXPECT_EQ(bits(with.result.mesh.z), bits(without.result.mesh.z));
      ASSERT_EQ(with.result.mesh.xy.size(), without.result.mesh.xy.size());
      EXPECT_EQ(0,
                std::memcmp(with.result.mesh.xy.data(), without.result.mesh.xy.data(),
                            with.result.mesh.xy.size() * sizeof(Point2)));
    }
}

// The overload that takes the input over lends its memory to the trim's rows (once
// the heights are read): the same mesh, spacing and flags as the call on a pointer,
// through the ordinary and the lattice paths, with merged duplicates, at 1 and 2
// threads; the input is left empty.
TEST(VtsPipeline, HandingTheInputOverGivesTheSameResult)
{
  std::vector<double> raster; // a lattice with a hole of missing cells
  for (int j = 0; j < 60; ++j)
    for (int i = 0; i < 60; ++i)
      if ((i - 30) * (i - 30) + (j - 25) * (j - 25) > 40)
        raster.insert(raster.end(), {double(i), double(j), 0.25 * i - 0.5 * j});
  const std::vector<std::pair<const char*, std::vector<double>>> inputs = {
      {"big voids", test::generatePoints(Distribution::BIG_VOIDS, 20000, 3)},
      {"clustered", test::generatePoints(Distribution::CLUSTERED, 20000, 4)},
      {"duplicates", test::generatePoints(Distribution::DUPLICATES, 5000, 5)},
      {"raster", raster}};
  const auto bits = [](const auto& v) {
    std::vector<unsigned char> b(v.size() * sizeof(v[0]));
    std::memcpy(b.data(), v.data(), b.size());
    return b;
  };
  for (const auto& [name, xyz] : inputs)
    for (unsigned threads : {1u, 2u}) {
      SCOPED_TRACE(std::string(name) + ", threads " + std::to_string(threads));
      VtsOptions options;
      options.threads = threads;
      options.duplicate_rule = DuplicateRule::MEAN_Z;
      options.reconstruction.trim = true;
      options.reconstruction.fill = true;
      VtsResult on_pointer, handed;
      ASSERT_TRUE(runVtsPipeline(xyz.data(), xyz.size() / 3, options, on_pointer).ok());
      std::vector<double> input = xyz;
      ASSERT_TRUE(runVtsPipeline(std::move(input), options, handed).ok());
      EXPECT_TRUE(input.empty()); // NOLINT(bugprone-use-after-move): the contract
      EXPECT_GT(on_pointer.reconstruction.trim.triangles_removed, 0U);
      EXPECT_EQ(on_pointer.mesh.triangles, handed.mesh.triangles);
      EXPECT_EQ(on_pointer.mesh.halfedges, handed.mesh.halfedges);
      EXPECT_EQ(bits(on_pointer.mesh.xy), bits(handed.mesh.xy));
      EXPECT_EQ(bits(on_pointer.mesh.z), bits(handed.mesh.z));
      EXPECT_EQ(on_pointer.source_index, handed.source_index);
      EXPECT_EQ(on_pointer.input_to_vertex, handed.input_to_vertex);
      const ReconstructionDiagnostics &a = on_pointer.reconstruction,
                                      &b = handed.reconstruction;
      EXPECT_EQ(a.trim.triangles_removed, b.trim.triangles_removed);
      EXPECT_EQ(a.trim.vertices_lost, b.trim.vertices_lost);
      EXPECT_EQ(bits(std::vector<double>{a.trim.spacing}),
                bits(std::vector<double>{b.trim.spacing}));
      EXPECT_EQ(a.fill.holes_found, b.fill.holes_found);
      EXPECT_EQ(a.fill.points_inserted, b.fill.points_inserted);
      EXPECT_EQ(a.fill.inserted, b.fill.inserted);
    }
}

TEST(VtsPipeline, NonFinitePointsAreDroppedAndCounted)
{
  std::vector<double> xyz = test::generatePoints(Distribution::UNIFORM, 500, 3);
  const std::size_t bad[] = {0, 17, 18, 250, 499};
  xyz[3 * bad[0]] = QUIET_NAN;
  xyz[3 * bad[1] + 1] = INF;
  xyz[3 * bad[2] + 2] = QUIET_NAN; // z alone is enough to drop a point
  xyz[3 * bad[3]] = -INF;
  xyz[3 * bad[4] + 2] = INF;
  const PipelineRun run = runPipeline(xyz);
  expectValidTriangulation(xyz, run);
  EXPECT_EQ(run.result.diagnostics.non_finite_dropped, 5u);
  for (const std::size_t i : bad)
    EXPECT_EQ(run.result.input_to_vertex[i], INVALID_ID) << "input " << i;
}

// ---- Errors: a code a caller can test and a message naming the values --------------

void expectError(const PipelineRun& run, StatusCode code,
                 const std::vector<std::string>& words)
{
  EXPECT_EQ(run.status.code, code) << run.status.toString();
  for (const std::string& w : words)
    EXPECT_NE(run.status.message.find(w), std::string::npos)
        << "message '" << run.status.message << "' should mention '" << w << "'";
  EXPECT_TRUE(run.result.mesh.triangles.empty());
  EXPECT_TRUE(run.result.mesh.xy.empty());
}

TEST(VtsPipelineErrors, EmptyInput)
{
  VtsResult result;
  const Status s = runVtsPipeline(nullptr, 0, VtsOptions{}, result);
  EXPECT_EQ(s.code, StatusCode::EMPTY_INPUT) << s.toString();
  EXPECT_FALSE(s.message.empty());
  EXPECT_TRUE(result.mesh.triangles.empty());
  EXPECT_EQ(std::string(statusCodeName(s.code)), "EMPTY_INPUT");
}

TEST(VtsPipelineErrors, HandedInputNotInTriplesIsRejected)
{
  // Ten values: three points and one stray value, which n = size / 3 would drop.
  std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5};
  VtsResult result;
  const Status s = runVtsPipeline(std::move(xyz), VtsOptions{}, result);
  EXPECT_EQ(s.code, StatusCode::INVALID_PARAMETER) << s.toString();
  EXPECT_NE(s.message.find("10 values"), std::string::npos) << s.message;
  EXPECT_TRUE(result.mesh.triangles.empty());
}

TEST(VtsPipelineErrors, AllNonFiniteIsEmptyInput)
{
  const std::vector<double> xyz = {QUIET_NAN, 0, 0,   1,    QUIET_NAN, 0,
                                   1,         1, INF, -INF, 2,         2};
  const PipelineRun run = runPipeline(xyz);
  expectError(run, StatusCode::EMPTY_INPUT, {"4"});
  EXPECT_EQ(run.result.diagnostics.non_finite_dropped, 4u);
  EXPECT_EQ(run.result.diagnostics.points_in, 4u);
}

TEST(VtsPipelineErrors, FewerThanThreeDistinctPoints)
{
  expectError(runPipeline({1, 2, 3}), StatusCode::TOO_FEW_POINTS, {});
  expectError(runPipeline({1, 2, 3, 4, 5, 6}), StatusCode::TOO_FEW_POINTS, {});
  std::vector<double> two_positions;
  for (int k = 0; k < 1000; ++k) {
    two_positions.insert(two_positions.end(), {5e5, 5e6, static_cast<double>(k)});
    two_positions.insert(two_positions.end(), {5e5 + 0.001, 5e6, 1.0});
  }
  const PipelineRun run = runPipeline(two_positions);
  expectError(run, StatusCode::TOO_FEW_POINTS, {"2"});
  EXPECT_EQ(run.result.diagnostics.duplicates_merged, 1998u);
}

TEST(VtsPipelineErrors, AllCollinear)
{
  expectError(runPipeline(test::generatePoints(Distribution::COLLINEAR, 1000, 1)),
              StatusCode::ALL_COLLINEAR, {});
  // Collinear with duplicates and a NaN among them, at UTM magnitude.
  const std::vector<double> xyz = {5e5,     5e6,     0,         5e5 + 1, 5e6 + 2,
                                   0,       5e5 + 2, 5e6 + 4,   0,       5e5 + 1,
                                   5e6 + 2, 9,       QUIET_NAN, 0,       0};
  expectError(runPipeline(xyz), StatusCode::ALL_COLLINEAR, {});
  // One point a single ulp off the line is enough to triangulate.
  std::vector<double> off = xyz;
  off[3 * 2 + 1] = std::nextafter(off[3 * 2 + 1], INF);
  const PipelineRun run = runPipeline(off);
  expectValidTriangulation(off, run);
  EXPECT_EQ(run.result.mesh.triangleCount(), 1u);
}

TEST(VtsPipelineErrors, InvalidCellSizeIsNamed)
{
  const std::vector<double> xyz = test::generatePoints(Distribution::UNIFORM, 100, 1);
  VtsOptions options;
  options.cell_size = -2.0;
  expectError(runPipeline(xyz, options), StatusCode::INVALID_PARAMETER,
              {"cell_size", "-2"});
  EXPECT_EQ(validateOptions(options).code, StatusCode::INVALID_PARAMETER);
  options.cell_size = QUIET_NAN;
  expectError(runPipeline(xyz, options), StatusCode::INVALID_PARAMETER,
              {"cell_size", "nan"});
  options.cell_size = INF;
  expectError(runPipeline(xyz, options), StatusCode::INVALID_PARAMETER,
              {"cell_size", "inf"});
  options.cell_size = 0.0; // automatic
  EXPECT_TRUE(validateOptions(options).ok());
}

// The documented decision (docs/decisions.md, "huge coordinates" and "tiny extent"):
// |x| or |y| beyond 1e60 is COORDINATE_RANGE, naming the point; up to 1e60 the mesh is
// built. An XY extent below 1e-80 (but not zero) is COORDINATE_RANGE; the magnitude of
// single coordinates (subnormals included) does not matter when the extent is normal.

TEST(VtsPipelineErrors, CoordinatesBeyond1e60AreRejected)
{
  for (const double scale : {1e200, 1e300, std::numeric_limits<double>::max() / 4}) {
    SCOPED_TRACE(scale);
    std::vector<double> xyz = test::generatePoints(Distribution::UNIFORM, 200, 2);
    for (std::size_t i = 0; i < xyz.size(); i += 3) {
      xyz[i] = (xyz[i] / 1000.0 - 0.5) * scale;
      xyz[i + 1] = (xyz[i + 1] / 1000.0 - 0.5) * scale;
    }
    expectError(runPipeline(xyz), StatusCode::COORDINATE_RANGE,
                {"point 0 has XY (", "beyond +-1e+60", "shift or rescale"});
  }
}

TEST(VtsPipelineErrors, CoordinatesUpTo1e60AreTriangulated)
{
  // Corners exactly at +-1e60: the largest accepted magnitude, a valid mesh.
  std::vector<double> xyz = test::generatePoints(Distribution::UNIFORM, 200, 2);
  for (std::size_t i = 0; i < xyz.size(); i += 3) {
    xyz[i] = (xyz[i] / 1000.0 - 0.5) * 1e59;
    xyz[i + 1] = (xyz[i + 1] / 1000.0 - 0.5) * 1e59;
  }
  xyz.insert(xyz.end(),
             {-1e60, -1e60, 0, 1e60, -1e60, 0, 1e60, 1e60, 0, -1e60, 1e60, 0});
  const PipelineRun run = runPipeline(xyz);
  ASSERT_TRUE(run.status.ok()) << run.status.toString();
  expectValidTriangulation(xyz, run);
  // One ulp further on one point: rejected, and that point is named.
  xyz[xyz.size() - 3] = std::nextafter(-1e60, -INF);
  expectError(runPipeline(xyz), StatusCode::COORDINATE_RANGE,
              {"point 203 has XY (", "beyond +-1e+60"});
}

TEST(VtsPipelineErrors, ExtentOfAFewUlpsAtUtmMagnitude)
{
  // 100 points on a 41 x 41 ulp lattice at (5.4e6, 5.4e6): duplicates and ties. The
  // extent (about 4e-8) is far above 1e-80: triangulated.
  std::vector<double> xyz;
  std::mt19937_64 rng(4);
  std::uniform_int_distribution<int> ulps(0, 40);
  for (int k = 0; k < 100; ++k) {
    double x = 5.4e6, y = 5.4e6;
    for (int s = ulps(rng); s > 0; --s)
      x = std::nextafter(x, INF);
    for (int s = ulps(rng); s > 0; --s)
      y = std::nextafter(y, INF);
    xyz.insert(xyz.end(), {x, y, 1.0});
  }
  const PipelineRun run = runPipeline(xyz);
  ASSERT_TRUE(run.status.ok()) << run.status.toString();
  expectValidTriangulation(xyz, run);
}

TEST(VtsPipelineErrors, SubnormalExtentIsRejected)
{
  // Multiples of the smallest subnormal: the extent is below 1e-80.
  const double tiny = std::numeric_limits<double>::denorm_min();
  std::vector<std::vector<double>> inputs = {
      {0, 0, 1, tiny, 0, 1, 0, tiny, 1},
      {0, 0, 1, 2 * tiny, 0, 1, 0, 2 * tiny, 1},
      {0, 0, 1, 40 * tiny, 0, 1, 0, 40 * tiny, 1, 40 * tiny, 40 * tiny, 1},
  };
  std::mt19937_64 rng(4);
  std::uniform_int_distribution<int> multiple(0, 40);
  std::vector<double> cloud;
  for (int k = 0; k < 100; ++k)
    cloud.insert(cloud.end(), {tiny * multiple(rng), tiny * multiple(rng), 1.0});
  inputs.push_back(cloud);
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    SCOPED_TRACE("input " + std::to_string(k));
    expectError(runPipeline(inputs[k]), StatusCode::COORDINATE_RANGE,
                {"the XY extent", "is below 1e-80", "rescale"});
  }
  // Just below the limit: rejected too.
  const double below = std::nextafter(1e-80, 0.0);
  expectError(runPipeline({0, 0, 1, below, 0, 1, 0, below, 1}),
              StatusCode::COORDINATE_RANGE, {"the XY extent", "is below 1e-80"});
}

TEST(VtsPipelineErrors, ExtentOf1eMinus80AndSubnormalsInANormalExtentAreTriangulated)
{
  const double tiny = std::numeric_limits<double>::denorm_min();
  const std::vector<std::vector<double>> inputs = {
      // The smallest accepted extent.
      {0, 0, 1, 1e-80, 0, 1, 0, 1e-80, 1, 1e-80, 1e-80, 2, 3e-81, 6e-81, 3},
      // Subnormal coordinates among normal ones: the extent is 1.
      {0, 0, 1, 1, 0, 1, 0, 1, 1, tiny, 3 * tiny, 2, 0.5, tiny, 3, 1, 1, 4},
  };
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    SCOPED_TRACE("input " + std::to_string(k));
    const PipelineRun run = runPipeline(inputs[k]);
    ASSERT_TRUE(run.status.ok()) << run.status.toString();
    expectValidTriangulation(inputs[k], run);
  }
}

// ---- The oracle itself
// ----------------------------------------------------------------

/// CGAL's triangulation of the XY of xyz as a mesh with its own ids.
TriangleMesh oracleMesh(const std::vector<double>& xyz, bool mirrored)
{
  TriangleMesh mesh;
  for (std::size_t i = 0; i < xyz.size(); i += 3)
    mesh.xy.push_back({xyz[i], xyz[i + 1]});
  mesh.z.assign(mesh.xy.size(), 0.0);
  const std::vector<IndexTriangle> tris =
      mirrored ? test::cgalDelaunayMirrored(mesh.xy) : test::cgalDelaunay(mesh.xy);
  for (const IndexTriangle& t : tris)
    mesh.triangles.insert(mesh.triangles.end(), t.begin(), t.end());
  EXPECT_TRUE(mesh.rebuildHalfedges());
  return mesh;
}

TEST(CgalOracle, MirroredCgalFollowsThePerturbation)
{
  // Comparing with the mirrored oracle under ties proves something only if it really
  // computes the perturbed triangulation.
  for (const Distribution d :
       {Distribution::EXACT_GRID, Distribution::CIRCLE, Distribution::CONCENTRIC_RINGS,
        Distribution::ANISOTROPIC, Distribution::FLOAT_ROUNDED}) {
    SCOPED_TRACE(test::distributionName(d));
    const TriangleMesh mesh = oracleMesh(test::generatePoints(d, 1000, 1), true);
    std::string why;
    EXPECT_TRUE(allTrianglesCcw(mesh, &why)) << why;
    EXPECT_TRUE(isDelaunay(mesh, &why)) << why;
    EXPECT_TRUE(test::isPerturbedDelaunay(mesh, &why)) << why;
  }
}

TEST(CgalOracle, PlainCgalBreaksTiesTheOtherWay)
{
  // On one circle every triangulation is Delaunay and the tie-break alone decides.
  // CGAL perturbs the lexicographically largest point most, pcl_vts the smallest: the
  // results differ, which is why the oracle mirrors the points. (On a square grid the
  // two rules agree: the smallest and largest corners of a cell are opposite. So
  // they do on any centrally symmetric set, hence a random 200 of the 256 points.)
  const std::vector<double> xyz = test::generatePoints(Distribution::CIRCLE, 200, 1);
  const TriangleMesh plain = oracleMesh(xyz, false);
  std::string why;
  EXPECT_TRUE(isDelaunay(plain, &why)) << why;
  EXPECT_FALSE(test::isPerturbedDelaunay(plain));
}

// ---- The whole-output check itself can fail
// ------------------------------------------

/// Failures expectValidTriangulation reports on run, captured instead of recorded.
std::vector<std::string> capturedFailures(const std::vector<double>& xyz,
                                          const PipelineRun& run)
{
  ::testing::TestPartResultArray results;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD,
        &results);
    expectValidTriangulation(xyz, run);
  }
  std::vector<std::string> messages;
  for (int i = 0; i < results.size(); ++i)
    messages.push_back(results.GetTestPartResult(i).message());
  return messages;
}

bool anyContains(const std::vector<std::string>& messages, const std::string& word)
{
  return std::any_of(messages.begin(), messages.end(), [&](const std::string& m) {
    return m.find(word) != std::string::npos;
  });
}

TEST(PipelineChecks, CatchDamagedResults)
{
  const std::vector<double> xyz = test::generatePoints(Distribution::UNIFORM, 300, 8);
  const PipelineRun good = runPipeline(xyz);
  ASSERT_TRUE(capturedFailures(xyz, good).empty());

  { // A flipped interior edge (convex quad, so both new triangles stay CCW).
    PipelineRun bad = good;
    TriangleMesh& m = bad.result.mesh;
    bool flipped = false;
    for (std::size_t i = 0; i < m.halfedges.size() && !flipped; ++i) {
      const auto e = static_cast<HalfedgeId>(i);
      const HalfedgeId t = m.halfedges[e];
      if (t == INVALID_ID)
        continue;
      const VertexId a = m.triangles[e], b = m.triangles[nextHalfedge(e)];
      const VertexId c = m.triangles[prevHalfedge(e)], d = m.triangles[prevHalfedge(t)];
      if (orient2d(m.xy[a], m.xy[d], m.xy[c]) != Sign::POSITIVE ||
          orient2d(m.xy[d], m.xy[b], m.xy[c]) != Sign::POSITIVE)
        continue;
      const TriangleId t1 = triangleOf(e), t2 = triangleOf(t);
      const VertexId first[3] = {a, d, c}, second[3] = {d, b, c};
      std::copy(first, first + 3, m.triangles.begin() + 3 * t1);
      std::copy(second, second + 3, m.triangles.begin() + 3 * t2);
      ASSERT_TRUE(m.rebuildHalfedges());
      flipped = true;
    }
    ASSERT_TRUE(flipped);
    const std::vector<std::string> failures = capturedFailures(xyz, bad);
    EXPECT_TRUE(anyContains(failures, "not Delaunay"));
    EXPECT_TRUE(anyContains(failures, "only in CGAL"));
  }
  { // A clockwise triangle.
    PipelineRun bad = good;
    std::swap(bad.result.mesh.triangles[0], bad.result.mesh.triangles[1]);
    EXPECT_TRUE(anyContains(capturedFailures(xyz, bad), "clockwise"));
  }
  { // A hull vertex missing.
    PipelineRun bad = good;
    bad.result.hull.pop_back();
    EXPECT_FALSE(capturedFailures(xyz, bad).empty());
  }
  { // A triangle missing.
    PipelineRun bad = good;
    bad.result.mesh.triangles.resize(bad.result.mesh.triangles.size() - 3);
    EXPECT_TRUE(bad.result.mesh.rebuildHalfedges());
    EXPECT_FALSE(capturedFailures(xyz, bad).empty());
  }
  { // A vertex whose z breaks the duplicate rule.
    PipelineRun bad = good;
    bad.result.mesh.z[5] += 1.0;
    EXPECT_TRUE(anyContains(capturedFailures(xyz, bad), "against rule"));
  }
}

} // namespace
} // namespace pcl_vts
