// compare_methods' metrics (tools/compare/mesh_metrics.h and parts) on hand-made meshes
// whose answers are known: zero and constant distances, a non-manifold fan, a flipped
// triangle, an overlapping pair, unused points, area-weighted sample counts, and the
// grid's nearest triangle against brute force.
#include "mesh_metrics.h"
#include "poisson_footprint.h"
#include "surface_samples.h"
#include "triangle_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace pcl_vts {
namespace compare {
namespace {

/// Square [0, side]^2 at height z, cells x cells squares, two CCW triangles each.
CompareMesh squareMesh(double side, int cells, double z)
{
  CompareMesh mesh;
  const double h = side / cells;
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i)
      mesh.xyz.insert(mesh.xyz.end(), {i * h, j * h, z});
  auto id = [&](int i, int j) {
    return static_cast<std::uint32_t>(j * (cells + 1) + i);
  };
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      mesh.triangles.insert(mesh.triangles.end(),
                            {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.insert(mesh.triangles.end(),
                            {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return mesh;
}

/// A (side/step + 1)^2 lattice of points on z = 0, slightly jittered.
PointSet planePoints(double side, double step)
{
  PointSet points;
  std::mt19937_64 engine(3);
  std::uniform_real_distribution<double> jitter(-0.1 * step, 0.1 * step);
  const int n = static_cast<int>(std::lround(side / step));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = std::clamp(i * step + jitter(engine), 0.0, side);
      const double y = std::clamp(j * step + jitter(engine), 0.0, side);
      points.xyz.insert(points.xyz.end(), {x, y, 0.0});
    }
  return points;
}

MeshMetrics metricsOf(const CompareMesh& mesh, const PointSet& points)
{
  const PointReference reference(points, 10, 2);
  MetricsOptions options;
  options.threads = 2;
  return computeMeshMetrics(mesh, reference, options);
}

TEST(MeshMetrics, FlatSquareOnItsPlanePointsHasZeroError)
{
  const CompareMesh mesh = squareMesh(10.0, 10, 0.0);
  const MeshMetrics m = metricsOf(mesh, planePoints(10.0, 0.5));
  EXPECT_EQ(m.samples, 2000u); // 10 per triangle
  EXPECT_LT(m.mesh_to_points.max, 1e-9);
  EXPECT_LT(m.points_to_mesh.max, 1e-9);
  EXPECT_LT(m.hausdorff, 1e-9);
  EXPECT_EQ(m.topology.boundary_edges, 40u);
  EXPECT_EQ(m.topology.non_manifold_edges, 0u);
  EXPECT_EQ(m.topology.flipped, 0u);
  EXPECT_EQ(m.overlap.overlapping_triangles, 0u);
  EXPECT_DOUBLE_EQ(m.overlap.overlap_area, 0.0);
  EXPECT_EQ(m.unused_points, -1); // no sources: not a vertex-based mesh
}

TEST(MeshMetrics, LiftedSquareIsAtTheLiftEverywhereBothWays)
{
  const double d = 0.25;
  const MeshMetrics m = metricsOf(squareMesh(10.0, 10, d), planePoints(10.0, 0.5));
  for (const DistanceStats* s : {&m.mesh_to_points, &m.points_to_mesh}) {
    EXPECT_NEAR(s->mean, d, 1e-9);
    EXPECT_NEAR(s->rms, d, 1e-9);
    EXPECT_NEAR(s->max, d, 1e-9);
  }
  EXPECT_NEAR(m.hausdorff, d, 1e-9);
}

TEST(MeshMetrics, SampleBeyondTheDataGrowsWithTheDistance)
{
  // The mesh reaches 5 units past the points: a sample there is not on the data.
  const MeshMetrics m = metricsOf(squareMesh(15.0, 15, 0.0), planePoints(10.0, 0.5));
  EXPECT_GT(m.mesh_to_points.max, 3.0);
  EXPECT_LT(m.points_to_mesh.max, 1e-9);
}

TEST(SurfaceError, SharedSearchPerTriangleEqualsOneQueryPerSample)
{
  // Small and huge triangles over scattered points: the per-triangle radius search
  // and its fallback must give exactly the per-sample nearest-point answer.
  std::mt19937_64 engine(5);
  std::uniform_real_distribution<double> u(0.0, 50.0), z(-1.0, 1.0);
  PointSet points;
  for (int i = 0; i < 3000; ++i)
    points.xyz.insert(points.xyz.end(), {u(engine), u(engine), z(engine)});
  CompareMesh mesh;
  for (std::uint32_t t = 0; t < 200; ++t) {
    const double size = t % 10 == 0 ? 40.0 : 1.5;
    const double cx = u(engine), cy = u(engine);
    for (int k = 0; k < 3; ++k)
      mesh.xyz.insert(mesh.xyz.end(),
                      {cx + size * z(engine), cy + size * z(engine), 2.0 * z(engine)});
    mesh.triangles.insert(mesh.triangles.end(), {3 * t, 3 * t + 1, 3 * t + 2});
  }
  const PointReference reference(points, 10, 2);
  const SurfaceSamples samples = sampleSurface(mesh, 10.0, 0, 3);
  const DistanceStats fast = meshToPoints(samples, mesh, reference, 2);
  double sum = 0.0, max = 0.0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double d = reference.distance(&samples.xyz[3 * i]);
    sum += d;
    max = std::max(max, d);
  }
  EXPECT_EQ(fast.count, samples.size());
  EXPECT_NEAR(fast.mean, sum / static_cast<double>(samples.size()), 1e-12);
  EXPECT_DOUBLE_EQ(fast.max, max);
}

TEST(MeshTopology, EdgeSharedByThreeTrianglesIsNonManifold)
{
  CompareMesh mesh;
  mesh.xyz = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0.5, 1};
  mesh.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  const TopologyCounts t = countTopology(mesh);
  EXPECT_EQ(t.non_manifold_edges, 1u);
  EXPECT_EQ(t.boundary_edges, 6u);
  ASSERT_EQ(t.non_manifold_edge_list.size(), 2u);
  EXPECT_EQ(t.non_manifold_edge_list[0], 0u);
  EXPECT_EQ(t.non_manifold_edge_list[1], 1u);
}

TEST(MeshTopology, ClockwiseTriangleIsFlipped)
{
  CompareMesh mesh;
  mesh.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  mesh.triangles = {0, 1, 2, 1, 2, 3}; // the second is clockwise seen from +z
  const TopologyCounts t = countTopology(mesh);
  EXPECT_EQ(t.flipped, 1u);
  EXPECT_EQ(t.vertices_used, 4u);
}

TEST(XyOverlap, OverlappingPairIsFoundAndTouchingOnesAreNot)
{
  CompareMesh mesh;
  // 0: unit right triangle; 1: the same shape shifted by (-0.25, -0.25) and lifted
  // (overlap: the triangle with legs 0.5, area 0.125); 2: sharing edge 1-2 of
  // triangle 0 from outside; 3: touching triangle 0 at vertex (0, 1) only.
  mesh.xyz = {0, 0,     0,    1, 0, 0, 0, 1,  0, -0.25, -0.25, 5, 0.75, -0.25,
              5, -0.25, 0.75, 5, 1, 1, 0, -1, 2, 0,     -1,    1, 0};
  mesh.triangles = {0, 1, 2, 3, 4, 5, 1, 6, 2, 2, 7, 8};
  EXPECT_TRUE(xyInteriorsIntersect(mesh, 0, 1));
  EXPECT_FALSE(xyInteriorsIntersect(mesh, 0, 2));
  EXPECT_FALSE(xyInteriorsIntersect(mesh, 0, 3));
  const TriangleGrid grid(mesh, 0, 0, 1, 1);
  const SurfaceSamples samples = sampleSurface(mesh, 20000.0, 0, 5);
  const XyOverlap overlap = measureXyOverlap(mesh, grid, samples, 2);
  EXPECT_EQ(overlap.overlapping_triangles, 2u);
  EXPECT_NEAR(overlap.overlap_area, 0.125, 0.01);
  EXPECT_DOUBLE_EQ(overlap.xy_area, 2.0);
}

TEST(MeshTopology, UnusedPointsCountedAndDuplicatesRepresented)
{
  PointSet points;
  // 0-2 are used; 3 has the XY of 0 (a merged duplicate); 4 is left out.
  points.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 7, 5, 5, 0};
  CompareMesh mesh;
  mesh.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 0};
  mesh.source = {0, 1, 2, 4};
  mesh.triangles = {0, 1, 2};
  EXPECT_EQ(countUnusedPoints(mesh, points), 1);
  mesh.source = {-1, -1, -1, -1};
  EXPECT_EQ(countUnusedPoints(mesh, points), -1);
}

