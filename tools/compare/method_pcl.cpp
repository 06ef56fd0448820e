// GP3 and Poisson rows (methods.h). All PCL surface/features templates live in this
// one translation unit: they are the slow part of the build.
#include "methods.h"

#include <pcl_vts/core/stopwatch.h>

#include <pcl/common/io.h>
#include <pcl/conversions.h>
#include <pcl/features/normal_3d.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/gp3.h>
#include <pcl/surface/poisson.h>

#include <sstream>

namespace pcl_vts {
namespace compare {
namespace {

std::string number(double value)
{
  std::ostringstream out;
  out.precision(4);
  out << value;
  return out.str();
}

/// pcl::NormalEstimation with k neighbours; normals flipped to point up (+z), as
/// terrain seen from above. Float coordinates in the local frame.
pcl::PointCloud<pcl::PointNormal>::Ptr estimateNormals(const PointSet& points, int k,
                                                       double& seconds)
{
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    (*cloud)[i] = pcl::PointXYZ(static_cast<float>(points.xyz[3 * i]),
                                static_cast<float>(points.xyz[3 * i + 1]),
                                static_cast<float>(points.xyz[3 * i + 2]));
  const Stopwatch watch;
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  estimation.setInputCloud(cloud);
  estimation.setSearchMethod(tree);
  estimation.setKSearch(k);
  pcl::PointCloud<pcl::Normal> normals;
  estimation.compute(normals);
  pcl::PointCloud<pcl::PointNormal>::Ptr result(new pcl::PointCloud<pcl::PointNormal>);
  pcl::concatenateFields(*cloud, normals, *result);
  for (pcl::PointNormal& p : *result) {
    if (!std::isfinite(p.normal_z)) { // too few distinct neighbours: say "up"
      p.normal_x = p.normal_y = 0.0f;
      p.normal_z = 1.0f;
    } else if (p.normal_z < 0.0f) {
      p.normal_x = -p.normal_x;
      p.normal_y = -p.normal_y;
      p.normal_z = -p.normal_z;
    }
  }
  seconds = watch.seconds();
  return result;
}

void copyPolygons(const std::vector<pcl::Vertices>& polygons, CompareMesh& mesh)
{
  mesh.triangles.clear();
  mesh.triangles.reserve(3 * polygons.size());
  for (const pcl::Vertices& polygon : polygons) // fans, should a polygon have > 3 ids
    for (std::size_t k = 2; k < polygon.vertices.size(); ++k)
      mesh.triangles.insert(mesh.triangles.end(),
                            {static_cast<std::uint32_t>(polygon.vertices[0]),
                             static_cast<std::uint32_t>(polygon.vertices[k - 1]),
                             static_cast<std::uint32_t>(polygon.vertices[k])});
}

Status runGp3(const PointSet& points, const MethodParameters& parameters,
              const pcl::PointCloud<pcl::PointNormal>::Ptr& cloud, CompareMesh& mesh,
              MethodReport& report)
{
  pcl::GreedyProjectionTriangulation<pcl::PointNormal> gp3;
  pcl::search::KdTree<pcl::PointNormal>::Ptr tree(
      new pcl::search::KdTree<pcl::PointNormal>);
  const double radius = gp3Radius(parameters);
  gp3.setSearchRadius(radius);
  gp3.setMu(parameters.gp3_mu);
  gp3.setMaximumNearestNeighbors(parameters.gp3_max_neighbours);
  gp3.setMaximumSurfaceAngle(M_PI / 4);
  gp3.setMinimumAngle(M_PI / 18);
  gp3.setMaximumAngle(2 * M_PI / 3);
  gp3.setNormalConsistency(false);
  gp3.setConsistentVertexOrdering(true);
  gp3.setInputCloud(cloud);
  gp3.setSearchMethod(tree);
  pcl::PolygonMesh out;
  const Stopwatch watch;
  gp3.reconstruct(out);
  report.seconds = watch.seconds();
  report.parameters = "search radius " + number(radius) + " (8 x spacing), mu " +
                      number(parameters.gp3_mu) + ", max neighbours " +
                      std::to_string(parameters.gp3_max_neighbours) +
                      ", angles 10-120 deg, max surface angle 45 deg, consistent "
                      "vertex ordering; normals k = " +
                      std::to_string(parameters.normal_k);
  mesh.xyz = points.xyz; // GP3's vertices are the input cloud, in order
  mesh.source.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    mesh.source[i] = static_cast<std::int32_t>(i);
  copyPolygons(out.polygons, mesh);
  return Status::success();
}

Status runPoisson(const MethodParameters& parameters,
                  const pcl::PointCloud<pcl::PointNormal>::Ptr& cloud,
                  CompareMesh& mesh, MethodReport& report)
{
  pcl::Poisson<pcl::PointNormal> poisson;
  const int depth = poissonDepth(parameters);
  poisson.setDepth(depth);
  poisson.setThreads(1);
  poisson.setInputCloud(cloud);
  pcl::PolygonMesh out;
  const Stopwatch watch;
  poisson.reconstruct(out);
  report.seconds = watch.seconds();
  report.parameters = "depth " + std::to_string(depth) +
                      ", degree 2, point weight 4, scale 1.1, samples per node 1, 1 "
                      "thread; normals k = " +
                      std::to_string(parameters.normal_k);
  pcl::PointCloud<pcl::PointXYZ> vertices;
  pcl::fromPCLPointCloud2(out.cloud, vertices);
  if (vertices.empty() || out.polygons.empty())
    return Status::error(StatusCode::INTERNAL_ERROR, "pcl::Poisson returned no mesh");
  mesh.xyz.resize(3 * vertices.size());
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    mesh.xyz[3 * v] = vertices[v].x;
    mesh.xyz[3 * v + 1] = vertices[v].y;
    mesh.xyz[3 * v + 2] = vertices[v].z;
  }
  mesh.source.assign(vertices.size(), -1); // new vertices, none is an input point
  copyPolygons(out.polygons, mesh);
  return Status::success();
}

} // namespace

Status runPclMethod(const std::string& name, const PointSet& points,
                    const MethodParameters& parameters, CompareMesh& mesh,
                    MethodReport& report)
{
  if (name != "gp3" && name != "poisson")
    return Status::error(StatusCode::INVALID_PARAMETER, "unknown PCL method " + name);
  const pcl::PointCloud<pcl::PointNormal>::Ptr cloud =
      estimateNormals(points, parameters.normal_k, report.normal_seconds);
  return name == "gp3" ? runGp3(points, parameters, cloud, mesh, report)
                       : runPoisson(parameters, cloud, mesh, report);
}

} // namespace compare
} // namespace pcl_vts
