// Cache blocks (VtsOptions::cache_blocks, docs/scaling.md): the triangles proven final
// by block-local Bowyer-Watson triangulations seed the strips, the search grows the
// rest. The triangulation must be the one of the plain path, checked against CGAL
// (our tie-break included) on every generator, at two strip widths, with the arrays
// identical for 1 and 3 threads; and the blocks must do the work (few searches left).
#include "support/generators.h"
#include "support/pipeline_checks.h"

#include <pcl_vts/core/vts_pipeline.h>

#include <gtest/gtest.h>

#include <vector>

namespace pcl_vts {
namespace {

using test::Distribution;
using test::PipelineRun;
using test::runPipeline;

class CacheBlocks : public ::testing::TestWithParam<Distribution> {};

TEST_P(CacheBlocks, SameTriangulationAsTheSearchAlone)
{
  // 12000 points: about 6000 cells, so several 32 x 32 blocks and their rings.
  const std::vector<double> xyz = test::generatePoints(GetParam(), 12000, 7);
  const StatusCode expected = test::expectedStatusCode(xyz);
  for (const std::uint32_t columns : {0u, 4u}) {
    SCOPED_TRACE("strip_columns=" + std::to_string(columns));
    VtsOptions options;
    options.lattice = false;
    options.strip_columns = columns;
    options.cache_blocks = true;
    const PipelineRun blocks = runPipeline(xyz, options);
    ASSERT_EQ(blocks.status.code, expected) << blocks.status.toString();
    if (expected != StatusCode::OK)
      return;
    test::expectValidTriangulation(xyz, blocks, options);
    options.threads = 3;
    const PipelineRun three = runPipeline(xyz, options);
    ASSERT_TRUE(three.status.ok()) << three.status.toString();
    EXPECT_EQ(three.result.mesh.triangles, blocks.result.mesh.triangles);
    EXPECT_EQ(three.result.mesh.halfedges, blocks.result.mesh.halfedges);
    options.threads = 1;
    options.cache_blocks = false;
    const PipelineRun plain = runPipeline(xyz, options);
    ASSERT_TRUE(plain.status.ok()) << plain.status.toString();
    EXPECT_EQ(test::trianglesByPosition(blocks.result.mesh),
              test::trianglesByPosition(plain.result.mesh));
  }
}

INSTANTIATE_TEST_SUITE_P(AllDistributions, CacheBlocks,
                         ::testing::ValuesIn(test::allDistributions()),
                         [](const ::testing::TestParamInfo<Distribution>& param) {
                           return test::distributionName(param.param);
                         });

TEST(CacheBlocksWork, FewSearchesAreLeft)
{
  // Jittered terrain: the blocks prove all but the triangles near block corners and
  // the hull, so the search runs for a small fraction of what it runs alone.
  const std::vector<double> xyz =
      test::generatePoints(Distribution::JITTERED_GRID, 20000, 3);
  VtsOptions options;
  options.lattice = false;
  options.cache_blocks = false;
  const PipelineRun plain = runPipeline(xyz, options);
  options.cache_blocks = true;
  const PipelineRun blocks = runPipeline(xyz, options);
  ASSERT_TRUE(plain.status.ok() && blocks.status.ok());
  const auto searches = [](const PipelineRun& run) {
    return run.result.diagnostics.local_searches +
           run.result.diagnostics.widened_searches;
  };
  EXPECT_GT(searches(plain), 20000u);
  EXPECT_LT(searches(blocks) * 10, searches(plain));
  EXPECT_EQ(blocks.result.mesh.triangleCount(), plain.result.mesh.triangleCount());
}

} // namespace
} // namespace pcl_vts
