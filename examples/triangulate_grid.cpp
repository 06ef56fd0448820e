// The smallest pcl_vts program: a 30 x 20 grid of points made in memory, triangulated
// by pcl::VTSGridTriangulation. It links pcl_vts::pcl_vts only (no PCL io): neither
// VTK nor GDAL is loaded. Exits 1 unless the mesh has the 2n - h - 2 triangles of the
// Delaunay triangulation of n points with h on the hull (here 2*600 - 96 - 2 = 1102;
// the grid is all cocircular ties, which the exact predicates break consistently).
#include <pcl_vts/vts_grid_triangulation.h>

#include <pcl/PolygonMesh.h>
#include <pcl/point_types.h>

#include <iostream>

int main()
{
  constexpr int COLUMNS = 30, ROWS = 20;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (int j = 0; j < ROWS; ++j)
    for (int i = 0; i < COLUMNS; ++i)
      cloud->push_back(pcl::PointXYZ(static_cast<float>(i), static_cast<float>(j),
                                     static_cast<float>((i * j) % 7)));

  pcl::VTSGridTriangulation<pcl::PointXYZ> vts;
  vts.setInputCloud(cloud);
  pcl::PolygonMesh mesh;
  vts.reconstruct(mesh);
  if (!vts.getLastStatus().ok()) {
    std::cerr << vts.getLastStatus().toString() << "\n";
    return 1;
  }
  const std::size_t n = COLUMNS * ROWS, h = 2 * (COLUMNS + ROWS) - 4;
  std::cout << "triangles " << mesh.polygons.size() << " (expected " << 2 * n - h - 2
            << ")\n";
  return mesh.polygons.size() == 2 * n - h - 2 ? 0 : 1;
}
