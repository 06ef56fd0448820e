// Tests of pcl::VTSGridTriangulation: the PCL contract (indices, ids into input_,
// NaN skipping, duplicate rules, status on bad input) checked by invariants of a
// Delaunay triangulation of the convex hull, never by golden triangle ids.
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/predicates.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/vts_grid_triangulation.h>

#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace {

using pcl_vts::StatusCode;
using XY = std::pair<double, double>;

template <typename PointT>
PointT makePoint(double x, double y, double z)
{
  PointT p;
  p.x = static_cast<float>(x);
  p.y = static_cast<float>(y);
  p.z = static_cast<float>(z);
  return p;
}

/// nx * ny points on a lattice of the given spacing, each moved by up to 0.3 spacing
/// (seeded), z a smooth function of XY. Float-rounded, as PCL stores it.
template <typename PointT>
typename pcl::PointCloud<PointT>::Ptr
jitteredGrid(int nx, int ny, double spacing, double x0, double y0, std::uint32_t seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3 * spacing, 0.3 * spacing);
  typename pcl::PointCloud<PointT>::Ptr cloud(new pcl::PointCloud<PointT>);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = x0 + i * spacing + jitter(rng);
      const double y = y0 + j * spacing + jitter(rng);
      cloud->push_back(makePoint<PointT>(x, y, 100.0 + std::sin(0.1 * i) * j));
    }
  return cloud;
}

