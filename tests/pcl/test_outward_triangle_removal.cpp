// The PCL post-passes end to end on real LiDAR ground (ISPRS filter test samples,
// float32 UTM): VTSGridTriangulation -> OutwardTriangleRemoval -> HoleFilling with
// default parameters. Checks every invariant of the output PolygonMesh (back through
// the core arrays) and prints the counts quoted in docs/reconstruction.md. Skipped
// when ../shared/data is absent. Also the adapters' error paths.
#include "support/surface_checks.h"

#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/hole_filling.h>
#include <pcl_vts/outward_triangle_removal.h>
#include <pcl_vts/vts_grid_triangulation.h>

#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace {

pcl_vts::TriangleMesh asArrays(const pcl::PolygonMesh& mesh)
{
  pcl_vts::TriangleMesh arrays;
  std::size_t reoriented = 0;
  const pcl_vts::Status status =
      pcl::vts_detail::polygonMeshToArrays(mesh, arrays, &reoriented);
  EXPECT_TRUE(status.ok()) << status.toString();
  EXPECT_EQ(reoriented, 0u); // every pass writes CCW triangles
  return arrays;
}

class IsprsGround : public ::testing::TestWithParam<const char*> {};

TEST_P(IsprsGround, DefaultsTrimAndFillIntoAValidSurface)
{
  const std::string path = std::string(PCL_VTS_SHARED_DATA_DIR) +
                           "/pcd/isprs_filtertest/" + GetParam() + "-utm-ground.pcd";
  if (!std::ifstream(path).good())
    GTEST_SKIP() << "shared data file not found: " << path;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  ASSERT_EQ(pcl::io::loadPCDFile(path, *cloud), 0);

  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  vts.setInputCloud(cloud);
  auto raw = std::make_shared<pcl::PolygonMesh>();
  vts.reconstruct(*raw);
  ASSERT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
  const double hull_area = pcl_vts::twiceArea(asArrays(*raw)) / 2;

  pcl::OutwardTriangleRemoval trim;
  trim.setInputMesh(raw);
  auto trimmed = std::make_shared<pcl::PolygonMesh>();
  trim.process(*trimmed);
  ASSERT_TRUE(trim.getLastStatus().ok()) << trim.getLastStatus().toString();
  const pcl_vts::TriangleMesh trimmed_arrays = asArrays(*trimmed);
  pcl_vts::test::expectValidSurfaceMesh(trimmed_arrays);
  EXPECT_EQ(trimmed->cloud.width * trimmed->cloud.height,
            raw->cloud.width * raw->cloud.height);
  EXPECT_EQ(raw->polygons.size() - trimmed->polygons.size(),
            trim.getResult().triangles_removed);

  pcl::HoleFilling fill;
  fill.setInputMesh(trimmed);
  pcl::PolygonMesh filled;
  fill.process(filled);
  ASSERT_TRUE(fill.getLastStatus().ok()) << fill.getLastStatus().toString();
  const pcl_vts::TriangleMesh filled_arrays = asArrays(filled);
  pcl_vts::test::expectValidSurfaceMesh(filled_arrays);
  const pcl_vts::FillResult& f = fill.getResult();
  EXPECT_EQ(filled.cloud.width, cloud->size() + f.points_inserted);
  EXPECT_EQ(fill.getInsertedFlags().size(), filled.cloud.width);
  EXPECT_EQ(f.holes_found, f.holes_filled + f.holes_left_open + f.holes_skipped);

  const double trimmed_area = pcl_vts::twiceArea(trimmed_arrays) / 2;
  const double filled_area = pcl_vts::twiceArea(filled_arrays) / 2;
  std::printf("[ figures  ] %s ground: %zu points, spacing %.2f m; trim: %zu of %zu "
              "triangles removed, %zu points lost, area %.0f -> %.0f m2 (hull); fill: "
              "%zu holes, %zu filled, %zu open (> %.0f m2), %zu skipped, %zu points "
              "inserted, area -> %.0f m2\n",
              GetParam(), cloud->size(), trim.getResult().spacing,
              trim.getResult().triangles_removed, raw->polygons.size(),
              trim.getResult().vertices_lost, hull_area, trimmed_area, f.holes_found,
              f.holes_filled, f.holes_left_open, f.max_hole_area, f.holes_skipped,
              f.points_inserted, filled_area);
  // Untuned defaults keep the surface: little of the hull goes, few points are lost.
  // samp41 (ground is 29 % of the points, the rest buildings) keeps 38 % of its hull.
  EXPECT_GT(trimmed_area, hull_area / 3);
  EXPECT_LE(trim.getResult().vertices_lost, cloud->size() / 100);
  EXPECT_GE(filled_area, trimmed_area);
}

INSTANTIATE_TEST_SUITE_P(SharedData, IsprsGround,
                         ::testing::Values("samp11", "samp12", "samp21", "samp22",
                                           "samp23", "samp24", "samp31", "samp41",
                                           "samp42", "samp51", "samp52", "samp53",
                                           "samp54", "samp61", "samp71"));

