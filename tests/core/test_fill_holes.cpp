// Hole filling and its parts: the polygon CDT (tiles the polygon, keeps its edges,
// Delaunay elsewhere, rejects non-simple input), the thin-plate spline (interpolates,
// reproduces planes), and fillHoles on the synthetic terrain: voids under the limit
// covered >= 99 % and their loops gone, larger ones left open, inserted points
// flagged, z error against the true surface compared with a flat-rim fill.
#include "support/generators.h"
#include "support/mesh_shuffle.h"
#include "support/pipeline_checks.h"
#include "support/surface_checks.h"

#include <pcl_vts/core/boundary_loops.h>
#include <pcl_vts/core/fill_holes.h>
#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/polygon_triangulation.h>
#include <pcl_vts/core/predicates.h>
#include <pcl_vts/core/reconstruct_surface.h>
#include <pcl_vts/core/thin_plate_spline.h>
#include <pcl_vts/core/trim_outward_triangles.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace pcl_vts {
namespace {

/// Every property of a CDT of the polygon points[0..n) with its Steiner points.
void expectPolygonCdt(const std::vector<Point2>& points, std::size_t n,
                      const PolygonTriangulation& out)
{
  TriangleMesh mesh;
  mesh.xy = points;
  mesh.z.assign(points.size(), 0.0);
  mesh.triangles.assign(out.triangles.begin(), out.triangles.end());
  ASSERT_TRUE(mesh.rebuildHalfedges());
  std::string why;
  EXPECT_TRUE(allTrianglesCcw(mesh, &why)) << why;
  EXPECT_TRUE(isEdgeManifold(mesh, &why)) << why;
  // Boundary = exactly the polygon edges, in its direction.
  std::set<std::pair<VertexId, VertexId>> boundary;
  for (std::size_t e = 0; e < mesh.halfedges.size(); ++e)
    if (mesh.halfedges[e] == INVALID_ID)
      boundary.insert({mesh.triangles[e], mesh.triangles[nextHalfedge(e)]});
  std::set<std::pair<VertexId, VertexId>> polygon;
  for (std::size_t i = 0; i < n; ++i)
    polygon.insert({static_cast<VertexId>(i), static_cast<VertexId>((i + 1) % n)});
  EXPECT_EQ(boundary, polygon);
  // Area equal to the polygon's, and Delaunay on every non-polygon edge.
  double twice_polygon = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    twice_polygon +=
        points[i].x * points[(i + 1) % n].y - points[(i + 1) % n].x * points[i].y;
  EXPECT_NEAR(twiceArea(mesh), twice_polygon, 1e-9 * std::fabs(twice_polygon));
  EXPECT_TRUE(isDelaunay(mesh, &why)) << why;
  // Euler: a disc.
  EXPECT_EQ(eulerCharacteristic(mesh), 1);
  std::size_t used = 0;
  for (const std::uint8_t u : out.steiner_used)
    used += u;
  EXPECT_EQ(mesh.triangleCount(), n - 2 + 2 * used);
}

TEST(PolygonTriangulation, ConvexSquareWithLatticePoints)
{
  std::vector<Point2> points = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  for (int j = 1; j < 4; ++j)
    for (int i = 1; i < 4; ++i) // exact ties: a square lattice
      points.push_back({static_cast<double>(i), static_cast<double>(j)});
  PolygonTriangulation out;
  ASSERT_TRUE(triangulatePolygon(points, 4, out).ok());
  EXPECT_EQ(std::count(out.steiner_used.begin(), out.steiner_used.end(), 1), 9);
  expectPolygonCdt(points, 4, out);
}

TEST(PolygonTriangulation, CombKeepsItsTeethAndSkipsBadPoints)
{
  // A comb: concave, with collinear vertices along the back.
  std::vector<Point2> points = {{0, 0}, {10, 0}, {10, 6}, {9, 6}, {9, 1},
                                {7, 1}, {7, 6},  {5, 6},  {5, 1}, {3, 1},
                                {3, 6}, {1, 6},  {1, 1},  {0, 1}};
  const std::size_t n = points.size();
  points.push_back({8, 0.5}); // inside
  points.push_back({4, 0.5}); // inside
  points.push_back({2, 3});   // inside a tooth gap? no: outside (gap between teeth)
  points.push_back({5, 0});   // on a polygon edge: skipped
  points.push_back({4, 0.5}); // duplicate: skipped
  points.push_back({8, 3});   // inside the last tooth
  PolygonTriangulation out;
  ASSERT_TRUE(triangulatePolygon(points, n, out).ok());
  EXPECT_EQ(out.steiner_used, (std::vector<std::uint8_t>{1, 1, 1, 0, 0, 0}));
  // Check without the skipped points.
  std::vector<Point2> kept(points.begin(), points.begin() + static_cast<long>(n));
  std::vector<std::uint32_t> remap(points.size());
  for (std::size_t i = 0; i < n; ++i)
    remap[i] = static_cast<std::uint32_t>(i);
  for (std::size_t k = n; k < points.size(); ++k)
    if (out.steiner_used[k - n]) {
      remap[k] = static_cast<std::uint32_t>(kept.size());
      kept.push_back(points[k]);
    }
  PolygonTriangulation mapped = out;
  for (std::uint32_t& v : mapped.triangles)
    v = remap[v];
  mapped.steiner_used = {1, 1, 1};
  expectPolygonCdt(kept, n, mapped);
}

TEST(PolygonTriangulation, RandomStarPolygonsWithManyPoints)
{
  for (int seed = 0; seed < 20; ++seed) {
    SCOPED_TRACE(seed);
    // Star-shaped polygon with random radii, then random points tested inside.
    std::vector<Point2> points;
    const int n = 12 + seed * 3;
    std::uint64_t state = 88172645463325252ull + static_cast<unsigned>(seed);
    auto random = [&state]() {
      state ^= state << 13;
      state ^= state >> 7;
      state ^= state << 17;
      return static_cast<double>(state >> 11) * 0x1p-53;
    };
    for (int i = 0; i < n; ++i) {
      const double angle = 2 * M_PI * i / n;
      const double r = 3 + 7 * random();
      points.push_back({r * std::cos(angle), r * std::sin(angle)});
    }
    for (int k = 0; k < 200; ++k)
      points.push_back({-10 + 20 * random(), -10 + 20 * random()});
    PolygonTriangulation out;
    ASSERT_TRUE(triangulatePolygon(points, static_cast<std::size_t>(n), out).ok());
    std::vector<Point2> kept(points.begin(), points.begin() + n);
    std::vector<std::uint32_t> remap(points.size());
    for (int i = 0; i < n; ++i)
      remap[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(i);
    for (std::size_t k = static_cast<std::size_t>(n); k < points.size(); ++k)
      if (out.steiner_used[k - static_cast<std::size_t>(n)]) {
        remap[k] = static_cast<std::uint32_t>(kept.size());
        kept.push_back(points[k]);
      }
    PolygonTriangulation mapped = out;
    for (std::uint32_t& v : mapped.triangles)
      v = remap[v];
    mapped.steiner_used.assign(kept.size() - static_cast<std::size_t>(n), 1);
    expectPolygonCdt(kept, static_cast<std::size_t>(n), mapped);
    EXPECT_GT(kept.size(), static_cast<std::size_t>(n) + 20);
  }
}

TEST(PolygonTriangulation, RejectsClockwiseAndSelfIntersectingPolygons)
{
  PolygonTriangulation out;
  const std::vector<Point2> cw = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  EXPECT_EQ(triangulatePolygon(cw, 4, out).code, StatusCode::INVALID_PARAMETER);
  const std::vector<Point2> bowtie = {{0, 0}, {2, 2}, {2, 0}, {0, 2}};
  EXPECT_EQ(triangulatePolygon(bowtie, 4, out).code, StatusCode::INVALID_PARAMETER);
  const Status status = triangulatePolygon(cw, 2, out);
  EXPECT_EQ(status.code, StatusCode::INVALID_PARAMETER);
  EXPECT_NE(status.message.find("polygon_size = 2"), std::string::npos);
}

TEST(ThinPlateSpline, InterpolatesAndReproducesPlanes)
{
  std::vector<Point2> xy;
  std::vector<double> plane, bumpy;
  for (int i = 0; i < 40; ++i) {
    const double a = 0.7 * i;
    xy.push_back({5e5 + 10 * std::cos(a) + 0.1 * i, 4e6 + 8 * std::sin(a)});
    plane.push_back(3 + 0.5 * (xy.back().x - 5e5) - 0.25 * (xy.back().y - 4e6));
    bumpy.push_back(std::sin(xy.back().x) + 0.1 * i);
  }
  ThinPlateSpline spline;
  ASSERT_TRUE(spline.fit(xy, plane));
  EXPECT_TRUE(spline.isSpline());
  EXPECT_NEAR(spline.evaluate({5e5 + 1, 4e6 + 2}), 3 + 0.5 - 0.5, 1e-6);
  ASSERT_TRUE(spline.fit(xy, bumpy));
  for (std::size_t i = 0; i < xy.size(); ++i)
    EXPECT_NEAR(spline.evaluate(xy[i]), bumpy[i], 1e-6);
  // Degenerate inputs fall back, never fail.
  ASSERT_TRUE(spline.fit({{0, 0}, {1, 1}, {2, 2}, {3, 3}}, {1, 2, 3, 4}));
  EXPECT_TRUE(std::isfinite(spline.evaluate({5, 0})));
  ASSERT_TRUE(spline.fit({{1, 1}}, {7}));
  EXPECT_DOUBLE_EQ(spline.evaluate({3, 3}), 7.0);
  EXPECT_FALSE(spline.fit({}, {}));
}

TriangleMesh trimmedTerrain(const test::SyntheticTerrain& terrain)
{
  const test::PipelineRun run = test::runPipeline(terrain.xyz);
  EXPECT_TRUE(run.status.ok()) << run.status.toString();
  TriangleMesh mesh = run.result.mesh;
  TrimResult trim;
  EXPECT_TRUE(trimOutwardTriangles(mesh, TrimOptions{}, trim).ok());
  return mesh;
}

/// 600 area units: voids of radius <= 10 are filled, radius 25 stays open.
constexpr double HOLE_LIMIT = 600.0;

TEST(FillHoles, SyntheticVoidsFilledUnderTheLimitAndZErrorReported)
{
  const test::SyntheticTerrain terrain = test::makeSyntheticTerrain(7);
  const TriangleMesh trimmed = trimmedTerrain(terrain);
  BoundaryLoops before;
  ASSERT_TRUE(findBoundaryLoops(trimmed, before).ok());

  test::ZError vertex_error[2], patch_error[2];
  for (const HoleZMethod method :
       {HoleZMethod::THIN_PLATE_SPLINE, HoleZMethod::FLAT_RIM_MEAN}) {
    const int m = method == HoleZMethod::THIN_PLATE_SPLINE ? 0 : 1;
    SCOPED_TRACE(m);
    TriangleMesh mesh = trimmed;
    FillOptions options;
    options.max_hole_area = HOLE_LIMIT;
    options.z_method = method;
    FillResult result;
    ASSERT_TRUE(fillHoles(mesh, options, result).ok());
    test::expectValidSurfaceMesh(mesh);
    EXPECT_EQ(result.holes_found, before.holeCount());
    EXPECT_EQ(result.holes_left_open, 1u);
    EXPECT_EQ(result.holes_skipped, 0u);
    EXPECT_EQ(result.holes_filled, result.holes_found - 1);
    EXPECT_EQ(result.inserted.size(), mesh.vertexCount());
    EXPECT_EQ(static_cast<std::size_t>(
                  std::count(result.inserted.begin(), result.inserted.end(), 1)),
              result.points_inserted);
    EXPECT_EQ(mesh.vertexCount(), trimmed.vertexCount() + result.points_inserted);
    EXPECT_EQ(mesh.triangleCount(), trimmed.triangleCount() + result.triangles_added);
    // Inserted points lie in the voids (their rims reach about one spacing out).
    for (std::size_t v = trimmed.vertexCount(); v < mesh.vertexCount(); ++v) {
      bool in_void = false;
      for (const test::Disc& d : terrain.voids)
        in_void =
            in_void || std::hypot(mesh.xy[v].x - d.cx, mesh.xy[v].y - d.cy) < d.r + 1;
      EXPECT_TRUE(in_void) << v;
    }

    // A filled hole leaves no loop behind: one outer loop and the open void.
    BoundaryLoops after;
    ASSERT_TRUE(findBoundaryLoops(mesh, after).ok());
    EXPECT_EQ(after.holeCount(), 1u);
    EXPECT_EQ(after.componentCount(), 1u);
    for (const test::Disc& d : terrain.voids) {
      const double coverage = test::discCoverage(mesh, d, 0.1);
      if (M_PI * d.r * d.r <= HOLE_LIMIT)
        EXPECT_GE(coverage, 0.99) << "void of radius " << d.r;
      else
        EXPECT_LE(coverage, 0.01) << "void of radius " << d.r;
      if (m == 0)
        std::printf("[ figures  ] void r = %.0f: covered %.2f%% after filling\n", d.r,
                    100 * coverage);
    }
    vertex_error[m] = test::vertexZError(mesh, result.inserted);
    patch_error[m] = test::patchZError(mesh, trimmed.triangleCount(), 0.1);
    std::printf("[ figures  ] %s: %zu holes filled, %zu points inserted; z error at "
                "inserted points RMS %.4f max %.4f; over the patches RMS %.4f max "
                "%.4f\n",
                m == 0 ? "thin-plate spline" : "flat rim mean", result.holes_filled,
                result.points_inserted, vertex_error[m].rms, vertex_error[m].max,
                patch_error[m].rms, patch_error[m].max);
  }
  EXPECT_LT(vertex_error[0].rms, 0.5 * vertex_error[1].rms);
  EXPECT_LT(patch_error[0].max, patch_error[1].max);
}

TEST(FillHoles, AutomaticLimitFillsSmallVoidsAndIsDeterministic)
{
  const test::SyntheticTerrain terrain = test::makeSyntheticTerrain(3);
  const TriangleMesh trimmed = trimmedTerrain(terrain);
  TriangleMesh a = trimmed, b = trimmed;
  FillResult ra, rb;
  ASSERT_TRUE(fillHoles(a, FillOptions{}, ra).ok());
  ASSERT_TRUE(fillHoles(b, FillOptions{}, rb).ok());
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.z, b.z);
  test::expectValidSurfaceMesh(a);
  // Automatic limit: 1000 spacing^2 with spacing ~0.7: radius-10 voids filled,
  // radius 25 left open.
  EXPECT_GT(ra.max_hole_area, 314.0);
  EXPECT_LT(ra.max_hole_area, 1963.0);
  EXPECT_EQ(ra.holes_left_open, 1u);
  // Filling again finds only the open hole.
  FillResult again;
  ASSERT_TRUE(fillHoles(a, FillOptions{}, again).ok());
  EXPECT_EQ(again.holes_found, 1u);
  EXPECT_EQ(again.points_inserted, 0u);
}

// The tiled path fills holes on a part of the mesh, with other ids: the inserted
// points (x, y and the spline's z) and the patches must depend on positions only.
TEST(FillHoles, DependsOnPositionsNotOnIds)
{
  for (const std::uint32_t seed : {3u, 8u}) {
    const test::SyntheticTerrain terrain = test::makeSyntheticTerrain(seed);
    TriangleMesh a = trimmedTerrain(terrain);
    TriangleMesh b = test::shuffledIds(a, seed);
    FillResult ra, rb;
    ASSERT_TRUE(fillHoles(a, FillOptions{}, ra).ok());
    ASSERT_TRUE(fillHoles(b, FillOptions{}, rb).ok());
    ASSERT_GT(ra.holes_filled, 2u);
    EXPECT_EQ(ra.holes_filled, rb.holes_filled);
    EXPECT_EQ(ra.points_inserted, rb.points_inserted);
    EXPECT_EQ(test::verticesByPosition(a), test::verticesByPosition(b));
    EXPECT_EQ(test::trianglesByPosition(a), test::trianglesByPosition(b));
  }
}

TEST(FillHoles, HoleAroundAnIslandOrThroughAPinchIsLeftAlone)
{
  // An annulus of squares with a separate square in its middle: the annulus hole
  // encloses another piece, so filling it would overlap that piece.
  TriangleMesh mesh;
  const int side = 7;
  for (int j = 0; j <= side; ++j)
    for (int i = 0; i <= side; ++i) {
      mesh.xy.push_back({static_cast<double>(i), static_cast<double>(j)});
      mesh.z.push_back(0.0);
    }
  auto id = [](int i, int j) { return static_cast<VertexId>(j * (side + 1) + i); };
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      const bool ring = i == 0 || j == 0 || i == side - 1 || j == side - 1;
      const bool island = i == 3 && j == 3;
      if (!ring && !island)
        continue;
      mesh.triangles.insert(mesh.triangles.end(),
                            {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.insert(mesh.triangles.end(),
                            {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  ASSERT_TRUE(mesh.rebuildHalfedges());
  const TriangleMesh copy = mesh;
  FillResult result;
  FillOptions options;
  options.max_hole_area = 100.0;
  ASSERT_TRUE(fillHoles(mesh, options, result).ok());
  EXPECT_EQ(result.holes_found, 1u);
  EXPECT_EQ(result.holes_skipped, 1u);
  EXPECT_EQ(result.holes_filled, 0u);
  EXPECT_EQ(mesh.triangles, copy.triangles);

  // Without the island the same hole is filled with lattice points.
  TriangleMesh annulus;
  annulus.xy = copy.xy;
  annulus.z = copy.z;
  for (std::size_t t = 0; t < copy.triangleCount(); ++t) {
    const Point2& p = copy.xy[copy.triangles[3 * t]];
    if (!(p.x == 3 && p.y == 3))
      annulus.triangles.insert(annulus.triangles.end(),
                               copy.triangles.begin() + static_cast<long>(3 * t),
                               copy.triangles.begin() + static_cast<long>(3 * t + 3));
  }
  ASSERT_TRUE(annulus.rebuildHalfedges());
  ASSERT_TRUE(fillHoles(annulus, options, result).ok());
  EXPECT_EQ(result.holes_filled, 1u);
  EXPECT_GT(result.points_inserted, 5u);
  test::expectValidSurfaceMesh(annulus);
  EXPECT_NEAR(twiceArea(annulus), 2.0 * 49.0, 1e-9);
}

TEST(FillHoles, InvalidOptionsAreRejected)
{
  TriangleMesh mesh;
  FillResult result;
  FillOptions options;
  options.max_hole_area = -1;
  EXPECT_EQ(fillHoles(mesh, options, result).code, StatusCode::INVALID_PARAMETER);
  options = FillOptions{};
  options.point_spacing = std::nan("");
  Status status = fillHoles(mesh, options, result);
  EXPECT_EQ(status.code, StatusCode::INVALID_PARAMETER);
  EXPECT_NE(status.message.find("point_spacing"), std::string::npos);
  options = FillOptions{};
  options.rim_clearance = 0.0;
  EXPECT_EQ(fillHoles(mesh, options, result).code, StatusCode::INVALID_PARAMETER);
  options = FillOptions{};
  options.rim_rings = 9;
  status = fillHoles(mesh, options, result);
  EXPECT_EQ(status.code, StatusCode::INVALID_PARAMETER);
  EXPECT_NE(status.message.find("rim_rings = 9"), std::string::npos);
}

TEST(ReconstructSurface, TrimThenFillOnTheSyntheticTerrain)
{
  const test::SyntheticTerrain terrain = test::makeSyntheticTerrain(7);
  const test::PipelineRun run = test::runPipeline(terrain.xyz);
  ASSERT_TRUE(run.status.ok());
  TriangleMesh mesh = run.result.mesh;
  ReconstructionOptions options;
  options.fill_options.max_hole_area = HOLE_LIMIT;
  ReconstructionDiagnostics diagnostics;
  ASSERT_TRUE(reconstructSurface(mesh, options, diagnostics).ok());
  test::expectValidSurfaceMesh(mesh);
  EXPECT_EQ(diagnostics.triangles_in, run.result.mesh.triangleCount());
  EXPECT_EQ(diagnostics.triangles_out, mesh.triangleCount());
  EXPECT_GT(diagnostics.trim.triangles_removed, 0u);
  EXPECT_GE(diagnostics.fill.holes_filled, 3u);
  // Everything but the open void and the notch is covered; nothing outside.
  test::SyntheticTerrain filled_footprint = terrain;
  filled_footprint.voids = {terrain.voids.back()};
  const test::CoverageFigures f = test::measureCoverage(mesh, filled_footprint, 0.25);
  EXPECT_GE(f.coverage(), 0.99);
  EXPECT_LE(f.spillRatio(), 0.005);

  ReconstructionOptions off;
  off.trim = off.fill = false;
  TriangleMesh untouched = run.result.mesh;
  ASSERT_TRUE(reconstructSurface(untouched, off, diagnostics).ok());
  EXPECT_EQ(untouched.triangles, run.result.mesh.triangles);
  EXPECT_EQ(diagnostics.fill.inserted.size(), untouched.vertexCount());

  ReconstructionOptions bad;
  bad.trim_options.trim_factor = 0.5;
  EXPECT_EQ(reconstructSurface(mesh, bad, diagnostics).code,
            StatusCode::INVALID_PARAMETER);
  bad.trim = false; // a disabled pass is not validated
  EXPECT_TRUE(reconstructSurface(untouched, bad, diagnostics).ok());
  TriangleMesh broken = run.result.mesh;
  broken.triangles[0] = static_cast<VertexId>(broken.vertexCount());
  EXPECT_EQ(reconstructSurface(broken, ReconstructionOptions{}, diagnostics).code,
            StatusCode::INVALID_PARAMETER);
}

TEST(ReconstructSurface, CornerNotAVertexIdIsRejectedBeforeAnyChange)
{
  // The trim checks the corners in its rows' count pass (reconstructSurface has no
  // pass of its own then): the same error as the pass without the trim, naming the
  // first bad corner, with the mesh and the diagnostics untouched.
  const test::SyntheticTerrain terrain = test::makeSyntheticTerrain(7);
  const test::PipelineRun run = test::runPipeline(terrain.xyz);
  ASSERT_TRUE(run.status.ok());
  const std::size_t n = run.result.mesh.vertexCount();
  const std::size_t corners = run.result.mesh.triangles.size();
  // (index, value) pairs written into the corners; the first bad one in index order.
  const std::vector<std::vector<std::pair<std::size_t, std::size_t>>> cases = {
      {{0, n}},
      {{corners - 1, n + 5}},
      {{corners / 2 + 2, n + 9}, {corners / 2, n + 1}},
      {{corners / 3 + 1, 4294967295u}, {corners - 2, n}}};
  for (const auto& writes : cases) {
    TriangleMesh broken = run.result.mesh;
    std::size_t first = corners;
    for (const auto& [index, value] : writes) {
      broken.triangles[index] = static_cast<VertexId>(value);
      first = std::min(first, index);
    }
    const std::string expected =
        "triangle corner " + std::to_string(broken.triangles[first]) +
        " is not a vertex id (" + std::to_string(n) + " vertices)";
    for (const bool trim : {true, false})
      for (const bool fill : {true, false}) {
        ReconstructionOptions options;
        options.trim = trim;
        options.fill = fill;
        TriangleMesh mesh = broken;
        ReconstructionDiagnostics diagnostics;
        diagnostics.triangles_in = 7;
        const Status status = reconstructSurface(mesh, options, diagnostics);
        EXPECT_EQ(status.code, StatusCode::INVALID_PARAMETER);
        EXPECT_EQ(status.message, expected);
        EXPECT_EQ(mesh.triangles, broken.triangles);
        EXPECT_EQ(mesh.halfedges, broken.halfedges);
        EXPECT_EQ(diagnostics.triangles_in, 0u);
        EXPECT_EQ(diagnostics.seconds_trim, 0.0);
      }
    TriangleMesh mesh = broken;
    TrimResult result;
    const Status status = trimOutwardTriangles(mesh, TrimOptions{}, result);
    EXPECT_EQ(status.code, StatusCode::INVALID_PARAMETER);
    EXPECT_EQ(status.message, expected);
    EXPECT_EQ(mesh.triangles, broken.triangles);
  }
}

TEST(ReconstructSurface, PinchNearAHoleTakesTheRowsOfTheWholeMesh)
{
  // With the trim's spacing the fill walks each vertex's fan for its neighbours; a
  // vertex with two fans (here a corner of an annulus touched by a triangle that
  // shares only that corner), two rings from the hole's rim, is not walked whole:
  // the fill falls back to the rows of the whole mesh and equals fillHoles alone.
  TriangleMesh mesh;
  const int side = 7;
  const auto extra = static_cast<VertexId>((side + 1) * (side + 1));
  for (int j = 0; j <= side; ++j)
    for (int i = 0; i <= side; ++i) {
      const double x = i, y = j;
      mesh.xy.push_back({x, y});
      mesh.z.push_back(0.1 * x * x + 0.2 * y + 0.05 * x * y);
    }
  auto id = [](int i, int j) { return static_cast<VertexId>(j * (side + 1) + i); };
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      if (!(i == 0 || j == 0 || i == side - 1 || j == side - 1))
        continue;
      mesh.triangles.insert(mesh.triangles.end(),
                            {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.insert(mesh.triangles.end(),
                            {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  mesh.xy.push_back({-1.0, -1.0});
  mesh.xy.push_back({0.0, -1.0});
  mesh.z.insert(mesh.z.end(), {7.0, 9.0});
  // First: the walk starts from the last halfedge leaving a vertex, in the annulus.
  mesh.triangles.insert(mesh.triangles.begin(), {id(0, 0), extra, extra + 1});
  ASSERT_TRUE(mesh.rebuildHalfedges());

  ReconstructionOptions options;
  options.fill_options.max_hole_area = 100.0;
  TriangleMesh together = mesh;
  ReconstructionDiagnostics diagnostics;
  ASSERT_TRUE(reconstructSurface(together, options, diagnostics).ok());
  EXPECT_EQ(diagnostics.trim.triangles_removed, 0u);
  EXPECT_EQ(diagnostics.fill.holes_filled, 1u);

  TriangleMesh apart = mesh;
  FillResult result;
  ASSERT_TRUE(fillHoles(apart, options.fill_options, result).ok());
  EXPECT_EQ(together.triangles, apart.triangles);
  EXPECT_EQ(together.z, apart.z);
  EXPECT_EQ(together.xy.size(), apart.xy.size());
}

TEST(ReconstructSurface, EqualsTrimThenFillCalledApart)
{
  // reconstructSurface hands the trim's spacing to the fill (measured again only at
  // the corners of removed triangles); the passes called apart measure the whole
  // trimmed mesh: the same mesh, bit for bit, with the automatic hole limit (the
  // global median) and a fixed one (the rims' local spacing alone).
  std::vector<std::vector<double>> inputs;
  for (const std::uint64_t seed : {7u, 8u, 9u})
    inputs.push_back(test::makeSyntheticTerrain(seed).xyz);
  inputs.push_back(test::generatePoints(test::Distribution::BIG_VOIDS, 20000, 3));
  inputs.push_back(test::generatePoints(test::Distribution::CLUSTERED, 20000, 4));
  std::size_t filled = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i)
    for (const double limit : {0.0, HOLE_LIMIT}) {
      SCOPED_TRACE(std::to_string(i) + " limit " + std::to_string(limit));
      const test::PipelineRun run = test::runPipeline(inputs[i]);
      ASSERT_TRUE(run.status.ok()) << run.status.toString();
      ReconstructionOptions options;
      options.fill_options.max_hole_area = limit;
      TriangleMesh together = run.result.mesh;
      ReconstructionDiagnostics diagnostics;
      ASSERT_TRUE(reconstructSurface(together, options, diagnostics).ok());

      TriangleMesh apart = run.result.mesh;
      TrimResult trimmed;
      ASSERT_TRUE(trimOutwardTriangles(apart, options.trim_options, trimmed).ok());
      FillResult result;
      ASSERT_TRUE(fillHoles(apart, options.fill_options, result).ok());
      EXPECT_EQ(together.triangles, apart.triangles);
      EXPECT_EQ(together.halfedges, apart.halfedges);
      EXPECT_EQ(together.z, apart.z);
      ASSERT_EQ(together.xy.size(), apart.xy.size());
      for (std::size_t v = 0; v < apart.xy.size(); ++v)
        ASSERT_TRUE(together.xy[v].x == apart.xy[v].x &&
                    together.xy[v].y == apart.xy[v].y)
            << "vertex " << v;
      EXPECT_EQ(diagnostics.fill.inserted, result.inserted);
      EXPECT_EQ(diagnostics.fill.max_hole_area, result.max_hole_area);
      EXPECT_EQ(diagnostics.fill.holes_found, result.holes_found);
      EXPECT_EQ(diagnostics.trim.spacing, trimmed.spacing);
      filled += result.holes_filled;
    }
  EXPECT_GT(filled, 10u);
}

} // namespace
} // namespace pcl_vts
