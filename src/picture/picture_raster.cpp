// Z-buffered rasterisation. See picture_raster.h.
#include "picture_raster.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl_vts {
namespace picture_detail {

namespace {

/// Edge function of the segment p-q, always computed from its lexicographically
/// smaller end: the two triangles sharing an edge get exactly opposite values, so the
/// closed triangles of a mesh leave no sample uncovered (no cracks).
struct Edge {
  double ox, oy, ex, ey, sign;

  Edge(const ScreenPoint& p, const ScreenPoint& q, double orientation)
  {
    const bool forward = p.column < q.column || (p.column == q.column && p.row < q.row);
    const ScreenPoint& o = forward ? p : q;
    const ScreenPoint& e = forward ? q : p;
    ox = o.column;
    oy = o.row;
    ex = e.column - o.column;
    ey = e.row - o.row;
    sign = forward ? orientation : -orientation;
  }

  double at(double x, double y) const { return sign * (ex * (y - oy) - ey * (x - ox)); }
};

} // namespace

Raster::Raster(int width, int height, PictureColour background)
    : width_(width)
    , height_(height)
    , depth_(static_cast<std::size_t>(width) * height,
             std::numeric_limits<float>::infinity())
    , rgb_(3 * static_cast<std::size_t>(width) * height)
{
  for (std::size_t i = 0; i < rgb_.size(); i += 3) {
    rgb_[i] = background.r;
    rgb_[i + 1] = background.g;
    rgb_[i + 2] = background.b;
  }
}

bool Raster::mayCover(const ScreenPoint& a, const ScreenPoint& b,
                      const ScreenPoint& c) const
{
  const double lo_c = std::ceil(std::min({a.column, b.column, c.column}) - 0.5);
  const double hi_c = std::floor(std::max({a.column, b.column, c.column}) - 0.5);
  const double lo_r = std::ceil(std::min({a.row, b.row, c.row}) - 0.5);
  const double hi_r = std::floor(std::max({a.row, b.row, c.row}) - 0.5);
  return lo_c <= hi_c && lo_r <= hi_r && hi_c >= 0 && lo_c <= width_ - 1.0 &&
         hi_r >= 0 && lo_r <= height_ - 1.0;
}

void Raster::fillTriangle(const ScreenPoint& a, const ScreenPoint& b,
                          const ScreenPoint& c, PictureColour colour)
{
  const double area2 =
      (b.column - a.column) * (c.row - a.row) - (b.row - a.row) * (c.column - a.column);
  if (!(area2 != 0) || !std::isfinite(area2))
    return; // degenerate or non-finite: covers no sample
  const double lo_c =
      std::max(0.0, std::ceil(std::min({a.column, b.column, c.column}) - 0.5));
  const double hi_c = std::min(
      width_ - 1.0, std::floor(std::max({a.column, b.column, c.column}) - 0.5));
  const double lo_r = std::max(0.0, std::ceil(std::min({a.row, b.row, c.row}) - 0.5));
  const double hi_r =
      std::min(height_ - 1.0, std::floor(std::max({a.row, b.row, c.row}) - 0.5));
  if (lo_c > hi_c || lo_r > hi_r)
    return;
  const double orientation = area2 > 0 ? 1.0 : -1.0;
  const Edge e0(a, b, orientation), e1(b, c, orientation), e2(c, a, orientation);
  // Depth plane; clamped to the vertices' range so that slivers cannot extrapolate.
  const double ddx =
      ((b.depth - a.depth) * (c.row - a.row) - (c.depth - a.depth) * (b.row - a.row)) /
      area2;
  const double ddy = ((c.depth - a.depth) * (b.column - a.column) -
                      (b.depth - a.depth) * (c.column - a.column)) /
                     area2;
  const double d_lo = std::min({a.depth, b.depth, c.depth});
  const double d_hi = std::max({a.depth, b.depth, c.depth});
  const int c0 = static_cast<int>(lo_c), c1 = static_cast<int>(hi_c);
  const int r0 = static_cast<int>(lo_r), r1 = static_cast<int>(hi_r);
  for (int r = r0; r <= r1; ++r) {
    const double y = r + 0.5;
    for (int col = c0; col <= c1; ++col) {
      const double x = col + 0.5;
      if (e0.at(x, y) < 0 || e1.at(x, y) < 0 || e2.at(x, y) < 0)
        continue;
      const double d =
          std::clamp(a.depth + ddx * (x - a.column) + ddy * (y - a.row), d_lo, d_hi);
      const std::size_t i = static_cast<std::size_t>(r) * width_ + col;
      if (static_cast<float>(d) < depth_[i]) {
        depth_[i] = static_cast<float>(d);
        rgb_[3 * i] = colour.r;
        rgb_[3 * i + 1] = colour.g;
        rgb_[3 * i + 2] = colour.b;
      }
    }
  }
}

void Raster::stamp(int column, int row, double depth, PictureColour colour)
{
  if (column < 0 || row < 0 || column >= width_ || row >= height_)
    return;
  const std::size_t i = static_cast<std::size_t>(row) * width_ + column;
  if (!(depth <= depth_[i]))
    return;
  rgb_[3 * i] = colour.r;
  rgb_[3 * i + 1] = colour.g;
  rgb_[3 * i + 2] = colour.b;
}

void Raster::drawLine(ScreenPoint a, ScreenPoint b, int brush, double depth_bias,
                      PictureColour colour)
{
  // Clip to the raster plus the brush (Liang-Barsky), so that an edge running far
  // outside costs no steps.
  const double dc = b.column - a.column, dr = b.row - a.row;
  double t0 = 0, t1 = 1;
  const double p[4] = {-dc, dc, -dr, dr};
  const double q[4] = {a.column + brush, width_ + brush - a.column, a.row + brush,
                       height_ + brush - a.row};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0)
        return;
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0)
      t0 = std::max(t0, t);
    else
      t1 = std::min(t1, t);
  }
  if (!(t0 <= t1))
    return; // outside, or NaN
  const double steps = std::ceil(std::max(std::abs(dc), std::abs(dr)) * (t1 - t0)) + 1;
  const double half = 0.5 * brush - 0.5;
  for (double k = 0; k <= steps; ++k) {
    const double t = t0 + (t1 - t0) * (k / steps);
    const double col = a.column + t * dc, row = a.row + t * dr;
    const double depth = a.depth + t * (b.depth - a.depth) - depth_bias;
    const int c0 = static_cast<int>(std::floor(col - half));
    const int r0 = static_cast<int>(std::floor(row - half));
    for (int y = r0; y < r0 + brush; ++y)
      for (int x = c0; x < c0 + brush; ++x)
        stamp(x, y, depth, colour);
  }
}

