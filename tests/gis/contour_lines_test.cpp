// Contours of a mesh that is not held (the tiled path's): the same lines, points and
// order as traceContours on the mesh held, on planes, bowls, terrains with holes,
// vertices exactly on levels, a pinch vertex and shuffled ids; the same refusals.
#include "contour_features.h"
#include "gis_test_mesh.h"

#include <pcl_vts/gis/contour_lines.h>
#include <pcl_vts/gis/gis_outputs.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

namespace pcl_vts {
namespace {

struct Traced {
  Status status = Status::success();
  std::vector<ContourLine> lines;
  ContourStats stats;
};

Traced inMemory(TriangleMesh mesh, double interval, double base)
{
  Traced out;
  if (!mesh.rebuildHalfedges()) {
    out.status = Status::error(StatusCode::INTERNAL_ERROR, "not a manifold");
    return out;
  }
  out.status = traceContours(
      mesh, interval, base,
      [&](const ContourLine& l) {
        out.lines.push_back(l);
        return Status::success();
      },
      &out.stats);
  return out;
}

Traced outOfCore(const TriangleMesh& mesh, double interval, double base,
                 const std::string& folder)
{
  Traced out;
  out.status = traceContoursOutOfCore(
      test::streamOf(mesh), interval, base, folder,
      [&](const ContourLine& l) {
        out.lines.push_back(l);
        return Status::success();
      },
      &out.stats);
  return out;
}

/// Equal lines: levels, closure, and every point to the bit, in the same order.
void expectSame(const Traced& a, const Traced& b)
{
  ASSERT_TRUE(a.status.ok()) << a.status.toString();
  ASSERT_TRUE(b.status.ok()) << b.status.toString();
  EXPECT_EQ(a.stats.levels, b.stats.levels);
  EXPECT_EQ(a.stats.lines, b.stats.lines);
  EXPECT_EQ(a.stats.closed, b.stats.closed);
  EXPECT_EQ(a.stats.segments, b.stats.segments);
  ASSERT_EQ(a.lines.size(), b.lines.size());
  for (std::size_t i = 0; i < a.lines.size(); ++i) {
    const ContourLine &x = a.lines[i], &y = b.lines[i];
    EXPECT_EQ(x.level, y.level) << i;
    EXPECT_EQ(x.closed, y.closed) << i;
    ASSERT_EQ(x.points.size(), y.points.size()) << i;
    for (std::size_t k = 0; k < x.points.size(); ++k) {
      EXPECT_EQ(x.points[k].x, y.points[k].x) << i << "," << k;
      EXPECT_EQ(x.points[k].y, y.points[k].y) << i << "," << k;
    }
  }
}

/// The mesh with vertex ids permuted, triangles reordered and each triangle's
/// corners rotated (the same surface, another order).
TriangleMesh shuffled(const TriangleMesh& mesh, unsigned seed)
{
  std::mt19937 rng(seed);
  std::vector<VertexId> to(mesh.vertexCount());
  std::iota(to.begin(), to.end(), 0);
  std::shuffle(to.begin(), to.end(), rng);
  TriangleMesh out;
  out.xy.resize(mesh.vertexCount());
  out.z.resize(mesh.vertexCount());
  for (std::size_t v = 0; v < to.size(); ++v) {
    out.xy[to[v]] = mesh.xy[v];
    out.z[to[v]] = mesh.z[v];
  }
  std::vector<std::size_t> order(mesh.triangleCount());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  for (std::size_t t : order) {
    const std::size_t r = rng() % 3;
    for (std::size_t k = 0; k < 3; ++k)
      out.triangles.push_back(to[mesh.triangles[3 * t + (k + r) % 3]]);
  }
  return out;
}

/// folder(): the tracer's temporary files, checked empty at the end; root(): outputs.
class ContoursOutOfCore : public ::testing::Test {
 protected:
  void SetUp() override
  {
    root_ = std::filesystem::temp_directory_path() /
            ("pcl_vts_contours_test_" + std::to_string(::getpid()));
    std::filesystem::remove_all(root_);
    std::filesystem::create_directories(root_ / "tmp");
  }
  void TearDown() override
  {
    EXPECT_TRUE(std::filesystem::is_empty(root_ / "tmp"))
        << "temporary files left behind";
    std::filesystem::remove_all(root_);
  }
  std::string folder() const { return (root_ / "tmp").string(); }
  std::string root() const { return root_.string(); }