template <typename PointT>
bool isFinitePoint(const PointT& p)
{
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

template <typename PointT>
XY xyOf(const PointT& p)
{
  return {p.x, p.y};
}

/// Checks that polygons is a Delaunay triangulation of the convex hull of the
/// distinct XY of the selected finite points (all points when selected is empty):
/// ids in range and selected, CCW (exact), an edge-manifold disk with Euler
/// number 1, every boundary edge a hull edge, 2n - h - 2 triangles, every distinct
/// point used exactly once, locally Delaunay everywhere.
template <typename PointT>
::testing::AssertionResult
isHullTriangulation(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& selected,
                    const std::vector<pcl::Vertices>& polygons,
                    const pcl_vts::Diagnostics& diag)
{
  std::vector<bool> is_selected(cloud.size(), selected.empty());
  for (const pcl::index_t id : selected)
    is_selected[static_cast<std::size_t>(id)] = true;
  std::set<XY> distinct;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (is_selected[i] && isFinitePoint(cloud[i]))
      distinct.insert(xyOf(cloud[i]));
  const std::size_t n = distinct.size();
  const std::size_t h = diag.hull_vertices;
  if (diag.distinct_points != n)
    return ::testing::AssertionFailure()
           << "diagnostics.distinct_points = " << diag.distinct_points << ", expected "
           << n;
  if (polygons.size() != 2 * n - h - 2 || diag.triangles != polygons.size())
    return ::testing::AssertionFailure()
           << polygons.size() << " triangles (diagnostics " << diag.triangles
           << "), expected 2n - h - 2 = " << 2 * n - h - 2 << " (n = " << n
           << ", h = " << h << ")";

  // Compact mesh over the used input ids.
  pcl_vts::TriangleMesh mesh;
  std::map<pcl::index_t, pcl_vts::VertexId> vertex_of;
  for (std::size_t t = 0; t < polygons.size(); ++t) {
    const pcl::Indices& ids = polygons[t].vertices;
    if (ids.size() != 3)
      return ::testing::AssertionFailure()
             << "polygon " << t << " has " << ids.size() << " vertices";
    for (const pcl::index_t id : ids) {
      if (id < 0 || static_cast<std::size_t>(id) >= cloud.size())
        return ::testing::AssertionFailure()
               << "polygon " << t << " has id " << id << " outside the cloud";
      const auto i = static_cast<std::size_t>(id);
      if (!is_selected[i] || !isFinitePoint(cloud[i]))
        return ::testing::AssertionFailure() << "polygon " << t << " uses point " << id
                                             << ", which is not selected or not finite";
      auto [it, inserted] =
          vertex_of.emplace(id, static_cast<pcl_vts::VertexId>(mesh.xy.size()));
      if (inserted) {
        mesh.xy.push_back({cloud[i].x, cloud[i].y});
        mesh.z.push_back(cloud[i].z);
      }
      mesh.triangles.push_back(it->second);
    }
    const pcl_vts::Point2& a = mesh.xy[mesh.triangles[3 * t]];
    const pcl_vts::Point2& b = mesh.xy[mesh.triangles[3 * t + 1]];
    const pcl_vts::Point2& c = mesh.xy[mesh.triangles[3 * t + 2]];
    if (pcl_vts::orient2d(a, b, c) != pcl_vts::Sign::POSITIVE)
      return ::testing::AssertionFailure()
             << "triangle " << t << " (" << ids[0] << ", " << ids[1] << ", " << ids[2]
             << ") is not counter-clockwise";
  }
  std::set<XY> used;
  for (const pcl_vts::Point2& p : mesh.xy)
    used.insert({p.x, p.y});
  if (mesh.xy.size() != n || used != distinct)
    return ::testing::AssertionFailure()
           << mesh.xy.size() << " points used at " << used.size()
           << " positions; expected each of the " << n << " distinct points once";

  std::string why;
  if (!mesh.rebuildHalfedges())
    return ::testing::AssertionFailure() << "an edge is used by more than 2 triangles";
  if (!pcl_vts::isEdgeManifold(mesh, &why))
    return ::testing::AssertionFailure() << "not edge-manifold: " << why;
  if (pcl_vts::eulerCharacteristic(mesh) != 1)
    return ::testing::AssertionFailure()
           << "Euler characteristic " << pcl_vts::eulerCharacteristic(mesh)
           << ", expected 1 (a disk)";
  if (pcl_vts::boundaryEdgeCount(mesh) != h)
    return ::testing::AssertionFailure()
           << pcl_vts::boundaryEdgeCount(mesh) << " boundary edges, expected h = " << h;
  if (!pcl_vts::isDelaunay(mesh, &why))
    return ::testing::AssertionFailure() << "not Delaunay: " << why;
  // A boundary edge with a point strictly right of it is not a hull edge.
  for (pcl_vts::HalfedgeId e = 0; e < mesh.halfedges.size(); ++e) {
    if (mesh.halfedges[e] != pcl_vts::INVALID_ID)
      continue;
    const pcl_vts::Point2& a = mesh.xy[mesh.triangles[e]];
    const pcl_vts::Point2& b = mesh.xy[mesh.triangles[pcl_vts::nextHalfedge(e)]];
    for (const pcl_vts::Point2& p : mesh.xy)
      if (pcl_vts::orient2d(a, b, p) == pcl_vts::Sign::NEGATIVE)
        return ::testing::AssertionFailure()
               << "boundary edge (" << a.x << ", " << a.y << ") -> (" << b.x << ", "
               << b.y << ") has point (" << p.x << ", " << p.y << ") outside";
  }
  return ::testing::AssertionSuccess();
}

/// Triangles as sets of input ids, rotation-normalised (first id smallest).
std::set<std::array<pcl::index_t, 3>>
triangleSet(const std::vector<pcl::Vertices>& polygons)
{
  std::set<std::array<pcl::index_t, 3>> set;
  for (const pcl::Vertices& poly : polygons) {
    std::array<pcl::index_t, 3> t{poly.vertices[0], poly.vertices[1], poly.vertices[2]};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    set.insert(t);
  }
  return set;
}

std::set<pcl::index_t> usedIds(const std::vector<pcl::Vertices>& polygons)
{
  std::set<pcl::index_t> ids;
  for (const pcl::Vertices& poly : polygons)
    ids.insert(poly.vertices.begin(), poly.vertices.end());
  return ids;
}

/// Runs reconstruct(points, polygons) and returns the polygons.
template <typename PointT>
std::vector<pcl::Vertices>
triangulate(pcl::VTSGridTriangulation<PointT>& vts,
            const typename pcl::PointCloud<PointT>::ConstPtr& cloud)
{
  vts.setInputCloud(cloud);
  pcl::PointCloud<PointT> points;
  std::vector<pcl::Vertices> polygons;
  vts.reconstruct(points, polygons);
  return polygons;
}

/// Non-empty placeholder output, to show that a failed reconstruction clears it.
std::vector<pcl::Vertices> stalePolygons()
{
  return {pcl::Vertices{}, pcl::Vertices{}};
}

} // namespace

