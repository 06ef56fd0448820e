// The README's program: read a PCD file, triangulate it with pcl::VTSGridTriangulation
// (exactly the Delaunay triangulation of the XY projection), print the counts, and
// save the mesh as binary PLY when asked.
//   usage: triangulate_pcd INPUT.pcd [OUTPUT.ply]
#include <pcl_vts/vts_grid_triangulation.h>

#include <pcl/PolygonMesh.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <iostream>

int main(int argc, char** argv)
{
  if (argc < 2 || argc > 3) {
    std::cerr << "usage: triangulate_pcd INPUT.pcd [OUTPUT.ply]\n";
    return 2;
  }
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  if (pcl::io::loadPCDFile(argv[1], *cloud) != 0) {
    std::cerr << "cannot read " << argv[1] << "\n";
    return 1;
  }

  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  vts.setInputCloud(cloud);
  vts.setDuplicateRule(pcl_vts::DuplicateRule::LOWEST_Z); // optional
  pcl::PolygonMesh mesh;
  vts.reconstruct(mesh);
  if (!vts.getLastStatus().ok()) {
    std::cerr << vts.getLastStatus().toString() << "\n"; // e.g. ALL_COLLINEAR: ...
    return 1;
  }
  const pcl_vts::Diagnostics& d = vts.getDiagnostics(); // counts and timings
  std::cout << "points " << cloud->size() << "\ndistinct points " << d.distinct_points
            << "\nhull vertices " << d.hull_vertices << "\ntriangles "
            << mesh.polygons.size() << "\n";

  if (argc == 3 && pcl::io::savePLYFileBinary(argv[2], mesh) != 0) {
    std::cerr << "cannot write " << argv[2] << "\n";
    return 1;
  }
  return 0;
}
