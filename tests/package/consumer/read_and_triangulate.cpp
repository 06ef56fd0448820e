// A user of the readers without PCL in sight: pcl_vts::io reads a file (a PCD goes
// through pcl_io inside the library), the core triangulates it. Prints the counts the
// package test compares with triangulate_pcd's; exit 1 unless the mesh has the
// 2n - h - 2 triangles of the Delaunay triangulation of n points with h on the hull.
//   usage: read_and_triangulate INPUT
#include <pcl_vts/core/vts_pipeline.h>
#include <pcl_vts/io/point_cloud_loader.h>

#include <iostream>
#include <vector>

int main(int argc, char** argv)
{
  if (argc != 2) {
    std::cerr << "usage: read_and_triangulate INPUT\n";
    return 2;
  }
  std::vector<double> xyz;
  pcl_vts::CloudDescription description;
  pcl_vts::Status status = pcl_vts::loadPointCloud(argv[1], {}, xyz, description);
  pcl_vts::VtsResult result;
  if (status.ok())
    status = pcl_vts::runVtsPipeline(xyz.data(), xyz.size() / 3, {}, result);
  if (!status.ok()) {
    std::cerr << status.toString() << "\n";
    return 1;
  }
  const std::size_t n = result.diagnostics.distinct_points;
  const std::size_t h = result.diagnostics.hull_vertices;
  const std::size_t triangles = result.mesh.triangleCount();
  std::cout << "points " << description.points_kept << "\ndistinct points " << n
            << "\nhull vertices " << h << "\ntriangles " << triangles << "\n";
  return triangles > 0 && triangles == 2 * n - h - 2 ? 0 : 1;
}