TEST(VTSGridTriangulation, ClassContract)
{
  pcl::VTSGridTriangulation<pcl::PointXYZ>::Ptr vts(
      new pcl::VTSGridTriangulation<pcl::PointXYZ>);
  EXPECT_EQ(vts->getClassName(), "VTSGridTriangulation");
  EXPECT_EQ(vts->getCellSize(), 0.0);
  EXPECT_EQ(vts->getDuplicateRule(), pcl_vts::DuplicateRule::LOWEST_Z);
  vts->setCellSize(2.5);
  vts->setDuplicateRule(pcl_vts::DuplicateRule::MEAN_Z);
  EXPECT_EQ(vts->getCellSize(), 2.5);
  EXPECT_EQ(vts->getDuplicateRule(), pcl_vts::DuplicateRule::MEAN_Z);

  // check_tree_ is false: the base class builds no search tree.
  vts->setInputCloud(jitteredGrid<pcl::PointXYZ>(5, 5, 1.0, 0.0, 0.0, 1));
  pcl::PolygonMesh mesh;
  vts->reconstruct(mesh);
  EXPECT_TRUE(vts->getLastStatus().ok()) << vts->getLastStatus().toString();
  EXPECT_EQ(vts->getSearchMethod(), nullptr);
}

TEST(VTSGridTriangulation, JitteredGridIsHullDelaunayTriangulation)
{
  for (const std::uint32_t seed : {42u, 7u, 2015u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto cloud = jitteredGrid<pcl::PointXYZ>(30, 20, 1.0, -3.0, 5.0, seed);
    pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
    vts.setInputCloud(cloud);
    pcl::PolygonMesh mesh;
    vts.reconstruct(mesh);
    ASSERT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
    EXPECT_TRUE(isHullTriangulation(*cloud, {}, mesh.polygons, vts.getDiagnostics()));
    EXPECT_EQ(mesh.cloud.width * mesh.cloud.height, cloud->size());

    const pcl_vts::Diagnostics& diag = vts.getDiagnostics();
    EXPECT_EQ(diag.points_in, cloud->size());
    EXPECT_EQ(diag.non_finite_dropped, 0u);
    EXPECT_EQ(diag.duplicates_merged, 0u);
    EXPECT_GT(diag.cell_size, 0.0);
    EXPECT_GT(diag.cells, 0u);
  }
}

TEST(VTSGridTriangulation, BothOverloadsGiveTheSameTriangles)
{
  const auto cloud = jitteredGrid<pcl::PointXYZ>(12, 9, 0.5, 0.0, 0.0, 3);
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  vts.setInputCloud(cloud);
  pcl::PolygonMesh mesh;
  vts.reconstruct(mesh);
  pcl::PointCloud<pcl::PointXYZ> points;
  std::vector<pcl::Vertices> polygons;
  vts.reconstruct(points, polygons);
  ASSERT_TRUE(vts.getLastStatus().ok());
  ASSERT_FALSE(polygons.empty());
  EXPECT_EQ(triangleSet(mesh.polygons), triangleSet(polygons));
  ASSERT_EQ(points.size(), cloud->size());
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_EQ(xyOf(points[i]), xyOf((*cloud)[i]));
}

TEST(VTSGridTriangulation, CellSizeChangesSpeedNotTriangles)
{
  const auto cloud = jitteredGrid<pcl::PointXYZ>(25, 25, 1.0, 0.0, 0.0, 11);
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  const auto reference = triangleSet(triangulate(vts, cloud));
  ASSERT_FALSE(reference.empty());
  for (const double cell_size : {0.3, 1.0, 4.0, 50.0}) {
    SCOPED_TRACE("cell_size " + std::to_string(cell_size));
    vts.setCellSize(cell_size);
    EXPECT_EQ(triangleSet(triangulate(vts, cloud)), reference);
    if (cell_size < 20.0) {
      EXPECT_EQ(vts.getDiagnostics().cell_size, cell_size);
    } else { // wider than the data (about 24 x 24): clamped to the XY extent
      EXPECT_LT(vts.getDiagnostics().cell_size, cell_size);
      EXPECT_GT(vts.getDiagnostics().cell_size, 20.0);
    }
  }
}

TEST(VTSGridTriangulation, ThreadsChangeSpeedNotTriangles)
{
  const auto cloud = jitteredGrid<pcl::PointXYZ>(60, 40, 1.0, 0.0, 0.0, 5);
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  EXPECT_EQ(vts.getNumberOfThreads(), 1u);
  const auto reference = triangulate(vts, cloud);
  ASSERT_FALSE(reference.empty());
  for (const unsigned threads : {2u, 0u}) {
    vts.setNumberOfThreads(threads);
    const auto polygons = triangulate(vts, cloud);
    ASSERT_EQ(polygons.size(), reference.size());
    for (std::size_t t = 0; t < polygons.size(); ++t)
      EXPECT_EQ(polygons[t].vertices, reference[t].vertices) << "triangle " << t;
  }
}

TEST(VTSGridTriangulation, ExactGridWithCocircularTies)
{
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 13; ++i)
      cloud->push_back(makePoint<pcl::PointXYZ>(i, j, 0.0));
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  const auto polygons = triangulate(vts, cloud);
  ASSERT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
  // Every lattice point on the border is a (collinear) hull vertex.
  EXPECT_EQ(vts.getDiagnostics().hull_vertices, 2u * (13 + 10) - 4);
  EXPECT_EQ(polygons.size(), 2u * 12 * 9);
  EXPECT_TRUE(isHullTriangulation(*cloud, {}, polygons, vts.getDiagnostics()));
}

