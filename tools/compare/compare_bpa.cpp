// compare_bpa: the Ball-Pivoting row of compare_methods, in its own executable so that
// Open3D (its own Eigen build flags, fmt, GL stubs) never shares a binary with PCL.
// Usage: compare_bpa POINTS.bin MESH.ply REPORT.txt NORMAL_K R1[,R2,...]
//        compare_bpa --idle POINTS.bin (reads the points and exits: memory baseline)
// Exit: 0 done, 1 usage, 2 input unreadable, 5 Open3D failed.
#include "compare_files.h"
#include "method_report.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/TriangleMesh.h>
#include <open3d/utility/Logging.h>
#include <sstream>
#include <string>
#include <vector>

namespace {

using pcl_vts::compare::CompareMesh;
using pcl_vts::compare::MethodReport;
using pcl_vts::compare::PointSet;

double secondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

bool parseRadii(const std::string& text, std::vector<double>& radii)
{
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double r = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !(r > 0.0))
      return false;
    radii.push_back(r);
  }
  return !radii.empty();
}

int run(int argc, char** argv)
{
  if (argc == 3 && std::string(argv[1]) == "--idle") { // baseline memory
    PointSet points;
    return pcl_vts::compare::readPointSet(argv[2], points).ok() ? 0 : 2;
  }
  std::vector<double> radii;
  const int k = argc == 6 ? std::atoi(argv[4]) : 0;
  if (argc != 6 || k < 3 || !parseRadii(argv[5], radii)) {
    std::fprintf(stderr, "usage: compare_bpa POINTS.bin MESH.ply REPORT.txt NORMAL_K "
                         "R1[,R2,...]\n");
    return 1;
  }
  PointSet points;
  if (pcl_vts::Status s = pcl_vts::compare::readPointSet(argv[1], points); !s.ok()) {
    std::fprintf(stderr, "compare_bpa: error: %s\n", s.toString().c_str());
    return 2;
  }
  open3d::utility::SetVerbosityLevel(open3d::utility::VerbosityLevel::Warning);
  open3d::geometry::PointCloud cloud;
  cloud.points_.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    cloud.points_[i] = Eigen::Vector3d(&points.xyz[3 * i]);
  MethodReport report;
  auto start = std::chrono::steady_clock::now();
  cloud.EstimateNormals(open3d::geometry::KDTreeSearchParamKNN(k));
  cloud.OrientNormalsToAlignWithDirection(Eigen::Vector3d(0.0, 0.0, 1.0));
  report.normal_seconds = secondsSince(start);
  start = std::chrono::steady_clock::now();
  const std::shared_ptr<open3d::geometry::TriangleMesh> mesh =
      open3d::geometry::TriangleMesh::CreateFromPointCloudBallPivoting(cloud, radii);
  report.seconds = secondsSince(start);
  std::ostringstream parameters;
  parameters.precision(4);
  parameters << "radii";
  for (double r : radii)
    parameters << " " << r;
  parameters << " (1, 2, 4 x spacing); normals: Open3D EstimateNormals k = " << k
             << ", oriented to +z";
  report.parameters = parameters.str();
  CompareMesh out;
  out.xyz.resize(3 * mesh->vertices_.size());
  for (std::size_t v = 0; v < mesh->vertices_.size(); ++v)
    for (int c = 0; c < 3; ++c)
      out.xyz[3 * v + c] = mesh->vertices_[v][c];
  // Open3D keeps the input cloud as the vertex list, in order.
  const bool same_vertices = mesh->vertices_.size() == points.size();
  out.source.resize(mesh->vertices_.size(), -1);
  if (same_vertices)
    for (std::size_t v = 0; v < points.size(); ++v)
      out.source[v] = static_cast<std::int32_t>(v);
  else
    report.notes.push_back("Open3D returned " + std::to_string(mesh->vertices_.size()) +
                           " vertices for " + std::to_string(points.size()) +
                           " points: unused points not counted");
  for (const Eigen::Vector3i& t : mesh->triangles_)
    for (int c = 0; c < 3; ++c)
      out.triangles.push_back(static_cast<std::uint32_t>(t[c]));
  if (pcl_vts::Status s = pcl_vts::compare::writeMeshPly(argv[2], out); !s.ok()) {
    std::fprintf(stderr, "compare_bpa: error: %s\n", s.toString().c_str());
    return 5;
  }
  if (pcl_vts::Status s = pcl_vts::compare::writeMethodReport(argv[3], report);
      !s.ok()) {
    std::fprintf(stderr, "compare_bpa: error: %s\n", s.toString().c_str());
    return 5;
  }
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "compare_bpa: error: %s\n", e.what());
    return 5;
  }
}
