// Systematic area-weighted sampling (surface_samples.h).
#include "surface_samples.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace pcl_vts {
namespace compare {

double triangleArea(const CompareMesh& mesh, std::size_t t)
{
  const double* a = &mesh.xyz[3 * mesh.triangles[3 * t]];
  const double* b = &mesh.xyz[3 * mesh.triangles[3 * t + 1]];
  const double* c = &mesh.xyz[3 * mesh.triangles[3 * t + 2]];
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

SurfaceSamples sampleSurface(const CompareMesh& mesh, double per_triangle,
                             std::size_t max_samples, std::uint64_t seed)
{
  SurfaceSamples samples;
  const std::size_t nt = mesh.triangleCount();
  std::vector<double> area(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    area[t] = triangleArea(mesh, t);
    if (!std::isfinite(area[t]))
      area[t] = 0.0;
    samples.total_area += area[t];
  }
  std::size_t count =
      static_cast<std::size_t>(std::llround(per_triangle * static_cast<double>(nt)));
  if (max_samples > 0)
    count = std::min(count, max_samples);
  if (count == 0 || !(samples.total_area > 0.0))
    return samples;
  std::mt19937_64 engine(seed);
  auto uniform = [&] { return static_cast<double>(engine() >> 11) * 0x1p-53; };
  const double step = samples.total_area / static_cast<double>(count);
  double next = uniform() * step; // cumulated area of the next sample
  double cumulated = 0.0;
  samples.xyz.reserve(3 * count + 3);
  samples.triangle.reserve(count + 1);
  for (std::size_t t = 0; t < nt && samples.size() < count; ++t) {
    const double end = cumulated + area[t];
    const double* a = &mesh.xyz[3 * mesh.triangles[3 * t]];
    const double* b = &mesh.xyz[3 * mesh.triangles[3 * t + 1]];
    const double* c = &mesh.xyz[3 * mesh.triangles[3 * t + 2]];
    while (next < end && samples.size() < count) {
      // Uniform in the triangle: sqrt(r1) folds the unit square onto it.
      const double r1 = std::sqrt(uniform()), r2 = uniform();
      const double wa = 1.0 - r1, wb = r1 * (1.0 - r2), wc = r1 * r2;
      for (int k = 0; k < 3; ++k)
        samples.xyz.push_back(wa * a[k] + wb * b[k] + wc * c[k]);
      samples.triangle.push_back(static_cast<std::uint32_t>(t));
      next += step;
    }
    cumulated = end;
  }
  return samples;
}

} // namespace compare
} // namespace pcl_vts
