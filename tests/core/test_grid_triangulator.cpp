// Region growing in strips: the triangle arrays are identical for every thread count
// (the strips, not the threads, fix the output; with the trim and fill too), every
// strip width gives the same triangulation, and each run is a valid Delaunay
// triangulation of the hull.
#include "support/generators.h"

#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <utility>

namespace pcl_vts {
namespace {

VtsResult triangulate(const std::vector<double>& xyz, unsigned threads,
                      std::uint32_t strip_columns = 0, bool cache_blocks = true)
{
  VtsOptions options;
  options.threads = threads;
  options.strip_columns = strip_columns;
  options.cache_blocks = cache_blocks;
  VtsResult result;
  const Status status = runVtsPipeline(xyz.data(), xyz.size() / 3, options, result);
  EXPECT_TRUE(status.ok()) << status.toString();
  return result;
}

TEST(GridTriangulator, OutputIsIdenticalForEveryThreadCount)
{
  using test::Distribution;
  for (const Distribution d :
       {Distribution::JITTERED_GRID, Distribution::EXACT_GRID, Distribution::CLUSTERED,
        Distribution::BIG_VOIDS, Distribution::FLOAT_ROUNDED}) {
    SCOPED_TRACE(test::distributionName(d));
    const std::vector<double> xyz = test::generatePoints(d, 30000, 17);
    const VtsResult one = triangulate(xyz, 1);
    std::string why;
    ASSERT_TRUE(isDelaunay(one.mesh, &why)) << why;
    for (const unsigned threads : {2u, 3u, 8u, 0u}) {
      SCOPED_TRACE(threads);
      const VtsResult many = triangulate(xyz, threads);
      EXPECT_EQ(many.mesh.triangles, one.mesh.triangles);
      EXPECT_EQ(many.mesh.halfedges, one.mesh.halfedges);
      EXPECT_EQ(many.source_index, one.source_index);
      EXPECT_EQ(many.diagnostics.triangles, one.diagnostics.triangles);
    }
  }
}

TEST(GridTriangulator, LargeInputIsIdenticalForEveryThreadCount)
{
  // Above 2^17 points the grid phase (gather, per-cell sort, index maps) runs on the
  // threads too; random input order makes every gather a scatter.
  const std::vector<double> xyz =
      test::generatePoints(test::Distribution::UNIFORM, 300000, 23);
  const VtsResult one = triangulate(xyz, 1);
  for (const unsigned threads : {2u, 3u}) {
    SCOPED_TRACE(threads);
    const VtsResult many = triangulate(xyz, threads);
    EXPECT_EQ(many.mesh.triangles, one.mesh.triangles);
    EXPECT_EQ(many.mesh.halfedges, one.mesh.halfedges);
    EXPECT_EQ(many.mesh.xy, one.mesh.xy);
    EXPECT_EQ(many.mesh.z, one.mesh.z);
    EXPECT_EQ(many.source_index, one.source_index);
    EXPECT_EQ(many.input_to_vertex, one.input_to_vertex);
  }
}

/// A jittered lattice side x side with round holes (radius 3 to 9, filled, and 15,
/// left open) and a square notch cut from one corner (outward triangles across it).
std::vector<double> holesAndNotch(std::size_t side)
{
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  const auto s = static_cast<double>(side);
  std::vector<double> xyz;
  for (std::size_t j = 0; j < side; ++j)
    for (std::size_t i = 0; i < side; ++i) {
      const auto x = static_cast<double>(i), y = static_cast<double>(j);
      if (x > 0.7 * s && y > 0.7 * s)
        continue; // the notch
      const double cx = std::fmod(x, 60.0) - 30.0, cy = std::fmod(y, 60.0) - 30.0;
      const double r =
          std::fmod(std::floor(x / 60.0) + 2.0 * std::floor(y / 60.0), 5.0) == 4.0
              ? 15.0
              : 3.0 + 1.5 * std::fmod(std::floor(x / 60.0) + std::floor(y / 60.0), 5.0);
      if (cx * cx + cy * cy < r * r)
        continue; // a hole
      const double px = x + jitter(rng), py = y + jitter(rng);
      xyz.insert(xyz.end(), {px, py, 5.0 * std::sin(0.05 * px) * std::cos(0.07 * py)});
    }
  return xyz;
}

TEST(GridTriangulator, DefaultPipelineWithTrimAndFillIsIdenticalForEveryThreadCount)
{
  // pcd_to_mesh's pipeline: the trim and the fill run on VtsOptions::threads too
  // (spacing, classification, compaction, checks); 3e5 points give every loop
  // several ranges.
  const std::vector<double> xyz = holesAndNotch(560);
  auto run = [&](unsigned threads) {
    VtsOptions options;
    options.threads = threads;
    options.reconstruction = ReconstructionOptions{}; // trim and fill, checked
    VtsResult result;
    const Status status = runVtsPipeline(xyz.data(), xyz.size() / 3, options, result);
    EXPECT_TRUE(status.ok()) << status.toString();
    return result;
  };
  const VtsResult one = run(1);
  const ReconstructionDiagnostics& post = one.reconstruction;
  EXPECT_GT(post.trim.triangles_removed, 1000u);
  EXPECT_GT(post.fill.holes_filled, 20u);
  EXPECT_GT(post.fill.holes_left_open, 0u);
  EXPECT_GT(post.fill.points_inserted, 1000u);
  std::string why;
  EXPECT_TRUE(isValidSurfaceMesh(one.mesh, &why)) << why;
  for (const unsigned threads : {2u, 3u, 8u, 0u}) {
    SCOPED_TRACE(threads);
    const VtsResult many = run(threads);
    EXPECT_EQ(many.mesh.triangles, one.mesh.triangles);
    EXPECT_EQ(many.mesh.halfedges, one.mesh.halfedges);
    EXPECT_EQ(many.mesh.xy, one.mesh.xy);
    EXPECT_EQ(many.mesh.z, one.mesh.z);
    EXPECT_EQ(many.source_index, one.source_index);
    EXPECT_EQ(many.reconstruction.fill.inserted, post.fill.inserted);
    EXPECT_EQ(many.reconstruction.trim.triangles_removed, post.trim.triangles_removed);
    EXPECT_EQ(many.reconstruction.trim.kept_to_stay_manifold,
              post.trim.kept_to_stay_manifold);
    EXPECT_EQ(many.reconstruction.trim.vertices_lost, post.trim.vertices_lost);
    EXPECT_EQ(many.reconstruction.trim.spacing, post.trim.spacing);
    EXPECT_EQ(many.reconstruction.fill.holes_filled, post.fill.holes_filled);
  }
}

TEST(GridTriangulator, ChecksOnThreadsGiveTheSameVerdictAndMessage)
{
  VtsResult result;
  const std::vector<double> xyz =
      test::generatePoints(test::Distribution::JITTERED_GRID, 200000, 3);
  ASSERT_TRUE(runVtsPipeline(xyz.data(), xyz.size() / 3, VtsOptions{}, result).ok());
  for (const unsigned threads : {1u, 3u, 8u})
    EXPECT_TRUE(isValidSurfaceMesh(result.mesh, nullptr, threads));
  // Two flipped triangles far apart: every thread count names the first one.
  TriangleMesh flipped = result.mesh;
  for (const std::size_t t : {flipped.triangleCount() - 5, flipped.triangleCount() / 3})
    std::swap(flipped.triangles[3 * t + 1], flipped.triangles[3 * t + 2]);
  flipped.rebuildHalfedges();
  // Twins broken at two places, far apart.
  TriangleMesh twins = result.mesh;
  for (const std::size_t e : {twins.halfedges.size() - 7, twins.halfedges.size() / 4})
    twins.halfedges[e] = INVALID_ID - 1;
  std::string ccw1, valid1, twins1;
  EXPECT_FALSE(allTrianglesCcw(flipped, &ccw1, 1));
  EXPECT_FALSE(isValidSurfaceMesh(flipped, &valid1, 1));
  EXPECT_FALSE(halfedgesConsistent(twins, &twins1, 1));
  for (const unsigned threads : {2u, 3u, 8u}) {
    SCOPED_TRACE(threads);
    std::string ccw, valid, twin;
    EXPECT_FALSE(allTrianglesCcw(flipped, &ccw, threads));
    EXPECT_EQ(ccw, ccw1);
    EXPECT_FALSE(isValidSurfaceMesh(flipped, &valid, threads));
    EXPECT_EQ(valid, valid1);
    EXPECT_FALSE(halfedgesConsistent(twins, &twin, threads));
    EXPECT_EQ(twin, twins1);
  }
}

/// Triangles as vertex triples rotated to start at their smallest id, sorted: the
/// triangulation without its order.
std::vector<std::array<VertexId, 3>> triangleSet(const TriangleMesh& mesh)
{
  std::vector<std::array<VertexId, 3>> set;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    std::array<VertexId, 3> v{mesh.triangles[3 * t], mesh.triangles[3 * t + 1],
                              mesh.triangles[3 * t + 2]};
    std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end());
    set.push_back(v);
  }
  std::sort(set.begin(), set.end());
  return set;
}