void Raster::drawDot(const ScreenPoint& p, double radius, double depth_bias,
                     PictureColour colour)
{
  if (!(p.column > -radius && p.column < width_ + radius && p.row > -radius &&
        p.row < height_ + radius))
    return;
  const int c0 = static_cast<int>(std::floor(p.column - radius));
  const int r0 = static_cast<int>(std::floor(p.row - radius));
  const int n = static_cast<int>(std::ceil(2 * radius)) + 1;
  for (int y = r0; y <= r0 + n; ++y)
    for (int x = c0; x <= c0 + n; ++x) {
      const double ux = x + 0.5 - p.column, uy = y + 0.5 - p.row;
      if (ux * ux + uy * uy <= radius * radius)
        stamp(x, y, p.depth - depth_bias, colour);
    }
}

Picture Raster::downsample(int factor) const
{
  Picture out;
  out.width = width_ / factor;
  out.height = height_ / factor;
  out.rgb.resize(3 * static_cast<std::size_t>(out.width) * out.height);
  const int n = factor * factor;
  for (int r = 0; r < out.height; ++r)
    for (int c = 0; c < out.width; ++c)
      for (int k = 0; k < 3; ++k) {
        int sum = 0;
        for (int sy = 0; sy < factor; ++sy)
          for (int sx = 0; sx < factor; ++sx)
            sum += rgb_[3 * ((static_cast<std::size_t>(r) * factor + sy) * width_ +
                             static_cast<std::size_t>(c) * factor + sx) +
                        k];
        out.rgb[3 * (static_cast<std::size_t>(r) * out.width + c) + k] =
            static_cast<std::uint8_t>((sum + n / 2) / n);
      }
  return out;
}

} // namespace picture_detail
} // namespace pcl_vts
