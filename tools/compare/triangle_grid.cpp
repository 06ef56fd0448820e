// Uniform XY grid of triangles (triangle_grid.h).
#include "triangle_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl_vts {
namespace compare {
namespace {

double dot(const double* a, const double* b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void sub(const double* a, const double* b, double* out)
{
  for (int k = 0; k < 3; ++k)
    out[k] = a[k] - b[k];
}

double distanceTo(const double* p, const double* q)
{
  double d[3];
  sub(p, q, d);
  return std::sqrt(dot(d, d));
}

} // namespace

// Closest point by Voronoi regions of the triangle (Ericson, Real-Time Collision
// Detection, 5.1.5), distance measured to it.
double pointTriangleDistance(const double* p, const double* a, const double* b,
                             const double* c)
{
  double ab[3], ac[3], ap[3];
  sub(b, a, ab);
  sub(c, a, ac);
  sub(p, a, ap);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0)
    return distanceTo(p, a);
  double bp[3];
  sub(p, b, bp);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3)
    return distanceTo(p, b);
  double closest[3];
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
    const double v = d1 / (d1 - d3);
    for (int k = 0; k < 3; ++k)
      closest[k] = a[k] + v * ab[k];
    return distanceTo(p, closest);
  }
  double cp[3];
  sub(p, c, cp);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6)
    return distanceTo(p, c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
    const double w = d2 / (d2 - d6);
    for (int k = 0; k < 3; ++k)
      closest[k] = a[k] + w * ac[k];
    return distanceTo(p, closest);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    for (int k = 0; k < 3; ++k)
      closest[k] = b[k] + w * (c[k] - b[k]);
    return distanceTo(p, closest);
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0) || !std::isfinite(sum)) {
    // Degenerate (collinear) triangle: the nearest of its three edges.
    double best = std::numeric_limits<double>::infinity();
    const double* corners[3] = {a, b, c};
    for (int e = 0; e < 3; ++e) {
      const double* s = corners[e];
      const double* t = corners[(e + 1) % 3];
      double st[3], sp[3];
      sub(t, s, st);
      sub(p, s, sp);
      const double len2 = dot(st, st);
      const double u = len2 > 0.0 ? std::clamp(dot(st, sp) / len2, 0.0, 1.0) : 0.0;
      for (int k = 0; k < 3; ++k)
        closest[k] = s[k] + u * st[k];
      best = std::min(best, distanceTo(p, closest));
    }
    return best;
  }
  const double v = vb / sum, w = vc / sum;
  for (int k = 0; k < 3; ++k)
    closest[k] = a[k] + v * ab[k] + w * ac[k];
  return distanceTo(p, closest);
}

TriangleGrid::TriangleGrid(const CompareMesh& mesh, double min_x, double min_y,
                           double max_x, double max_y)
    : mesh_(mesh)
{
  const std::size_t nt = mesh.triangleCount();
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    min_x = std::min(min_x, mesh.xyz[3 * v]);
    max_x = std::max(max_x, mesh.xyz[3 * v]);
    min_y = std::min(min_y, mesh.xyz[3 * v + 1]);
    max_y = std::max(max_y, mesh.xyz[3 * v + 1]);
  }
  const double w = std::max(max_x - min_x, 0.0), h = std::max(max_y - min_y, 0.0);
  cell_ = std::sqrt(std::max(w * h, 1e-300) /
                    static_cast<double>(std::max<std::size_t>(nt, 1))) *
          1.5;
  if (!(cell_ > 0.0) || !std::isfinite(cell_))
    cell_ = std::max({w, h, 1.0});
  // Bound the cell count for very thin boxes.
  while ((w / cell_ + 1.0) * (h / cell_ + 1.0) > 4.0 * static_cast<double>(nt) + 16.0)
    cell_ *= 1.5;
  x0_ = min_x;
  y0_ = min_y;
  nx_ = static_cast<long>(w / cell_) + 1;
  ny_ = static_cast<long>(h / cell_) + 1;
  const std::size_t cells =
      static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  start_.assign(cells + 1, 0);
  // Two passes: count, then fill (counting sort by cell).
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::uint32_t> cursor;
    if (pass == 1) {
      for (std::size_t c = 0; c < cells; ++c)
        start_[c + 1] += start_[c];
      items_.resize(start_[cells]);
      cursor.assign(start_.begin(), start_.end() - 1);
    }
    for (std::uint32_t t = 0; t < nt; ++t) {
      long x0, y0, x1, y1;
      cellRange(t, x0, y0, x1, y1);
      for (long cy = y0; cy <= y1; ++cy)
        for (long cx = x0; cx <= x1; ++cx) {
          const std::size_t cell = static_cast<std::size_t>(cy) * nx_ + cx;
          if (pass == 0)
            ++start_[cell + 1];
          else
            items_[cursor[cell]++] = t;
        }
    }
  }
}