TEST(VTSGridTriangulation, HonoursIndicesAndReturnsInputIds)
{
  const auto cloud = jitteredGrid<pcl::PointXYZ>(20, 15, 1.0, 0.0, 0.0, 5);
  pcl::IndicesPtr indices(new pcl::Indices);
  // Every third point, listed backwards, so positions in indices differ from ids.
  for (int i = static_cast<int>(cloud->size()) - 1; i >= 0; i -= 3)
    indices->push_back(i);

  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  vts.setInputCloud(cloud);
  vts.setIndices(indices);
  pcl::PolygonMesh mesh;
  vts.reconstruct(mesh);
  ASSERT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
  EXPECT_EQ(vts.getDiagnostics().points_in, indices->size());
  EXPECT_EQ(mesh.cloud.width * mesh.cloud.height, cloud->size());
  EXPECT_TRUE(
      isHullTriangulation(*cloud, *indices, mesh.polygons, vts.getDiagnostics()));
  const std::set<pcl::index_t> selected(indices->begin(), indices->end());
  EXPECT_EQ(usedIds(mesh.polygons), selected);
}

TEST(VTSGridTriangulation, RejectsIndicesOutsideTheCloud)
{
  const auto cloud = jitteredGrid<pcl::PointXYZ>(4, 4, 1.0, 0.0, 0.0, 5);
  pcl::IndicesPtr indices(new pcl::Indices{0, 1, 2, 99});
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  vts.setInputCloud(cloud);
  vts.setIndices(indices);
  pcl::PolygonMesh mesh;
  mesh.polygons = stalePolygons();
  vts.reconstruct(mesh);
  EXPECT_TRUE(mesh.polygons.empty());
  EXPECT_EQ(vts.getLastStatus().code, StatusCode::INVALID_PARAMETER);
  EXPECT_NE(vts.getLastStatus().message.find("99"), std::string::npos)
      << vts.getLastStatus().message;
}