TEST(GridTriangulator, EveryStripWidthGivesTheSameTriangulation)
{
  // Strips one column wide put nearly every triangle on a strip border: the seeds,
  // ownership and border twins are all exercised. One strip wider than the grid is
  // the plain region growing.
  using test::Distribution;
  for (const Distribution d :
       {Distribution::UNIFORM, Distribution::JITTERED_GRID, Distribution::EXACT_GRID,
        Distribution::CLUSTERED, Distribution::BIG_VOIDS, Distribution::CIRCLE,
        Distribution::CONCENTRIC_RINGS, Distribution::THIN_STRIP,
        Distribution::ANISOTROPIC, Distribution::ROTATED_LATTICE,
        Distribution::FLOAT_ROUNDED}) {
    SCOPED_TRACE(test::distributionName(d));
    const std::vector<double> xyz = test::generatePoints(d, 4000, 5);
    const VtsResult whole = triangulate(xyz, 1, 1u << 30);
    std::string why;
    ASSERT_TRUE(isDelaunay(whole.mesh, &why)) << why;
    const auto expected = triangleSet(whole.mesh);
    for (const std::uint32_t columns : {1u, 2u, 8u, 0u}) {
      SCOPED_TRACE(columns);
      const VtsResult strips = triangulate(xyz, 1, columns);
      EXPECT_TRUE(isDelaunay(strips.mesh, &why)) << why;
      EXPECT_EQ(triangleSet(strips.mesh), expected);
      const VtsResult parallel = triangulate(xyz, 3, columns);
      EXPECT_EQ(parallel.mesh.triangles, strips.mesh.triangles);
      EXPECT_EQ(parallel.mesh.halfedges, strips.mesh.halfedges);
    }
  }
}

TEST(GridTriangulator, StripBordersCostFewExtraSearches)
{
  // Every triangle needs one search; triangles straddling a strip border are grown by
  // both strips, and each seed costs two searches per candidate edge.
  const std::vector<double> xyz =
      test::generatePoints(test::Distribution::UNIFORM, 20000, 3);
  const VtsResult r = triangulate(xyz, 2, 0, false); // the search alone
  const Diagnostics& d = r.diagnostics;
  const std::size_t searches = d.local_searches + d.widened_searches;
  EXPECT_GE(searches, d.triangles);
  EXPECT_LE(searches, d.triangles + d.triangles / 8);
}

TEST(GridTriangulator, StripWidthMustBeAPowerOfTwo)
{
  VtsOptions options;
  options.strip_columns = 3;
  EXPECT_EQ(validateOptions(options).code, StatusCode::INVALID_PARAMETER);
  options.strip_columns = 64;
  EXPECT_TRUE(validateOptions(options).ok());
}

} // namespace
} // namespace pcl_vts