TEST(SurfaceSamples, TenPerTriangleSharedInProportionToArea)
{
  CompareMesh mesh;
  // Areas 8 and 0.5 (3D, one of them tilted out of the plane), 1 degenerate.
  mesh.xyz = {0,  0, 0, 4,  0, 0, 0,  4, 0, 10, 0, 0,
              11, 0, 0, 10, 0, 1, 20, 0, 0, 21, 0, 0};
  mesh.triangles = {0, 1, 2, 3, 4, 5, 6, 7, 6};
  const SurfaceSamples s = sampleSurface(mesh, 10.0, 0, 9);
  ASSERT_EQ(s.size(), 30u);
  EXPECT_DOUBLE_EQ(s.total_area, 8.5);
  std::size_t counts[3] = {0, 0, 0};
  for (std::uint32_t t : s.triangle)
    ++counts[t];
  EXPECT_NEAR(static_cast<double>(counts[0]), 30.0 * 8.0 / 8.5, 1.0);
  EXPECT_NEAR(static_cast<double>(counts[1]), 30.0 * 0.5 / 8.5, 1.0);
  EXPECT_EQ(counts[2], 0u);
  // Every sample lies on its triangle.
  for (std::size_t i = 0; i < s.size(); ++i) {
    const std::uint32_t t = s.triangle[i];
    EXPECT_LT(pointTriangleDistance(&s.xyz[3 * i], &mesh.xyz[3 * mesh.triangles[3 * t]],
                                    &mesh.xyz[3 * mesh.triangles[3 * t + 1]],
                                    &mesh.xyz[3 * mesh.triangles[3 * t + 2]]),
              1e-12);
  }
  EXPECT_EQ(sampleSurface(mesh, 10.0, 7, 9).size(), 7u); // the cap
}