TEST(VTSGridTriangulation, SkipsAndCountsNonFinitePoints)
{
  auto cloud = jitteredGrid<pcl::PointXYZ>(10, 10, 1.0, 0.0, 0.0, 9);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  (*cloud)[3].x = nan;
  (*cloud)[17].z = nan;
  (*cloud)[40].y = inf;
  (*cloud)[0].x = -inf; // a corner: dropping it changes the hull
  cloud->is_dense = false;

  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  const auto polygons = triangulate(vts, cloud);
  ASSERT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
  EXPECT_EQ(vts.getDiagnostics().non_finite_dropped, 4u);
  EXPECT_EQ(vts.getDiagnostics().points_in, cloud->size());
  EXPECT_TRUE(isHullTriangulation(*cloud, {}, polygons, vts.getDiagnostics()));
  const auto used = usedIds(polygons);
  for (const pcl::index_t id : {0, 3, 17, 40})
    EXPECT_EQ(used.count(id), 0u) << "non-finite point " << id << " was used";
  EXPECT_EQ(used.size(), cloud->size() - 4);
}

TEST(VTSGridTriangulation, DuplicateRulesPickTheRepresentative)
{
  // Point 5 of the grid is repeated at the end at other heights.
  const auto base = jitteredGrid<pcl::PointXYZ>(6, 6, 1.0, 0.0, 0.0, 13);
  const pcl::index_t first = 5;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>(*base));
  (*cloud)[first].z = 10.0f;
  const pcl::index_t low = static_cast<pcl::index_t>(cloud->size());
  cloud->push_back(makePoint<pcl::PointXYZ>((*cloud)[first].x, (*cloud)[first].y, 4.0));
  const pcl::index_t high = low + 1;
  cloud->push_back(
      makePoint<pcl::PointXYZ>((*cloud)[first].x, (*cloud)[first].y, 19.0));

  const std::vector<std::pair<pcl_vts::DuplicateRule, pcl::index_t>> cases = {
      {pcl_vts::DuplicateRule::LOWEST_Z, low},
      {pcl_vts::DuplicateRule::HIGHEST_Z, high},
      {pcl_vts::DuplicateRule::FIRST, first},
      {pcl_vts::DuplicateRule::MEAN_Z, first}};
  for (const auto& [rule, expected] : cases) {
    SCOPED_TRACE(std::string("rule ") + pcl_vts::duplicateRuleName(rule));
    pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
    vts.setDuplicateRule(rule);
    const auto polygons = triangulate(vts, cloud);
    ASSERT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
    EXPECT_EQ(vts.getDiagnostics().duplicates_merged, 2u);
    EXPECT_TRUE(isHullTriangulation(*cloud, {}, polygons, vts.getDiagnostics()));
    const auto used = usedIds(polygons);
    for (const pcl::index_t id : {first, low, high})
      EXPECT_EQ(used.count(id), id == expected ? 1u : 0u) << "point " << id;
  }
}

