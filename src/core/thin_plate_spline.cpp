// Thin-plate spline: dense (n+3)^2 system solved by Gaussian elimination with partial
// pivoting on normalised coordinates (unit radius), so that conditioning does not
// depend on the input units or a georeferenced origin.
#include <pcl_vts/core/thin_plate_spline.h>

#include <algorithm>
#include <cmath>

namespace pcl_vts {

namespace {

double kernel(double r2)
{
  return r2 > 0.0 ? 0.5 * r2 * std::log(r2) : 0.0; // r^2 log r
}

/// Solves a x = b in place (a: n*n row-major); false when a pivot vanishes.
bool solveDense(std::vector<double>& a, std::vector<double>& b, std::size_t n)
{
  double norm = 0.0;
  for (const double v : a)
    norm = std::max(norm, std::fabs(v));
  const double tiny = norm * 1e-13;
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t pivot = k;
    for (std::size_t i = k + 1; i < n; ++i)
      if (std::fabs(a[i * n + k]) > std::fabs(a[pivot * n + k]))
        pivot = i;
    if (!(std::fabs(a[pivot * n + k]) > tiny))
      return false;
    if (pivot != k) {
      for (std::size_t j = 0; j < n; ++j)
        std::swap(a[k * n + j], a[pivot * n + j]);
      std::swap(b[k], b[pivot]);
    }
    const double inv = 1.0 / a[k * n + k];
    for (std::size_t i = k + 1; i < n; ++i) {
      const double f = a[i * n + k] * inv;
      if (f == 0.0)
        continue;
      for (std::size_t j = k; j < n; ++j)
        a[i * n + j] -= f * a[k * n + j];
      b[i] -= f * b[k];
    }
  }
  for (std::size_t k = n; k-- > 0;) {
    double s = b[k];
    for (std::size_t j = k + 1; j < n; ++j)
      s -= a[k * n + j] * b[j];
    b[k] = s / a[k * n + k];
  }
  return true;
}

} // namespace

bool ThinPlateSpline::fit(const std::vector<Point2>& xy, const std::vector<double>& z)
{
  centres_.clear();
  weights_.clear();
  affine_[0] = affine_[1] = affine_[2] = 0.0;
  const std::size_t n = std::min(xy.size(), z.size());
  if (n == 0)
    return false;
  double mean = 0.0;
  centre_ = {0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    centre_.x += xy[i].x / static_cast<double>(n);
    centre_.y += xy[i].y / static_cast<double>(n);
    mean += z[i] / static_cast<double>(n);
  }
  scale_ = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    scale_ = std::max(scale_, std::hypot(xy[i].x - centre_.x, xy[i].y - centre_.y));
  if (!(scale_ > 0.0))
    scale_ = 1.0;
  affine_[0] = mean;
  for (std::size_t i = 0; i < n; ++i)
    centres_.push_back(
        {(xy[i].x - centre_.x) / scale_, (xy[i].y - centre_.y) / scale_});

  if (n >= 4) {
    const std::size_t m = n + 3;
    std::vector<double> a(m * m, 0.0);
    std::vector<double> b(m, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j) {
        const double dx = centres_[i].x - centres_[j].x;
        const double dy = centres_[i].y - centres_[j].y;
        a[i * m + j] = kernel(dx * dx + dy * dy);
      }
      const double row[3] = {1.0, centres_[i].x, centres_[i].y};
      for (std::size_t k = 0; k < 3; ++k) {
        a[i * m + n + k] = row[k];
        a[(n + k) * m + i] = row[k];
      }
      b[i] = z[i] - mean;
    }
    if (solveDense(a, b, m)) {
      weights_.assign(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
      affine_[0] = mean + b[n];
      affine_[1] = b[n + 1];
      affine_[2] = b[n + 2];
      return true;
    }
  }
  // Plane fallback: normal equations of z - mean = b x + c y.
  double sxx = 0.0, sxy = 0.0, syy = 0.0, sxz = 0.0, syz = 0.0, sx = 0.0, sy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sx += centres_[i].x;
    sy += centres_[i].y;
  }
  sx /= static_cast<double>(n);
  sy /= static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = centres_[i].x - sx, y = centres_[i].y - sy, w = z[i] - mean;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
    sxz += x * w;
    syz += y * w;
  }
  const double det = sxx * syy - sxy * sxy;
  if (std::fabs(det) > 1e-12 * (sxx * syy + 1e-300)) {
    affine_[1] = (sxz * syy - syz * sxy) / det;
    affine_[2] = (syz * sxx - sxz * sxy) / det;
    affine_[0] = mean - affine_[1] * sx - affine_[2] * sy;
  }
  centres_.clear();
  return true;
}

double ThinPlateSpline::evaluate(const Point2& p) const
{
  const double x = (p.x - centre_.x) / scale_;
  const double y = (p.y - centre_.y) / scale_;
  double value = affine_[0] + affine_[1] * x + affine_[2] * y;
  for (std::size_t i = 0; i < weights_.size(); ++i) {
    const double dx = x - centres_[i].x, dy = y - centres_[i].y;
    value += weights_[i] * kernel(dx * dx + dy * dy);
  }
  return value;
}

} // namespace pcl_vts