TEST(OutwardTriangleRemoval, ErrorsLeaveNoPolygon)
{
  pcl::OutwardTriangleRemoval trim;
  pcl::PolygonMesh out;
  out.polygons.resize(3);
  trim.process(out);
  EXPECT_EQ(trim.getLastStatus().code, pcl_vts::StatusCode::EMPTY_INPUT);
  EXPECT_TRUE(out.polygons.empty());

  // A quad polygon is not a triangle mesh.
  pcl::PointCloud<pcl::PointXYZ> square;
  square.push_back({0, 0, 0});
  square.push_back({1, 0, 0});
  square.push_back({1, 1, 0});
  square.push_back({0, 1, 0});
  auto quad = std::make_shared<pcl::PolygonMesh>();
  pcl::toPCLPointCloud2(square, quad->cloud);
  quad->polygons.resize(1);
  quad->polygons[0].vertices = {0, 1, 2, 3};
  trim.setInputMesh(quad);
  trim.process(out);
  EXPECT_EQ(trim.getLastStatus().code, pcl_vts::StatusCode::INVALID_PARAMETER);
  EXPECT_NE(trim.getLastStatus().message.find("not 3"), std::string::npos);

  // Out-of-range id, then a bad factor.
  quad->polygons[0].vertices = {0, 1, 7};
  trim.process(out);
  EXPECT_EQ(trim.getLastStatus().code, pcl_vts::StatusCode::INVALID_PARAMETER);
  quad->polygons[0].vertices = {0, 2, 1}; // clockwise: reoriented, accepted
  trim.setTrimFactor(0.5);
  trim.process(out);
  EXPECT_EQ(trim.getLastStatus().code, pcl_vts::StatusCode::INVALID_PARAMETER);
  EXPECT_NE(trim.getLastStatus().message.find("trim_factor = 0.5"), std::string::npos);
  trim.setTrimFactor(4.0);
  trim.process(out);
  ASSERT_TRUE(trim.getLastStatus().ok()) << trim.getLastStatus().toString();
  ASSERT_EQ(out.polygons.size(), 1u);
  EXPECT_EQ(out.polygons[0].vertices, (pcl::Indices{0, 1, 2}));
}

TEST(HoleFilling, FillsASquareHoleAndAppendsFlaggedPoints)
{
  // 8 x 8 unit grid of points minus the triangles of the 2 x 2 squares in the
  // middle: one hole of area 4.
  pcl::PointCloud<pcl::PointXYZ> grid;
  for (int j = 0; j <= 8; ++j)
    for (int i = 0; i <= 8; ++i)
      grid.push_back({static_cast<float>(i), static_cast<float>(j),
                      static_cast<float>(0.1 * i * j)});
  auto mesh = std::make_shared<pcl::PolygonMesh>();
  pcl::toPCLPointCloud2(grid, mesh->cloud);
  auto id = [](int i, int j) { return static_cast<pcl::index_t>(j * 9 + i); };
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      if (i >= 3 && i <= 4 && j >= 3 && j <= 4)
        continue;
      pcl::Vertices a, b;
      a.vertices = {id(i, j), id(i + 1, j), id(i + 1, j + 1)};
      b.vertices = {id(i, j), id(i + 1, j + 1), id(i, j + 1)};
      mesh->polygons.push_back(a);
      mesh->polygons.push_back(b);
    }
  pcl::HoleFilling fill;
  fill.setInputMesh(mesh);
  fill.setPointSpacing(0.5);
  pcl::PolygonMesh out;
  fill.process(out);
  ASSERT_TRUE(fill.getLastStatus().ok()) << fill.getLastStatus().toString();
  EXPECT_EQ(fill.getResult().holes_filled, 1u);
  EXPECT_GT(fill.getResult().points_inserted, 0u);
  EXPECT_EQ(out.cloud.width, 81u + fill.getResult().points_inserted);
  const pcl_vts::TriangleMesh arrays = asArrays(out);
  pcl_vts::test::expectValidSurfaceMesh(arrays);
  EXPECT_NEAR(pcl_vts::twiceArea(arrays), 2 * 64.0, 1e-9);
  pcl::PointCloud<pcl::PointXYZ> back;
  pcl::fromPCLPointCloud2(out.cloud, back);
  for (std::size_t k = 81; k < back.size(); ++k) {
    EXPECT_EQ(fill.getInsertedFlags()[k], 1);
    EXPECT_GT(back[k].x, 3.0f);
    EXPECT_LT(back[k].x, 5.0f);
    // z = 0.1 x y exactly reproduced? The spline is smooth, not exact: near it.
    EXPECT_NEAR(back[k].z, 0.1f * back[k].x * back[k].y, 0.05f);
  }
  fill.setMaxHoleArea(3.0); // the hole (area 4) now stays open
  fill.process(out);
  ASSERT_TRUE(fill.getLastStatus().ok());
  EXPECT_EQ(fill.getResult().holes_left_open, 1u);
  EXPECT_EQ(out.cloud.width, 81u);
  fill.setMaxHoleArea(-1.0);
  fill.process(out);
  EXPECT_EQ(fill.getLastStatus().code, pcl_vts::StatusCode::INVALID_PARAMETER);
  EXPECT_TRUE(out.polygons.empty());
}

} // namespace