TEST(VTSGridTriangulation, MeanZIsWrittenToTheOutputCloud)
{
  const auto base = jitteredGrid<pcl::PointXYZ>(6, 6, 1.0, 0.0, 0.0, 17);
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>(*base));
  const pcl::index_t first = 14;
  (*cloud)[first].z = 1.0f;
  cloud->push_back(makePoint<pcl::PointXYZ>((*cloud)[first].x, (*cloud)[first].y, 2.0));
  cloud->push_back(makePoint<pcl::PointXYZ>((*cloud)[first].x, (*cloud)[first].y, 6.0));
  const float mean_z = 3.0f;
  const pcl::PointCloud<pcl::PointXYZ> original = *cloud;

  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  vts.setDuplicateRule(pcl_vts::DuplicateRule::MEAN_Z);
  vts.setInputCloud(cloud);

  pcl::PolygonMesh mesh;
  vts.reconstruct(mesh);
  ASSERT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
  EXPECT_EQ(usedIds(mesh.polygons).count(first), 1u);
  pcl::PointCloud<pcl::PointXYZ> mesh_points;
  pcl::fromPCLPointCloud2(mesh.cloud, mesh_points);

  pcl::PointCloud<pcl::PointXYZ> points;
  std::vector<pcl::Vertices> polygons;
  vts.reconstruct(points, polygons);
  ASSERT_TRUE(vts.getLastStatus().ok());

  ASSERT_EQ(mesh_points.size(), original.size());
  ASSERT_EQ(points.size(), original.size());
  for (std::size_t i = 0; i < original.size(); ++i) {
    const float expected_z =
        static_cast<pcl::index_t>(i) == first ? mean_z : original[i].z;
    EXPECT_EQ(mesh_points[i].z, expected_z) << "PolygonMesh cloud, point " << i;
    EXPECT_EQ(points[i].z, expected_z) << "points overload, point " << i;
  }
  // The input cloud itself is left alone.
  EXPECT_EQ((*cloud)[first].z, 1.0f);
}

TEST(VTSGridTriangulation, RejectsInvalidCellSize)
{
  const auto cloud = jitteredGrid<pcl::PointXYZ>(6, 6, 1.0, 0.0, 0.0, 19);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::pair<double, std::string>> cases = {
      {-1.0, "-1"}, {nan, "nan"}, {inf, "inf"}};
  for (const auto& [cell_size, text] : cases) {
    SCOPED_TRACE("cell_size " + text);
    pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
    vts.setCellSize(cell_size);
    vts.setInputCloud(cloud);
    pcl::PolygonMesh mesh;
    mesh.polygons = stalePolygons();
    vts.reconstruct(mesh);
    EXPECT_TRUE(mesh.polygons.empty());
    EXPECT_EQ(vts.getLastStatus().code, StatusCode::INVALID_PARAMETER);
    const std::string& message = vts.getLastStatus().message;
    EXPECT_NE(message.find("cell_size"), std::string::npos) << message;
    EXPECT_NE(message.find(text), std::string::npos) << message;

    // A valid value afterwards replaces the error.
    vts.setCellSize(0.0);
    vts.reconstruct(mesh);
    EXPECT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
    EXPECT_FALSE(mesh.polygons.empty());
  }
}

TEST(VTSGridTriangulation, RejectsInvalidDuplicateRule)
{
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  vts.setDuplicateRule(static_cast<pcl_vts::DuplicateRule>(42));
  const auto polygons = triangulate(vts, jitteredGrid<pcl::PointXYZ>(4, 4, 1, 0, 0, 1));
  EXPECT_TRUE(polygons.empty());
  EXPECT_EQ(vts.getLastStatus().code, StatusCode::INVALID_PARAMETER);
  EXPECT_NE(vts.getLastStatus().message.find("42"), std::string::npos);
}

TEST(VTSGridTriangulation, CollinearInputIsAnError)
{
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (int i = 0; i < 20; ++i)
    cloud->push_back(makePoint<pcl::PointXYZ>(3.0 + 0.5 * i, -1.0 + 0.25 * i, i));
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  vts.setInputCloud(cloud);
  pcl::PolygonMesh mesh;
  mesh.polygons = stalePolygons();
  vts.reconstruct(mesh);
  EXPECT_TRUE(mesh.polygons.empty());
  EXPECT_EQ(vts.getLastStatus().code, StatusCode::ALL_COLLINEAR)
      << vts.getLastStatus().toString();
  EXPECT_EQ(vts.getDiagnostics().distinct_points, 20u);
}

