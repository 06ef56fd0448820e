// Area-weighted sample points on a mesh, as Metro does: the expected number of samples
// on a triangle is proportional to its 3D area, so every sample stands for the same
// area and plain means over samples are area-weighted means. Systematic sampling (one
// random start, then equal steps along the cumulated area) gives each triangle its
// share to within one sample; positions inside a triangle are uniform (seeded).
// PCL-free.
#pragma once

#include "compare_mesh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace compare {

struct SurfaceSamples {
  std::vector<double> xyz;             ///< 3 per sample
  std::vector<std::uint32_t> triangle; ///< the triangle each sample lies on
  double total_area = 0.0;             ///< 3D area of the mesh
  std::size_t size() const { return triangle.size(); }
  /// Area each sample stands for.
  double areaPerSample() const
  {
    return size() ? total_area / static_cast<double>(size()) : 0.0;
  }
};

/// About per_triangle samples per triangle on average (per_triangle * triangles in
/// all, at most max_samples; 0 = no cap), area-weighted. Zero-area triangles get none.
SurfaceSamples sampleSurface(const CompareMesh& mesh, double per_triangle,
                             std::size_t max_samples, std::uint64_t seed);

/// 3D area of triangle t.
double triangleArea(const CompareMesh& mesh, std::size_t t);

} // namespace compare
} // namespace pcl_vts
