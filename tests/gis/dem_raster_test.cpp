// DEM rasterization against independent oracles: a plane (every triangle gives the
// same exact value), a non-planar TIN (brute force over all triangles in long
// double), an L-shaped footprint with pixel centres exactly on its boundary.
#include "gis_test_mesh.h"

#include <pcl_vts/gis/dem_raster.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace pcl_vts {
namespace {

constexpr float NODATA = -9999.0f;

std::vector<float> rasterize(const TriangleMesh& mesh, const DemGrid& grid,
                             std::size_t block_rows, DemRasterStats* stats = nullptr)
{
  std::vector<float> out(grid.cols * grid.rows, 12345.0f);
  std::size_t expect_row = 0;
  Status s = rasterizeDem(
      mesh, grid, NODATA, block_rows,
      [&](std::size_t row0, std::size_t count, const float* v) {
        EXPECT_EQ(row0, expect_row); // blocks arrive in order, north to south
        EXPECT_LE(count, block_rows);
        expect_row += count;
        std::copy(v, v + count * grid.cols, out.begin() + row0 * grid.cols);
        return Status::success();
      },
      stats);
  EXPECT_TRUE(s.ok()) << s.toString();
  EXPECT_EQ(expect_row, grid.rows);
  return out;
}

/// The value a float DEM may hold for an exact value: within 2 float ulps.
void expectFloatClose(float got, long double exact, std::size_t col, std::size_t row)
{
  const long double tol = 2.0L * std::ldexp(1.0L, -23) * std::fabs(exact) + 1e-30L;
  EXPECT_LE(std::fabs(static_cast<long double>(got) - exact), tol)
      << "pixel " << col << "," << row << " got " << got << " want " << (double)exact;
}

TEST(DemRaster, PlaneEqualsExactInterpolationInsideAndNodataOutside)
{
  auto plane = [](double x, double y) { return 2.5 * x - 0.75 * y + 310.0; };
  const TriangleMesh mesh =
      test::gridMesh(9, 7, 500000.37, 5200000.11, 1.3, 1.7, plane);
  DemGrid grid;
  ASSERT_TRUE(demGridForMesh(mesh, 0.5, grid).ok());
  // Default grid: edges on multiples of R, so centres at k*R + R/2.
  EXPECT_EQ(std::fmod(grid.x0, 0.5), 0.0);
  EXPECT_EQ(std::fmod(grid.y1, 0.5), 0.0);
  const std::vector<float> v = rasterize(mesh, grid, 5);
  const double xmin = 500000.37, xmax = xmin + 9 * 1.3, ymin = 5200000.11,
               ymax = ymin + 7 * 1.7;
  std::size_t inside = 0;
  for (std::size_t r = 0; r < grid.rows; ++r)
    for (std::size_t c = 0; c < grid.cols; ++c) {
      const double x = grid.centreX(c), y = grid.centreY(r);
      const bool in = x >= xmin && x <= xmax && y >= ymin && y <= ymax;
      const float got = v[r * grid.cols + c];
      if (!in) {
        EXPECT_EQ(got, NODATA) << c << "," << r;
        continue;
      }
      ++inside;
      expectFloatClose(got, 2.5L * x - 0.75L * y + 310.0L, c, r);
    }
  EXPECT_GT(inside, 400u);
}

TEST(DemRaster, NonPlanarTinMatchesBruteForceAndBlocksDoNotMatter)
{
  auto bilinear = [](double x, double y) { return 0.3 * x * y - x + 2 * y; };
  const TriangleMesh mesh = test::gridMesh(6, 5, -3.13, 2.21, 1.0, 1.25, bilinear);
  DemGrid grid;
  ASSERT_TRUE(demGridForMesh(mesh, 0.2, grid).ok());
  const std::vector<float> v = rasterize(mesh, grid, 3);
  for (std::size_t r = 0; r < grid.rows; ++r)
    for (std::size_t c = 0; c < grid.cols; ++c) {
      const long double px = grid.centreX(c), py = grid.centreY(r);
      bool found = false;
      long double z = 0;
      for (std::size_t t = 0; t < mesh.triangleCount() && !found; ++t) {
        const VertexId ia = mesh.triangles[3 * t], ib = mesh.triangles[3 * t + 1],
                       ic = mesh.triangles[3 * t + 2];
        const long double ax = mesh.xy[ia].x, ay = mesh.xy[ia].y, bx = mesh.xy[ib].x,
                          by = mesh.xy[ib].y, cx = mesh.xy[ic].x, cy = mesh.xy[ic].y;
        const long double det = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay);
        const long double l1 = ((px - ax) * (cy - ay) - (cx - ax) * (py - ay)) / det;
        const long double l2 = ((bx - ax) * (py - ay) - (px - ax) * (by - ay)) / det;
        if (l1 >= -1e-15L && l2 >= -1e-15L && l1 + l2 <= 1 + 1e-15L) {
          found = true;
          z = mesh.z[ia] + l1 * (mesh.z[ib] - mesh.z[ia]) +
              l2 * (mesh.z[ic] - mesh.z[ia]);
        }
      }
      const float got = v[r * grid.cols + c];
      if (!found)
        EXPECT_EQ(got, NODATA);
      else
        expectFloatClose(got, z, c, r);
    }
  // The same raster whatever the block height.
  EXPECT_EQ(rasterize(mesh, grid, 1), v);
  EXPECT_EQ(rasterize(mesh, grid, 1000), v);
}

