// The pipeline on real DEMs from ../shared/data (ESRI ASCII grids, cell centres as
// points, NODATA skipped: concave outlines, UTM offsets, a non-dyadic cell size).
// Grids are full of cocircular ties, so equality is checked against the mirrored CGAL
// oracle (same tie-break) on top of every invariant. Skipped when the data is absent.
#include "support/asc_reader.h"
#include "support/pipeline_checks.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

namespace pcl_vts {
namespace {

struct DemCase {
  const char* path; ///< relative to PCL_VTS_SHARED_DATA_DIR
  std::size_t valid_cells;
};

// Valid cell counts from ../shared/data/README.md.
const DemCase DEMS[] = {
    {"dem/landlab/west_bijou_gully.asc", 1088},
    {"dem/landlab/hugo_site.asc", 2152},
    {"dem/landlab/zSW3.asc", 100448},
    {"dem/topotoolbox/exampleDEM_orkhon.asc", 17640},
};

class RealDem : public ::testing::TestWithParam<DemCase> {};

TEST_P(RealDem, TriangulationIsDelaunayAndEqualToCgal)
{
  const std::string path = std::string(PCL_VTS_SHARED_DATA_DIR) + "/" + GetParam().path;
  SCOPED_TRACE(path);
  if (!std::ifstream(path).good())
    GTEST_SKIP() << "shared data file not found: " << path;
  test::AsciiGrid grid;
  std::string error;
  ASSERT_TRUE(test::readAsciiGrid(path, grid, &error)) << error;
  ASSERT_EQ(grid.xyz.size() / 3, GetParam().valid_cells);
  EXPECT_EQ(grid.xyz.size() / 3 + grid.nodata_cells, grid.ncols * grid.nrows);

  const test::PipelineRun run = test::runPipeline(grid.xyz);
  ASSERT_TRUE(run.status.ok()) << run.status.toString();
  const test::ValidationSummary summary = test::expectValidTriangulation(grid.xyz, run);
  EXPECT_EQ(summary.distinct_points, GetParam().valid_cells); // cell centres differ
  EXPECT_EQ(run.result.diagnostics.duplicates_merged, 0u);
}

INSTANTIATE_TEST_SUITE_P(SharedData, RealDem, ::testing::ValuesIn(DEMS),
                         [](const ::testing::TestParamInfo<DemCase>& param_info) {
                           std::string name = param_info.param.path;
                           name = name.substr(name.rfind('/') + 1);
                           name = name.substr(0, name.find('.'));
                           return name;
                         });

TEST(AsciiGridReader, CornerAndCentreConventionsAndNodata)
{
  const std::string path = ::testing::TempDir() + "pcl_vts_reader_test.asc";
  {
    std::ofstream out(path);
    out << "NCOLS 3\nnrows 2\nxllcenter 100.5\nYLLCORNER 200\ncellsize 1\n"
           "NODATA_value -9999\n1 2 3\n4 -9999 6\n";
  }
  test::AsciiGrid grid;
  std::string error;
  ASSERT_TRUE(test::readAsciiGrid(path, grid, &error)) << error;
  EXPECT_EQ(grid.ncols, 3u);
  EXPECT_EQ(grid.nrows, 2u);
  EXPECT_EQ(grid.nodata_cells, 1u);
  // Top row first; xllcenter 100.5 = corner 100; row 0 is the upper one (y = 201.5).
  const std::vector<double> expected = {100.5, 201.5, 1,     101.5, 201.5,
                                        2,     102.5, 201.5, 3,     100.5,
                                        200.5, 4,     102.5, 200.5, 6};
  EXPECT_EQ(grid.xyz, expected);
  EXPECT_FALSE(test::readAsciiGrid(path + ".missing", grid, &error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
  {
    std::ofstream out(path);
    out << "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4\n";
  }
  EXPECT_FALSE(test::readAsciiGrid(path, grid, &error));
  EXPECT_NE(error.find("expected 6 values, got 4"), std::string::npos) << error;
}

} // namespace
} // namespace pcl_vts