bool TriangleGrid::cellOf(double x, double y, long& cx, long& cy) const
{
  const double fx = std::floor((x - x0_) / cell_), fy = std::floor((y - y0_) / cell_);
  if (!(fx >= 0.0 && fy >= 0.0 && fx < static_cast<double>(nx_) &&
        fy < static_cast<double>(ny_)))
    return false;
  cx = static_cast<long>(fx);
  cy = static_cast<long>(fy);
  return true;
}

void TriangleGrid::cellRange(std::uint32_t t, long& x0, long& y0, long& x1,
                             long& y1) const
{
  const double* a = vertex(mesh_.triangles[3 * t]);
  const double* b = vertex(mesh_.triangles[3 * t + 1]);
  const double* c = vertex(mesh_.triangles[3 * t + 2]);
  auto clampCell = [](double f, long n) {
    return static_cast<long>(std::clamp(f, 0.0, static_cast<double>(n - 1)));
  };
  x0 = clampCell(std::floor((std::min({a[0], b[0], c[0]}) - x0_) / cell_), nx_);
  x1 = clampCell(std::floor((std::max({a[0], b[0], c[0]}) - x0_) / cell_), nx_);
  y0 = clampCell(std::floor((std::min({a[1], b[1], c[1]}) - y0_) / cell_), ny_);
  y1 = clampCell(std::floor((std::max({a[1], b[1], c[1]}) - y0_) / cell_), ny_);
}

double TriangleGrid::nearestDistance(const double* p, std::uint32_t* triangle) const
{
  double best = std::numeric_limits<double>::infinity();
  std::uint32_t best_t = 0;
  if (items_.empty())
    return best;
  auto clampCell = [](double f, long n) {
    return static_cast<long>(std::clamp(f, 0.0, static_cast<double>(n - 1)));
  };
  const long cx = clampCell(std::floor((p[0] - x0_) / cell_), nx_);
  const long cy = clampCell(std::floor((p[1] - y0_) / cell_), ny_);
  const long max_ring = std::max(nx_, ny_);
  auto visit = [&](long x, long y) {
    if (x < 0 || y < 0 || x >= nx_ || y >= ny_)
      return;
    forEachInCellIndex(x, y, [&](std::uint32_t t) {
      const double d = pointTriangleDistance(p, vertex(mesh_.triangles[3 * t]),
                                             vertex(mesh_.triangles[3 * t + 1]),
                                             vertex(mesh_.triangles[3 * t + 2]));
      if (d < best) {
        best = d;
        best_t = t;
      }
    });
  };
  for (long r = 0; r <= max_ring; ++r) {
    if (r == 0)
      visit(cx, cy);
    else {
      for (long x = cx - r; x <= cx + r; ++x) {
        visit(x, cy - r);
        visit(x, cy + r);
      }
      for (long y = cy - r + 1; y <= cy + r - 1; ++y) {
        visit(cx - r, y);
        visit(cx + r, y);
      }
    }
    // Anything not seen yet lies outside the block of rings 0..r: at least r cells
    // away from p in XY.
    if (best <= static_cast<double>(r) * cell_)
      break;
  }
  if (triangle)
    *triangle = best_t;
  return best;
}

} // namespace compare
} // namespace pcl_vts
