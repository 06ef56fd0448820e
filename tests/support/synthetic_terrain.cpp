// See synthetic_terrain.h.
#include "support/synthetic_terrain.h"

#include <cmath>
#include <random>

namespace pcl_vts {
namespace test {

double SyntheticTerrain::height(double x, double y)
{
  return 20.0 * std::sin(x / 40.0) * std::cos(y / 55.0) +
         5.0 * std::sin((x + y) / 25.0) + 0.02 * x;
}

bool SyntheticTerrain::inFootprint(double x, double y) const
{
  if (x < 0.0 || y < 0.0 || x > size || y > size)
    return false;
  if (x > notch_x0 && x < notch_x1 && y > notch_y0)
    return false;
  for (const Disc& d : voids)
    if (std::hypot(x - d.cx, y - d.cy) < d.r)
      return false;
  return true;
}

SyntheticTerrain makeSyntheticTerrain(std::uint64_t seed)
{
  SyntheticTerrain t;
  t.size = 400.0;
  t.notch_x0 = 150.0;
  t.notch_x1 = 250.0;
  t.notch_y0 = 250.0;
  t.voids = {{60, 60, 2}, {120, 60, 3}, {200, 70, 6}, {300, 90, 10}, {80, 250, 25}};
  std::mt19937_64 rng(seed);
  auto jitter = [&rng]() {
    // 53 random bits -> [0, 1): platform independent, unlike std distributions.
    return static_cast<double>(rng() >> 11) * 0x1p-53 * 0.6 - 0.3;
  };
  for (int j = 0; j < 400; ++j)
    for (int i = 0; i < 400; ++i) {
      const double x = i + 0.5 + jitter();
      const double y = j + 0.5 + jitter();
      if (!t.inFootprint(x, y))
        continue;
      t.xyz.push_back(x);
      t.xyz.push_back(y);
      t.xyz.push_back(SyntheticTerrain::height(x, y));
    }
  return t;
}

} // namespace test
} // namespace pcl_vts