TEST(TriangleGrid, NearestTriangleMatchesBruteForce)
{
  std::mt19937_64 engine(11);
  std::uniform_real_distribution<double> u(0.0, 100.0), small(-3.0, 3.0);
  CompareMesh mesh;
  for (std::uint32_t t = 0; t < 300; ++t) {
    const double cx = u(engine), cy = u(engine), cz = small(engine);
    for (int k = 0; k < 3; ++k)
      mesh.xyz.insert(mesh.xyz.end(),
                      {cx + small(engine), cy + small(engine), cz + small(engine)});
    mesh.triangles.insert(mesh.triangles.end(), {3 * t, 3 * t + 1, 3 * t + 2});
  }
  const TriangleGrid grid(mesh, -20, -20, 120, 120);
  for (int q = 0; q < 500; ++q) {
    const double p[3] = {u(engine) * 1.4 - 20.0, u(engine) * 1.4 - 20.0,
                         small(engine) * 5};
    double brute = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
      brute = std::min(brute,
                       pointTriangleDistance(p, &mesh.xyz[9 * t], &mesh.xyz[9 * t + 3],
                                             &mesh.xyz[9 * t + 6]));
    EXPECT_DOUBLE_EQ(grid.nearestDistance(p), brute) << "query " << q;
  }
}

TEST(TriangleGrid, PointTriangleDistanceRegions)
{
  const double a[3] = {0, 0, 0}, b[3] = {2, 0, 0}, c[3] = {0, 2, 0};
  const double above[3] = {0.5, 0.5, 3}, corner[3] = {-3, -4, 0}, edge[3] = {1, -2, 0};
  EXPECT_DOUBLE_EQ(pointTriangleDistance(above, a, b, c), 3.0);
  EXPECT_DOUBLE_EQ(pointTriangleDistance(corner, a, b, c), 5.0);
  EXPECT_DOUBLE_EQ(pointTriangleDistance(edge, a, b, c), 2.0);
  const double d[3] = {4, 0, 0}; // degenerate: a segment
  EXPECT_DOUBLE_EQ(pointTriangleDistance(above, a, b, d), std::sqrt(0.25 + 9.0));
}

TEST(PoissonFootprint, TrianglesAwayFromTheDataAreCut)
{
  CompareMesh mesh = squareMesh(20.0, 20, 0.0); // data only on [0, 10]^2
  const FootprintTrim trim = trimToFootprint(mesh, planePoints(10.0, 0.5), 0.5, 4.0);
  EXPECT_EQ(trim.triangles_before, 800u);
  EXPECT_LT(trim.triangles_after, 800u);
  EXPECT_GT(trim.triangles_after, 200u);
  EXPECT_NEAR(trim.area_before, 400.0, 1e-9);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
    for (int k = 0; k < 3; ++k)
      EXPECT_LE(mesh.xyz[3 * mesh.triangles[3 * t + k]], 10.0 + 2.0 + 1.0);
}

} // namespace
} // namespace compare
} // namespace pcl_vts
