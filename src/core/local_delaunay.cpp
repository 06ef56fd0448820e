#include "local_delaunay.h"

#include <pcl_vts/core/predicates.h>

#include <algorithm>
#include <cmath>

namespace pcl_vts {
namespace detail {

bool LocalDelaunay::triangulate(const CellGrid& grid, const CellWindow& w,
                                const CellWindow& core)
{
  const double c = grid.cell_size;
  const double x0 = grid.origin_x + w.i0 * c, x1 = grid.origin_x + w.i1 * c;
  const double y0 = grid.origin_y + w.j0 * c, y1 = grid.origin_y + w.j1 * c;
  const double cx = 0.5 * x0 + 0.5 * x1, cy = 0.5 * y0 + 0.5 * y1;
  // Points may sit a slack outside their cells: the super triangle is far wider.
  const double d = std::max(x1 - x0, y1 - y0) + c + std::fabs(cx) * 0x1p-40 +
                   std::fabs(cy) * 0x1p-40;
  p.clear();
  p.push_back({cx - 10.0 * d, cy - 10.0 * d});
  p.push_back({cx + 10.0 * d, cy - 10.0 * d});
  p.push_back({cx, cy + 10.0 * d});
  for (const Point2& s : p)
    if (!std::isfinite(s.x) || !std::isfinite(s.y))
      return false;
  v.assign({0, 1, 2});
  adj.assign({-1, -1, -1});
  if (stamp_.empty())
    stamp_.resize(1);
  stamp_[0] = 0;
  last_ = 0;
  ids.assign(3, INVALID_ID);
  in_core.assign(3, 0);
  for (std::uint32_t stride = 4; stride >= 1; stride /= 2)
    for (std::uint32_t j = w.j0; j < w.j1; ++j) {
      const bool forward = ((j - w.j0) & 1u) == 0;
      for (std::uint32_t m = 0; m < w.i1 - w.i0; ++m) {
        const std::uint32_t i = forward ? w.i0 + m : w.i1 - 1 - m;
        const std::uint32_t di = i - w.i0, dj = j - w.j0;
        if (di % stride != 0 || dj % stride != 0 ||
            (stride < 4 && di % (2 * stride) == 0 && dj % (2 * stride) == 0))
          continue;
        const CellId cell = grid.cellId(i, j);
        const std::uint8_t inside =
            i >= core.i0 && i < core.i1 && j >= core.j0 && j < core.j1 ? 1 : 0;
        for (std::uint32_t k = grid.cell_start[cell]; k < grid.cell_start[cell + 1];
             ++k) {
          ids.push_back(k);
          in_core.push_back(inside);
          p.push_back(grid.points[k]);
          insert(static_cast<std::int32_t>(p.size() - 1));
        }
      }
    }
  return true;
}

void LocalDelaunay::insert(std::int32_t k)
{
  const Point2 q = p[static_cast<std::size_t>(k)];
  if (head_.size() < p.size())
    head_.resize(2 * p.size());
  // Visibility walk from the last new triangle (it ends in a Delaunay mesh); the edge
  // it came in by is not tested again.
  std::int32_t t = last_;
  int entry = -1;
  for (;;) {
    int e = 0;
    for (; e < 3; ++e) {
      if (e == entry)
        continue;
      const Point2& a =
          p[static_cast<std::size_t>(v[static_cast<std::size_t>(3 * t + e)])];
      const Point2& b =
          p[static_cast<std::size_t>(v[static_cast<std::size_t>(3 * t + (e + 1) % 3)])];
      if (orient2d(a, b, q) == Sign::NEGATIVE)
        break;
    }
    if (e == 3)
      break;
    const std::int32_t o = adj[static_cast<std::size_t>(3 * t + e)];
    t = o / 3;
    entry = o % 3;
  }
  // Cavity: every triangle whose perturbed circumcircle holds q, grown from t.
  stamp_counter_ += 2;
  const std::uint32_t bad_mark = stamp_counter_, good_mark = stamp_counter_ + 1;
  bad_.clear();
  boundary_.clear();
  bad_.push_back(t);
  stamp_[static_cast<std::size_t>(t)] = bad_mark;
  for (std::size_t i = 0; i < bad_.size(); ++i) {
    const std::int32_t b = bad_[i];
    for (int e = 0; e < 3; ++e) {
      const auto h = static_cast<std::size_t>(3 * b + e);
      const std::int32_t o = adj[h];
      if (o >= 0) {
        const auto n = static_cast<std::size_t>(o / 3);
        std::uint32_t& s = stamp_[n];
        if (s == bad_mark)
          continue;
        if (s != good_mark) {
          if (incirclePerturbed(p[static_cast<std::size_t>(v[3 * n])],
                                p[static_cast<std::size_t>(v[3 * n + 1])],
                                p[static_cast<std::size_t>(v[3 * n + 2])],
                                q) == Sign::POSITIVE) {
            s = bad_mark;
            bad_.push_back(static_cast<std::int32_t>(n));
            continue;
          }
          s = good_mark;
        }
      }
      boundary_.push_back({v[h], v[static_cast<std::size_t>(3 * b + (e + 1) % 3)], o});
    }
  }
  // The star of q over the cavity boundary: the cavity's slots first, then new ones.
  const std::size_t first_new = v.size() / 3;
  const auto slot = [&](std::size_t j) {
    return j < bad_.size() ? bad_[j]
                           : static_cast<std::int32_t>(first_new + (j - bad_.size()));
  };
  if (boundary_.size() > bad_.size()) {
    const std::size_t added = boundary_.size() - bad_.size();
    v.resize(v.size() + 3 * added);
    adj.resize(adj.size() + 3 * added);
    stamp_.resize(stamp_.size() + added, 0);
  }
  for (std::size_t j = 0; j < boundary_.size(); ++j) {
    const auto s = static_cast<std::size_t>(slot(j));
    const std::array<std::int32_t, 3>& edge = boundary_[j];
    v[3 * s] = edge[0];
    v[3 * s + 1] = edge[1];
    v[3 * s + 2] = k;
    adj[3 * s] = edge[2];
    if (edge[2] >= 0)
      adj[static_cast<std::size_t>(edge[2])] = static_cast<std::int32_t>(3 * s);
    head_[static_cast<std::size_t>(edge[0])] = static_cast<std::int32_t>(s);
  }
  for (std::size_t j = 0; j < boundary_.size(); ++j) {
    const std::int32_t t1 = slot(j);
    const std::int32_t t2 =
        head_[static_cast<std::size_t>(v[static_cast<std::size_t>(3 * t1 + 1)])];
    adj[static_cast<std::size_t>(3 * t1 + 1)] = 3 * t2 + 2;
    adj[static_cast<std::size_t>(3 * t2 + 2)] = 3 * t1 + 1;
  }
  last_ = slot(boundary_.size() - 1);
}

bool LocalDelaunay::finalTriangle(std::size_t t, double x_lo, double x_hi, double y_lo,
                                  double y_hi) const
{
  // The circumdisk grown by a bound on its rounding (boundCircumdisk of the tiled
  // path, src/tiling/known_space.cpp); a flat triangle proves nothing.
  const Point2& a = p[static_cast<std::size_t>(v[3 * t])];
  const Point2& b = p[static_cast<std::size_t>(v[3 * t + 1])];
  const Point2& c = p[static_cast<std::size_t>(v[3 * t + 2])];
  const double bx = b.x - a.x, by = b.y - a.y;
  const double cx = c.x - a.x, cy = c.y - a.y;
  const double t1 = bx * cy, t2 = by * cx;
  const double det = 2.0 * (t1 - t2);
  if (!(std::fabs(det) > 1e-6 * (std::fabs(t1) + std::fabs(t2))) || !std::isfinite(det))
    return false;
  const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  const double ux = (cy * b2 - by * c2) / det;
  const double uy = (bx * c2 - cx * b2) / det;
  const double r0 = std::sqrt(ux * ux + uy * uy);
  const double r = r0 + 1e-7 * (r0 + std::sqrt(b2) + std::sqrt(c2)) +
                   1e-15 * (std::fabs(a.x) + std::fabs(a.y));
  const double mx = a.x + ux, my = a.y + uy;
  return std::isfinite(r) && mx - r > x_lo && mx + r < x_hi && my - r > y_lo &&
         my + r < y_hi;
}

} // namespace detail
} // namespace pcl_vts
