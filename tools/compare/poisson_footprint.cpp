// Trimming a Poisson mesh to the data footprint (poisson_footprint.h), with a 2D
// kd-tree (PCL's over x, y, z = 0).
#include "poisson_footprint.h"
#include "surface_samples.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl_vts {
namespace compare {

FootprintTrim trimToFootprint(CompareMesh& mesh, const PointSet& input, double spacing,
                              double factor)
{
  FootprintTrim trim;
  trim.threshold = factor * spacing;
  const std::size_t nt = mesh.triangleCount();
  trim.triangles_before = nt;
  for (int k = 0; k < 3; ++k) {
    trim.box_min[k] = std::numeric_limits<double>::infinity();
    trim.box_max[k] = -std::numeric_limits<double>::infinity();
  }
  for (std::uint32_t v : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      trim.box_min[k] = std::min(trim.box_min[k], mesh.xyz[3 * v + k]);
      trim.box_max[k] = std::max(trim.box_max[k], mesh.xyz[3 * v + k]);
    }
  pcl::PointCloud<pcl::PointXYZ>::Ptr flat(new pcl::PointCloud<pcl::PointXYZ>);
  flat->resize(input.size());
  for (std::size_t i = 0; i < input.size(); ++i)
    (*flat)[i] = pcl::PointXYZ(static_cast<float>(input.xyz[3 * i]),
                               static_cast<float>(input.xyz[3 * i + 1]), 0.0f);
  if (flat->empty())
    return trim;
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(flat);
  std::vector<int> ids(1);
  std::vector<float> d2(1);
  std::vector<std::uint32_t> kept;
  kept.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < nt; ++t) {
    double c[2] = {0.0, 0.0};
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 2; ++j)
        c[j] += mesh.xyz[3 * mesh.triangles[3 * t + k] + j] / 3.0;
    tree.nearestKSearch(
        pcl::PointXYZ(static_cast<float>(c[0]), static_cast<float>(c[1]), 0.0f), 1, ids,
        d2);
    const double* q = &input.xyz[3 * static_cast<std::size_t>(ids[0])];
    const double distance = std::hypot(c[0] - q[0], c[1] - q[1]);
    trim.max_centroid_distance = std::max(trim.max_centroid_distance, distance);
    const double area = triangleArea(mesh, t);
    trim.area_before += area;
    if (distance <= trim.threshold)
      kept.insert(kept.end(), mesh.triangles.begin() + static_cast<long>(3 * t),
                  mesh.triangles.begin() + static_cast<long>(3 * t + 3));
    else
      trim.area_cut += area;
  }
  mesh.triangles.swap(kept);
  trim.triangles_after = mesh.triangleCount();
  return trim;
}

} // namespace compare
} // namespace pcl_vts
