// Region growing with parallel searches: the triangle arrays are identical for every
// thread count (the batch order, not the threads, fixes the output), and each run is
// a valid Delaunay triangulation of the hull.
#include "support/generators.h"

#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <gtest/gtest.h>

namespace pcl_vts {
namespace {

VtsResult triangulate(const std::vector<double>& xyz, unsigned threads)
{
  VtsOptions options;
  options.threads = threads;
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

TEST(GridTriangulator, NoTriangleIsSearchedTwice)
{
  // Edges of one batch are vertex-disjoint, so every search yields a new triangle:
  // searches = triangles - 1 (the seed triangle comes from the seed hull edge, which
  // is searched once too).
  const std::vector<double> xyz =
      test::generatePoints(test::Distribution::UNIFORM, 20000, 3);
  const VtsResult r = triangulate(xyz, 2);
  const Diagnostics& d = r.diagnostics;
  EXPECT_EQ(d.local_searches + d.widened_searches, d.triangles);
}

} // namespace
} // namespace pcl_vts
