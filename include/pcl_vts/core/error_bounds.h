// Floating-point error bounds beside the exact predicates (predicates.h): where a
// search prunes with floating-point geometry, these decide how wide the margin must
// be for the pruning never to drop what the exact predicates would keep. Signs are
// decided by predicates.h; bounds here, implemented in predicates.cpp.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/point2.h>
#include <pcl_vts/core/predicates.h>

#include <cmath>

namespace pcl_vts {

/// Relative slack on comparisons of squared distances computed in floating point
/// (a few unit roundoffs each; this is far wider).
constexpr double SQUARED_DISTANCE_SLACK = 1e-9;

/// A disk that certainly contains the exact circumcircle (closed) of a, b, p.
struct SafeDisk {
  double cx = 0.0;
  double cy = 0.0;
  double radius = 0.0;
  bool valid = false; ///< false: too ill-conditioned to bound; nothing is pruned
};

/// Circumcircle of (a, b, p), counter-clockwise, inflated by a rigorous bound on the
/// floating-point error of its centre and radius.
PCL_VTS_CORE_EXPORT SafeDisk safeCircumdisk(const Point2& a, const Point2& b,
                                            const Point2& p);

/// A disk that contains the exact circumdisk of a, b, c in any orientation, or
/// "unbounded" when the triangle is too flat for floating point to bound its circle.
/// Unlike SafeDisk, whose search may then prune nothing, a proof that uses this one
/// must claim the whole plane when unbounded. The finality rule of the cache blocks
/// (src/core/local_delaunay.h) and of the tiles (src/tiling/known_space.h) both stand
/// on it: a triangle is final once this disk lies in space whose points are known.
struct CircumdiskBound {
  Point2 center;
  double radius = 0;
  bool unbounded = false;
};

/// The circumdisk of (a, b, c) grown by a bound on the rounding of its computation
/// (tests/core/test_block_finality.cpp checks it against exact circles).
inline CircumdiskBound boundCircumdisk(const Point2& a, const Point2& b,
                                       const Point2& c)
{
  CircumdiskBound disk;
  const double bx = b.x - a.x, by = b.y - a.y;
  const double cx = c.x - a.x, cy = c.y - a.y;
  const double t1 = bx * cy, t2 = by * cx;
  const double det = 2.0 * (t1 - t2);
  // The determinant's relative error is a few ulps of |t1| + |t2| over |det|; below
  // this ratio the centre could be anywhere, so nothing is claimed.
  if (!(std::fabs(det) > 1e-6 * (std::fabs(t1) + std::fabs(t2))) ||
      !std::isfinite(det)) {
    disk.unbounded = true;
    return disk;
  }
  const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  const double ux = (cy * b2 - by * c2) / det;
  const double uy = (bx * c2 - cx * b2) / det;
  disk.center = {a.x + ux, a.y + uy};
  const double r = std::sqrt(ux * ux + uy * uy);
  // Relative error of the offset: well under 1e-9 given the test above; the sum
  // a + u adds an ulp of |a|. 1e-7 covers both with a wide margin.
  disk.radius = r + 1e-7 * (r + std::sqrt(b2) + std::sqrt(c2)) +
                1e-15 * (std::fabs(a.x) + std::fabs(a.y));
  if (!std::isfinite(disk.radius))
    disk.unbounded = true;
  return disk;
}

/// False only when c certainly lies in the closed right half-plane of the directed
/// line a->b (orient2d(a, b, c) <= 0), from a floating-point cross product and its
/// certified error bound: a filter that never says false for a point strictly left.
inline bool mayLieLeft(const Point2& a, const Point2& b, const Point2& c)
{
  const double ex = b.x - a.x, ey = b.y - a.y;
  const double dx = c.x - a.x, dy = c.y - a.y;
  const double cross = ex * dy - ey * dx;
  const double bound =
      8.0 * detail::UNIT_ROUNDOFF * (std::fabs(ex * dy) + std::fabs(ey * dx));
  return cross + bound > 0.0;
}

} // namespace pcl_vts