TEST(DemRaster, LShapeNodataExactlyOutsideWithCentresOnTheBoundary)
{
  // 4x4 unit cells minus the top-right 2x2: the footprint is an L.
  auto keep = [](int i, int j) { return !(i >= 2 && j >= 2); };
  const TriangleMesh mesh = test::gridMesh(
      4, 4, 0.0, 0.0, 1.0, 1.0, [](double x, double y) { return x + y; }, keep);
  DemGrid grid;
  // Bounds shifted by R/2: centres at multiples of 0.5, many exactly on edges.
  ASSERT_TRUE(demGridForBounds(-1.25, -1.25, 5.25, 5.25, 0.5, grid).ok());
  EXPECT_EQ(grid.cols, 13u);
  DemRasterStats stats;
  const std::vector<float> v = rasterize(mesh, grid, 4, &stats);
  std::size_t inside = 0;
  for (std::size_t r = 0; r < grid.rows; ++r)
    for (std::size_t c = 0; c < grid.cols; ++c) {
      const double x = grid.centreX(c), y = grid.centreY(r);
      const bool in_square = x >= 0 && x <= 4 && y >= 0 && y <= 4;
      const bool in_notch = x > 2 && y > 2; // the open notch; its edges stay inside
      const bool in = in_square && !in_notch;
      const float got = v[r * grid.cols + c];
      if (in) {
        ++inside;
        EXPECT_EQ(got, static_cast<float>(x + y)) << x << "," << y;
      } else
        EXPECT_EQ(got, NODATA) << x << "," << y;
    }
  EXPECT_EQ(stats.pixels_inside, inside);
  EXPECT_EQ(inside, 9u * 9u - 4u * 4u);
}

/// rasterizeDemOutOfCore into one array, checking that every window comes once.
std::vector<float> rasterizeOutOfCore(const TriangleMesh& mesh, const DemGrid& grid,
                                      std::uint64_t memory, const std::string& folder,
                                      DemRasterStats* stats = nullptr)
{
  const MeshStream stream = test::streamOf(mesh);
  std::vector<float> out(grid.cols * grid.rows, 12345.0f);
  std::vector<int> written(out.size(), 0);
  const Status s = rasterizeDemOutOfCore(
      stream, grid, NODATA, 256, memory, folder,
      [&](std::size_t row0, std::size_t col0, std::size_t rows, std::size_t cols,
          const float* v) {
        for (std::size_t r = 0; r < rows; ++r)
          for (std::size_t c = 0; c < cols; ++c) {
            out[(row0 + r) * grid.cols + col0 + c] = v[r * cols + c];
            ++written[(row0 + r) * grid.cols + col0 + c];
          }
        return Status::success();
      },
      stats);
  EXPECT_TRUE(s.ok()) << s.toString();
  EXPECT_TRUE(
      std::all_of(written.begin(), written.end(), [](int w) { return w == 1; }));
  return out;
}

TEST(DemRaster, OutOfCoreEqualsInMemoryForEveryWindowSize)
{
  // The tiled path's DEM: triangles filed per window on disk, then window by window.
  // Shared edges on pixel centres (grid meshes with centres on their lines), a
  // footprint with a notch, and long thin triangles across many windows.
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / "pcl_vts_dem_out_of_core_test";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  auto keep = [](int i, int j) { return !(i >= 5 && j >= 4); };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const TriangleMesh meshes[] = {
      test::gridMesh(
          9, 7, 0.0, 0.0, 1.0, 1.0, [](double x, double y) { return x * y; }, keep),
      test::gridMesh(40, 3, -7.3, 1.1, 0.77, 9.5, [&](double x, double y) {
        return std::sin(x) + y + 0.01 * u(rng);
      })};
  for (const TriangleMesh& mesh : meshes) {
    for (const double resolution : {0.05, 0.25, 0.5}) {
      SCOPED_TRACE(resolution);
      DemGrid grid;
      ASSERT_TRUE(demGridForMesh(mesh, resolution, grid).ok());
      DemRasterStats memory_stats;
      const std::vector<float> expected = rasterize(mesh, grid, 256, &memory_stats);
      // From one window (plenty of memory) down to 32-pixel windows.
      for (const std::uint64_t memory :
           {std::uint64_t{1} << 30, std::uint64_t{20000}, std::uint64_t{100}}) {
        SCOPED_TRACE(memory);
        DemRasterStats stats;
        EXPECT_TRUE(rasterizeOutOfCore(mesh, grid, memory, folder.string(), &stats) ==
                    expected);
        EXPECT_EQ(stats.pixels_inside, memory_stats.pixels_inside);
      }
    }
  }
  EXPECT_TRUE(std::filesystem::is_empty(folder)) << "temporary files left behind";
  std::filesystem::remove_all(folder);
}

TEST(DemRaster, GridRules)
{
  DemGrid grid;
  EXPECT_FALSE(demGridForBounds(0, 0, 10, 10, 3, grid).ok()); // 3.33 pixels
  EXPECT_FALSE(demGridForBounds(0, 0, -10, 10, 1, grid).ok());
  EXPECT_FALSE(demGridForBounds(0, 0, 10, 10, 0, grid).ok());
  ASSERT_TRUE(demGridForBounds(100, 200, 110, 205, 0.5, grid).ok());
  EXPECT_EQ(grid.cols, 20u);
  EXPECT_EQ(grid.rows, 10u);
  EXPECT_EQ(grid.centreX(0), 100.25);
  EXPECT_EQ(grid.centreY(0), 204.75);
  // A degenerate triangle covers nothing.
  TriangleMesh flat;
  flat.xy = {{0, 0}, {1, 1}, {2, 2}};
  flat.z = {1, 2, 3};
  flat.triangles = {0, 1, 2};
  ASSERT_TRUE(demGridForMesh(flat, 0.5, grid).ok());
  DemRasterStats stats;
  rasterize(flat, grid, 2, &stats);
  EXPECT_EQ(stats.pixels_inside, 0u);
}

} // namespace
} // namespace pcl_vts
