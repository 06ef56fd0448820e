// Synthetic terrain (synthetic_terrain.h).
#include "synthetic_terrain.h"

#include <cmath>
#include <random>

namespace pcl_vts {
namespace compare {

double syntheticHeight(double x, double y)
{
  const double hills = 12.0 * std::sin(x / 63.0) * std::cos(y / 47.0) +
                       6.0 * std::sin((x + 2.0 * y) / 37.0);
  const double peak1 =
      15.0 * std::exp(-((x - 150.0) * (x - 150.0) + (y - 120.0) * (y - 120.0)) /
                      (2.0 * 40.0 * 40.0));
  const double peak2 =
      -10.0 * std::exp(-((x - 260.0) * (x - 260.0) + (y - 230.0) * (y - 230.0)) /
                       (2.0 * 25.0 * 25.0));
  const double ripple = 0.3 * std::sin(x / 3.1) * std::sin(y / 3.7);
  return 300.0 + hills + peak1 + peak2 + ripple;
}

double syntheticSide(std::size_t n)
{
  return std::sqrt(static_cast<double>(n));
}

PointSet syntheticTerrain(std::size_t n, std::uint64_t seed)
{
  PointSet points;
  points.offset[0] = SYNTHETIC_ORIGIN_X;
  points.offset[1] = SYNTHETIC_ORIGIN_Y;
  points.offset[2] = 0.0;
  std::mt19937_64 engine(seed * 0x9E3779B97F4A7C15ull + 7);
  const double side = syntheticSide(n);
  auto uniform = [&] { return static_cast<double>(engine() >> 11) * 0x1p-53 * side; };
  points.xyz.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = uniform(), y = uniform();
    points.xyz.push_back(x);
    points.xyz.push_back(y);
    points.xyz.push_back(syntheticHeight(x, y));
  }
  return points;
}

} // namespace compare
} // namespace pcl_vts