TEST(VTSGridTriangulation, TooFewDistinctPointsIsAnError)
{
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->push_back(makePoint<pcl::PointXYZ>(0, 0, 0));
  cloud->push_back(makePoint<pcl::PointXYZ>(1, 0, 0));
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  EXPECT_TRUE(triangulate(vts, cloud).empty());
  EXPECT_EQ(vts.getLastStatus().code, StatusCode::TOO_FEW_POINTS);

  // Three points, but two share their XY.
  cloud->push_back(makePoint<pcl::PointXYZ>(1, 0, 5));
  EXPECT_TRUE(triangulate(vts, cloud).empty());
  EXPECT_EQ(vts.getLastStatus().code, StatusCode::TOO_FEW_POINTS);
  EXPECT_EQ(vts.getDiagnostics().duplicates_merged, 1u);

  // A third distinct point makes one triangle.
  cloud->push_back(makePoint<pcl::PointXYZ>(0, 1, 0));
  const auto polygons = triangulate(vts, cloud);
  EXPECT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
  EXPECT_EQ(polygons.size(), 1u);
  EXPECT_TRUE(isHullTriangulation(*cloud, {}, polygons, vts.getDiagnostics()));
}

TEST(VTSGridTriangulation, EmptyOrAllNonFiniteInputIsAnError)
{
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  EXPECT_TRUE(triangulate(vts, cloud).empty());
  EXPECT_EQ(vts.getLastStatus().code, StatusCode::EMPTY_INPUT);

  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < 5; ++i)
    cloud->push_back(makePoint<pcl::PointXYZ>(nan, i, 0));
  EXPECT_TRUE(triangulate(vts, cloud).empty());
  EXPECT_EQ(vts.getLastStatus().code, StatusCode::EMPTY_INPUT);
  EXPECT_EQ(vts.getDiagnostics().non_finite_dropped, 5u);
}

TEST(VTSGridTriangulation, NoInputCloudIsAnErrorNotACrash)
{
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  // Through the base class, as generic PCL code would call it.
  pcl::SurfaceReconstruction<pcl::PointXYZ>& base = vts;
  pcl::PolygonMesh mesh;
  mesh.polygons = stalePolygons();
  base.reconstruct(mesh);
  EXPECT_TRUE(mesh.polygons.empty());
  EXPECT_EQ(vts.getLastStatus().code, StatusCode::EMPTY_INPUT);
  EXPECT_NE(vts.getLastStatus().message.find("setInputCloud"), std::string::npos);

  pcl::PointCloud<pcl::PointXYZ> points;
  std::vector<pcl::Vertices> polygons = stalePolygons();
  base.reconstruct(points, polygons);
  EXPECT_TRUE(polygons.empty());
  EXPECT_TRUE(points.empty());
  EXPECT_EQ(vts.getLastStatus().code, StatusCode::EMPTY_INPUT);
}

TEST(VTSGridTriangulation, ReusedObjectForgetsThePreviousCloud)
{
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  const auto big = jitteredGrid<pcl::PointXYZ>(15, 15, 1.0, 0.0, 0.0, 23);
  const auto small = jitteredGrid<pcl::PointXYZ>(4, 3, 1.0, 0.0, 0.0, 29);
  EXPECT_TRUE(
      isHullTriangulation(*big, {}, triangulate(vts, big), vts.getDiagnostics()));
  EXPECT_TRUE(
      isHullTriangulation(*small, {}, triangulate(vts, small), vts.getDiagnostics()));
  EXPECT_EQ(vts.getDiagnostics().points_in, small->size());
}

TEST(VTSGridTriangulation, UtmFloatCloud)
{
  // 1 m spacing near (500 km E, 4100 km N): float keeps 1/32 m in x, 1/4 m in y.
  const auto cloud = jitteredGrid<pcl::PointXYZ>(40, 30, 1.0, 500000.0, 4100000.0, 31);
  std::set<XY> distinct;
  for (const auto& p : *cloud)
    distinct.insert(xyOf(p));
  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  const auto polygons = triangulate(vts, cloud);
  ASSERT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
  EXPECT_EQ(vts.getDiagnostics().distinct_points, distinct.size());
  EXPECT_TRUE(isHullTriangulation(*cloud, {}, polygons, vts.getDiagnostics()));
}

