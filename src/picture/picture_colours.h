// The palette of renderMesh: a hypsometric ramp by height, hill shading, class tints.
// Kept apart from the red, magenta, orange and near-black that mark edges, flips and
// points, so that those stay recognisable (the tests look for them exactly).
#pragma once

#include <pcl_vts/picture/image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace pcl_vts {
namespace picture_detail {
namespace colours {

constexpr PictureColour REMOVED_GREY{175, 175, 175};
constexpr PictureColour FILLED_BLUE{60, 110, 235};
/// Hypsometric tint: lowland green, tan, brown, pale summits (no red, magenta or
/// orange, which mark edges and flips).
inline PictureColour rampColour(double t)
{
  static const std::array<std::array<double, 4>, 5> stops = {{{0.00, 60, 125, 85},
                                                              {0.30, 145, 175, 95},
                                                              {0.55, 220, 205, 135},
                                                              {0.80, 165, 125, 90},
                                                              {1.00, 235, 230, 220}}};
  t = std::clamp(t, 0.0, 1.0);
  std::size_t k = 1;
  while (k + 1 < stops.size() && t > stops[k][0])
    ++k;
  const auto& a = stops[k - 1];
  const auto& b = stops[k];
  const double f = (t - a[0]) / (b[0] - a[0]);
  auto mix = [&](int i) {
    return static_cast<std::uint8_t>(a[i] + f * (b[i] - a[i]) + 0.5);
  };
  return {mix(1), mix(2), mix(3)};
}

inline PictureColour shaded(PictureColour c, double factor)
{
  auto s = [&](std::uint8_t v) {
    return static_cast<std::uint8_t>(std::min(255.0, v * factor + 0.5));
  };
  return {s(c.r), s(c.g), s(c.b)};
}

inline PictureColour blend(PictureColour a, PictureColour b, double share_of_b)
{
  auto m = [&](std::uint8_t x, std::uint8_t y) {
    return static_cast<std::uint8_t>(x + share_of_b * (y - x) + 0.5);
  };
  return {m(a.r, b.r), m(a.g, b.g), m(a.b, b.b)};
}

/// Lambert term for light from the north-west, 45 degrees up (cartographic hillshade).
inline double hillshade(double nx, double ny, double nz)
{
  return std::max(0.0, -0.5 * nx + 0.5 * ny + M_SQRT1_2 * nz);
}

} // namespace colours
} // namespace picture_detail
} // namespace pcl_vts
