// Exact geometric predicates: the only place in pcl_vts that decides the sign of a
// determinant. A floating-point filter answers almost every call; when it cannot
// certify the sign, an exact evaluation (expansion arithmetic, or big rationals for
// extreme magnitudes) decides. Correct for every finite double input; no init call.
// Ties on cocircular points are broken by symbolic perturbation (docs/algorithm.md).
#pragma once

#include <pcl_vts/core/point2.h>

namespace pcl_vts {

/// Sign of a determinant: also reads as CW/COLLINEAR/CCW or OUTSIDE/ON/INSIDE.
enum class Sign : int { NEGATIVE = -1, ZERO = 0, POSITIVE = 1 };

/// Orientation of (a, b, c): POSITIVE when c lies left of the directed line a->b
/// (counter-clockwise triangle), ZERO when collinear. Exact.
Sign
orient2d(const Point2& a, const Point2& b, const Point2& c);

/// In-circle test: for a counter-clockwise triangle (a, b, c), POSITIVE when d lies
/// strictly inside its circumcircle, ZERO on it, NEGATIVE outside (sign flips for a
/// clockwise triangle). Exact.
Sign
incircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

/// In-circle test under symbolic perturbation: each point is lifted to
/// |p|^2 + eps^rank(p), where rank is the lexicographic order of the points
/// (smaller point, larger perturbation). Equals incircle() whenever that is not
/// ZERO; returns ZERO only when all four points are collinear. Every Delaunay
/// triangulation decided with it is the unique triangulation of the perturbed set.
Sign
incirclePerturbed(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

namespace detail {
/// The exact slow paths, exposed for tests (they bypass the filter).
Sign
orient2dExact(const Point2& a, const Point2& b, const Point2& c);
Sign
incircleExact(const Point2& a, const Point2& b, const Point2& c, const Point2& d);
/// Counters of calls that fell through the filter (per thread).
struct PredicateCounters {
  unsigned long long orient_exact = 0;
  unsigned long long incircle_exact = 0;
};
PredicateCounters&
predicateCounters();
} // namespace detail

} // namespace pcl_vts