TEST(VTSGridTriangulation, RealTerrainSamp11)
{
  const std::string path =
      std::string(PCL_VTS_TEST_DATA_DIR) + "/samp11-utm-ground.pcd";
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  ASSERT_EQ(pcl::io::loadPCDFile<pcl::PointXYZ>(path, *cloud), 0) << path;
  ASSERT_GT(cloud->size(), 1000u);

  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  vts.setInputCloud(cloud);
  pcl::PolygonMesh mesh;
  vts.reconstruct(mesh);
  ASSERT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
  EXPECT_TRUE(isHullTriangulation(*cloud, {}, mesh.polygons, vts.getDiagnostics()));
  const pcl_vts::Diagnostics& diag = vts.getDiagnostics();
  EXPECT_EQ(diag.points_in, cloud->size());
  EXPECT_EQ(diag.distinct_points + diag.duplicates_merged + diag.non_finite_dropped,
            cloud->size());
}

// ---- Other point types ----------------------------------------------------------

template <typename PointT>
class VTSGridTriangulationTyped : public ::testing::Test {};

using PointTypes = ::testing::Types<pcl::PointXYZI, pcl::PointXYZRGB, pcl::PointXYZRGBA,
                                    pcl::PointNormal, pcl::PointXYZINormal,
                                    pcl::PointXYZRGBNormal, pcl::PointDEM>;
TYPED_TEST_SUITE(VTSGridTriangulationTyped, PointTypes, );

TYPED_TEST(VTSGridTriangulationTyped, JitteredGridWithIndicesAndMeanZ)
{
  auto cloud = jitteredGrid<TypeParam>(12, 10, 2.0, 100.0, 200.0, 37);
  // A duplicate of point 8 at another height: MEAN_Z writes the mean at point 8.
  const pcl::index_t first = 8;
  cloud->push_back(makePoint<TypeParam>((*cloud)[first].x, (*cloud)[first].y,
                                        (*cloud)[first].z + 2));
  const auto mean_z = static_cast<float>(
      (static_cast<double>((*cloud)[first].z) + static_cast<double>(cloud->back().z)) /
      2);
  pcl::IndicesPtr indices(new pcl::Indices);
  for (pcl::index_t i = 0; i < static_cast<pcl::index_t>(cloud->size()); ++i)
    if (i % 5 != 2) // drop some points; 8 and its duplicate (last) are kept
      indices->push_back(i);
  ASSERT_EQ(indices->back(), static_cast<pcl::index_t>(cloud->size()) - 1);

  pcl::VTSGridTriangulation<TypeParam> vts;
  vts.setDuplicateRule(pcl_vts::DuplicateRule::MEAN_Z);
  vts.setInputCloud(cloud);
  vts.setIndices(indices);
  pcl::PointCloud<TypeParam> points;
  std::vector<pcl::Vertices> polygons;
  vts.reconstruct(points, polygons);
  ASSERT_TRUE(vts.getLastStatus().ok()) << vts.getLastStatus().toString();
  EXPECT_EQ(vts.getDiagnostics().duplicates_merged, 1u);
  EXPECT_TRUE(isHullTriangulation(*cloud, *indices, polygons, vts.getDiagnostics()));
  EXPECT_EQ(usedIds(polygons).count(first), 1u);
  ASSERT_EQ(points.size(), cloud->size());
  EXPECT_EQ(points[first].z, mean_z);

  pcl::PolygonMesh mesh;
  vts.reconstruct(mesh);
  EXPECT_EQ(triangleSet(mesh.polygons), triangleSet(polygons));
  pcl::PointCloud<TypeParam> mesh_points;
  pcl::fromPCLPointCloud2(mesh.cloud, mesh_points);
  ASSERT_EQ(mesh_points.size(), cloud->size());
  EXPECT_EQ(mesh_points[first].z, mean_z);
}