 private:
  std::filesystem::path root_;
};

TEST_F(ContoursOutOfCore, SameLinesAsInMemory)
{
  // Integer heights put many vertices exactly on levels; the holes and the notch
  // give open lines ending on inner boundaries beside closed loops.
  auto terrain = [](double x, double y) {
    return std::round(5 * std::sin(x / 3) + 4 * std::cos(y / 4) + 0.3 * x);
  };
  auto holes = [](int i, int j) {
    return !((i >= 8 && i < 13 && j >= 6 && j < 10) || (i >= 22 && j >= 18) ||
             (i == 4 && j == 15));
  };
  // Two blocks that touch at one vertex only (a pinch: manifold edges).
  auto pinch = [](int i, int j) { return (i < 5) == (j < 5); };
  auto cone = [](double x, double y) { return std::hypot(x - 5, y - 5); };
  const struct {
    TriangleMesh mesh;
    double interval, base;
  } cases[] = {
      {test::gridMesh(10, 8, 0, 0, 1, 1,
                      [](double x, double y) { return 0.5 * x + 0.25 * y; }),
       0.5, 0.0},
      {test::gridMesh(20, 20, -5.05, -5.05, 0.5, 0.5,
                      [](double x, double y) { return x * x + y * y; }),
       2.0, 0.0},
      {test::gridMesh(30, 25, 0, 0, 1, 1, terrain, holes), 1.0, 0.0},
      {test::gridMesh(30, 25, 0, 0, 1, 1, terrain, holes), 0.7, 0.13},
      {test::gridMesh(30, 25, 500000.5, 4100000.25, 0.9, 1.1, terrain, holes), 2.0,
       -1.0},
      {test::gridMesh(10, 10, 0, 0, 1, 1, cone, pinch), 0.5, 0.0},
      {test::gridMesh(10, 10, 0, 0, 1, 1, cone, pinch), 1.0, 0.0},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(std::to_string(c.mesh.triangleCount()) + " triangles every " +
                 std::to_string(c.interval));
    const Traced memory = inMemory(c.mesh, c.interval, c.base);
    EXPECT_GT(memory.lines.size(), 3u);
    expectSame(memory, outOfCore(c.mesh, c.interval, c.base, folder()));
    // Another order of the same mesh: again the lines traceContours gives for it.
    const TriangleMesh other = shuffled(c.mesh, 5);
    expectSame(inMemory(other, c.interval, c.base),
               outOfCore(other, c.interval, c.base, folder()));
  }
}

TEST_F(ContoursOutOfCore, OpenAndClosedLinesAndPinchesAreTraced)
{
  // The cone over two blocks touching at its apex: every level's circle is cut by
  // the blocks into two arcs ending on the boundary (no closed loop); the holes of
  // a terrain give both kinds.
  const TriangleMesh pinch = test::gridMesh(
      10, 10, 0, 0, 1, 1, [](double x, double y) { return std::hypot(x - 5, y - 5); },
      [](int i, int j) { return (i < 5) == (j < 5); });
  const Traced cone = outOfCore(pinch, 1.0, 0.0, folder());
  ASSERT_TRUE(cone.status.ok());
  EXPECT_EQ(cone.stats.closed, 0u);
  EXPECT_EQ(cone.stats.lines, 2 * cone.stats.levels);
  const TriangleMesh bowl = test::gridMesh(
      20, 20, -5.05, -5.05, 0.5, 0.5, [](double x, double y) { return x * x + y * y; },
      [](int i, int j) { return !(i == 3 && j == 10); });
  const Traced loops = outOfCore(bowl, 2.0, 0.0, folder());
  ASSERT_TRUE(loops.status.ok());
  EXPECT_GT(loops.stats.closed, 5u);
  EXPECT_GT(loops.stats.lines, loops.stats.closed);
}

TEST_F(ContoursOutOfCore, RefusesWhatInMemoryRefuses)
{
  const TriangleMesh plane =
      test::gridMesh(4, 4, 0, 0, 1, 1, [](double x, double) { return 1000 * x; });
  auto sink = [](const ContourLine&) { return Status::success(); };
  for (const double interval : {0.0, -1.0, std::nan(""), 1e-20}) {
    const Status s =
        traceContoursOutOfCore(test::streamOf(plane), interval, 0.0, folder(), sink);
    EXPECT_EQ(s.code, StatusCode::INVALID_PARAMETER) << interval;
    EXPECT_EQ(traceContours(plane, interval, 0.0, sink).code,
              StatusCode::INVALID_PARAMETER);
  }
  TriangleMesh bad = plane;
  bad.triangles.back() = 99;
  EXPECT_EQ(traceContoursOutOfCore(test::streamOf(bad), 1.0, 0.0, folder(), sink).code,
            StatusCode::INVALID_PARAMETER);
  // An edge (0,0)-(2,0) crossed at z = 1 with three triangles on it, and an edge
  // used twice in the same direction: not a manifold, as rebuildHalfedges says.
  TriangleMesh fan;
  fan.xy = {{0, 0}, {2, 0}, {1, 1}, {1, -1}, {1, 2}};
  fan.z = {0, 2, 0, 0, 0};
  fan.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  EXPECT_FALSE(TriangleMesh(fan).rebuildHalfedges());
  EXPECT_EQ(traceContoursOutOfCore(test::streamOf(fan), 1.0, 0.0, folder(), sink).code,
            StatusCode::INTERNAL_ERROR);
  fan.triangles = {0, 1, 2, 0, 1, 4};
  EXPECT_FALSE(TriangleMesh(fan).rebuildHalfedges());
  EXPECT_EQ(traceContoursOutOfCore(test::streamOf(fan), 1.0, 0.0, folder(), sink).code,
            StatusCode::INTERNAL_ERROR);
  // No triangle at all: no line, no error.
  TriangleMesh empty;
  ContourStats stats;
  EXPECT_TRUE(
      traceContoursOutOfCore(test::streamOf(empty), 1.0, 0.0, folder(), sink, &stats)
          .ok());
  EXPECT_EQ(stats.lines, 0u);
}

TEST_F(ContoursOutOfCore, FileHasTheInMemoryFeatures)
{
  const TriangleMesh mesh = test::gridMesh(
      30, 25, 2600000, 1200000, 2, 2,
      [](double x, double y) { return 400 + 20 * std::sin(x / 9) * std::cos(y / 7); },
      [](int i, int j) { return !(i > 10 && i < 15 && j > 5 && j < 12); });
  std::string wkt;
  ASSERT_TRUE(normalizeCrs("EPSG:2056", wkt).ok());
  for (const char* ext : {".gpkg", ".shp"}) {
    const std::string held = root() + "/held" + ext;
    const std::string streamed = root() + "/streamed" + ext;
    TriangleMesh with_halfedges = mesh;
    with_halfedges.rebuildHalfedges();
    ContourStats a, b;
    ASSERT_TRUE(writeContourFile(held, with_halfedges, 5.0, 0.0, wkt, &a).ok());
    ASSERT_TRUE(
        writeContourFile(streamed, test::streamOf(mesh), 5.0, 0.0, wkt, folder(), &b)
            .ok());
    const auto features = test::contourFeatures(held);
    EXPECT_GT(features.size(), 10u);
    EXPECT_EQ(features.size(), a.lines);
    EXPECT_TRUE(features == test::contourFeatures(streamed)) << ext;
  }
}

} // namespace
} // namespace pcl_vts
