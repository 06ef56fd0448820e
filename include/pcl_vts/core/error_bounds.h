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
