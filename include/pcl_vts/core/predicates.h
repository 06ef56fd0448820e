// Exact geometric predicates: the only place in pcl_vts that decides the sign of a
// determinant. A floating-point filter answers almost every call; when it cannot
// certify the sign, an exact evaluation (expansion arithmetic, or big rationals for
// extreme magnitudes) decides. Correct for every finite double input; no init call.
// Ties on cocircular points are broken by symbolic perturbation (docs/algorithm.md).
// The filters' bounds assume no fused multiply-add: the core's CMake target passes
// -ffp-contract=off to everything that links it.
// The floating-point bounds that let a search prune safely sit beside these, in
// error_bounds.h.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/point2.h>

#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pcl_vts {

/// Sign of a determinant: also reads as CW/COLLINEAR/CCW or OUTSIDE/ON/INSIDE.
enum class Sign : int { NEGATIVE = -1, ZERO = 0, POSITIVE = 1 };

namespace detail {
/// The exact slow paths (they bypass the filter); exposed for tests.
PCL_VTS_CORE_EXPORT Sign orient2dExact(const Point2& a, const Point2& b,
                                       const Point2& c);
PCL_VTS_CORE_EXPORT Sign incircleExact(const Point2& a, const Point2& b,
                                       const Point2& c, const Point2& d);

constexpr double UNIT_ROUNDOFF = 0x1p-53;
constexpr double CCW_ERR_BOUND_A = (3.0 + 16.0 * UNIT_ROUNDOFF) * UNIT_ROUNDOFF;
constexpr double ICC_ERR_BOUND_A = (10.0 + 96.0 * UNIT_ROUNDOFF) * UNIT_ROUNDOFF;
// Absolute error a subnormal intermediate can add; keeps the filter sound under
// gradual underflow (Shewchuk's bounds assume none). 2^-1060 would do; 2^-1000 is
// as sound (a larger bound only sends more calls to the exact path) and keeps the
// bound a normal number: a subnormal one costs a microcode assist on every call.
constexpr double UNDERFLOW_SLACK = 0x1p-1000;

/// The in-circle determinant of (a, b, c, d) translated to d, with the products and
/// lifts its error bound is made of: the one evaluation incircle's dynamic filter and
/// incirclePerturbedInBox's box filter share (the same operations in the same order).
struct IncircleTerms {
  double bdxcdy, cdxbdy, cdxady, adxcdy, adxbdy, bdxady;
  double alift, blift, clift;
  double det;
};
inline IncircleTerms incircleTerms(const Point2& a, const Point2& b, const Point2& c,
                                   const Point2& d)
{
  const double adx = a.x - d.x, ady = a.y - d.y;
  const double bdx = b.x - d.x, bdy = b.y - d.y;
  const double cdx = c.x - d.x, cdy = c.y - d.y;
  IncircleTerms t;
  t.bdxcdy = bdx * cdy;
  t.cdxbdy = cdx * bdy;
  t.cdxady = cdx * ady;
  t.adxcdy = adx * cdy;
  t.adxbdy = adx * bdy;
  t.bdxady = bdx * ady;
  t.alift = adx * adx + ady * ady;
  t.blift = bdx * bdx + bdy * bdy;
  t.clift = cdx * cdx + cdy * cdy;
  t.det = t.alift * (t.bdxcdy - t.cdxbdy) + t.blift * (t.cdxady - t.adxcdy) +
          t.clift * (t.adxbdy - t.bdxady);
  return t;
}

/// incircleTerms(a, b, c, d).det alone, two lanes at a time where SSE2 is there (every
/// x86-64): the same products, lifts, differences and sums in the same order, so the
/// same double (b.y * c.x is c.x * b.y: IEEE products commute), for the box filters'
/// hot loops. test_predicates checks the equality bit for bit.
inline double incircleDet(const Point2& a, const Point2& b, const Point2& c,
                          const Point2& d)
{
#if defined(__SSE2__)
  const __m128d dd = _mm_loadu_pd(&d.x);
  const __m128d ad = _mm_sub_pd(_mm_loadu_pd(&a.x), dd); // (adx, ady)
  const __m128d bd = _mm_sub_pd(_mm_loadu_pd(&b.x), dd);
  const __m128d cd = _mm_sub_pd(_mm_loadu_pd(&c.x), dd);
  const __m128d aa = _mm_mul_pd(ad, ad), bb = _mm_mul_pd(bd, bd),
                cc = _mm_mul_pd(cd, cd);
  // (alift, blift) and clift
  const __m128d lifts = _mm_add_pd(_mm_unpacklo_pd(aa, bb), _mm_unpackhi_pd(aa, bb));
  const __m128d clift = _mm_add_sd(cc, _mm_unpackhi_pd(cc, cc));
  // (bdx * cdy, bdy * cdx), (cdx * ady, cdy * adx), (adx * bdy, ady * bdx)
  const __m128d x1 = _mm_mul_pd(bd, _mm_shuffle_pd(cd, cd, 1));
  const __m128d x2 = _mm_mul_pd(cd, _mm_shuffle_pd(ad, ad, 1));
  const __m128d x3 = _mm_mul_pd(ad, _mm_shuffle_pd(bd, bd, 1));
  // (bdxcdy - cdxbdy, cdxady - adxcdy) and adxbdy - bdxady
  const __m128d d12 = _mm_sub_pd(_mm_unpacklo_pd(x1, x2), _mm_unpackhi_pd(x1, x2));
  const __m128d d3 = _mm_sub_sd(x3, _mm_unpackhi_pd(x3, x3));
  const __m128d p12 = _mm_mul_pd(lifts, d12);
  const __m128d sum12 = _mm_add_sd(p12, _mm_unpackhi_pd(p12, p12));
  return _mm_cvtsd_f64(_mm_add_sd(sum12, _mm_mul_sd(clift, d3)));
#else
  return incircleTerms(a, b, c, d).det;
#endif
}

/// |v| without a branch (a sign bit mask): the filter's terms have random signs, and
/// `v < 0 ? -v : v` compiles to a branch that mispredicts about half the time.
inline double absValue(double v)
{
  return std::fabs(v);
}
} // namespace detail

/// Orientation of (a, b, c): POSITIVE when c lies left of the directed line a->b
/// (counter-clockwise triangle), ZERO when collinear. Exact.
inline Sign orient2d(const Point2& a, const Point2& b, const Point2& c)
{
  // Shewchuk's stage-A filter inline; the exact evaluation is out of line.
  const double detleft = (a.x - c.x) * (b.y - c.y);
  const double detright = (a.y - c.y) * (b.x - c.x);
  const double det = detleft - detright;
  const double errbound = detail::CCW_ERR_BOUND_A *
                              (detail::absValue(detleft) + detail::absValue(detright)) +
                          detail::UNDERFLOW_SLACK;
  if (det > errbound)
    return Sign::POSITIVE;
  if (-det > errbound)
    return Sign::NEGATIVE;
  return detail::orient2dExact(a, b, c);
}

/// In-circle test: for a counter-clockwise triangle (a, b, c), POSITIVE when d lies
/// strictly inside its circumcircle, ZERO on it, NEGATIVE outside (sign flips for a
/// clockwise triangle). Exact.
inline Sign incircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d)
{
  using detail::absValue;
  const detail::IncircleTerms t = detail::incircleTerms(a, b, c, d);
  const double permanent = (absValue(t.bdxcdy) + absValue(t.cdxbdy)) * t.alift +
                           (absValue(t.cdxady) + absValue(t.adxcdy)) * t.blift +
                           (absValue(t.adxbdy) + absValue(t.bdxady)) * t.clift;
  // The lifts bound the squared differences, hence how far an underflowed product
  // can be amplified.
  const double errbound = detail::ICC_ERR_BOUND_A * permanent +
                          detail::UNDERFLOW_SLACK * (1.0 + t.alift + t.blift + t.clift);
  if (t.det > errbound)
    return Sign::POSITIVE;
  if (-t.det > errbound)
    return Sign::NEGATIVE;
  return detail::incircleExact(a, b, c, d);
}

/// In-circle test under symbolic perturbation: each point is lifted to
/// |p|^2 + eps^rank(p), where rank is the lexicographic order of the points
/// (smaller point, larger perturbation). Equals incircle() whenever that is not
/// ZERO; returns ZERO only when all four points are collinear. Every Delaunay
/// triangulation decided with it is the unique triangulation of the perturbed set.
PCL_VTS_CORE_EXPORT Sign incirclePerturbedTie(const Point2& a, const Point2& b,
                                              const Point2& c, const Point2& d);

inline Sign incirclePerturbed(const Point2& a, const Point2& b, const Point2& c,
                              const Point2& d)
{
  const Sign s = incircle(a, b, c, d);
  return s != Sign::ZERO ? s : incirclePerturbedTie(a, b, c, d);
}

namespace detail {
/// Semi-static filters for many tests among points of one known box (the cache blocks'
/// Bowyer-Watson, src/core/local_delaunay.cpp): the error bound is computed once per
/// box instead of per call, so a call is the determinant and one comparison. The
/// bounded predicates below return exactly what orient2d / incirclePerturbed return,
/// for every input: where the determinant does not clear the box's bound they call
/// them.
///
/// Why the bound is sound (Shewchuk, "Adaptive precision floating-point arithmetic and
/// fast robust geometric predicates", 1997, stage A): orient2d and incircle compute
/// det and errbound in floating point from the rounded differences (a.x - c.x, ...),
/// and certify sign(det) when |det| > errbound (their own rounding included in the
/// constants, UNDERFLOW_SLACK covering underflow). errbound is an expression of +
/// and * over non-negative doubles (|products|, lifts); round-to-nearest is monotone,
/// so evaluating the same expression, in the same order, on upper bounds of its
/// inputs gives a double >= errbound. For points with x in [x_lo, x_hi], the real
/// |a.x - c.x| <= x_hi - x_lo, hence the rounded |a.x - c.x| <= fl(x_hi - x_lo) = X
/// (monotone again); likewise Y; every |product of two differences| <= fl(X * Y),
/// every lift <= fl(fl(X * X) + fl(Y * Y)). So |det| > box bound implies |det| >
/// errbound: the sign orient2d / incircle would return, never ZERO, and
/// incirclePerturbed returns that same sign (its tie-break only acts on ZERO). The
/// determinant is computed by the same expression as in orient2d / incircle. A box
/// so wide that the bound is not finite (inf or NaN) certifies nothing: every call
/// goes to the full predicate.
/// orient2d and incirclePerturbed out of line, the points by value (in registers):
/// the rare fallback of the box filters below, so that the callers' hot loops keep
/// their points in registers.
PCL_VTS_CORE_EXPORT Sign orient2dOutOfLine(Point2 a, Point2 b, Point2 c);
PCL_VTS_CORE_EXPORT Sign incirclePerturbedOutOfLine(Point2 a, Point2 b, Point2 c,
                                                    Point2 d);

struct BoxBounds {
  double orient = 0.0;   ///< for orient2dInBox
  double incircle = 0.0; ///< for incirclePerturbedInBox
};

/// The bounds for points inside [x_lo, x_hi] x [y_lo, y_hi] (x_lo <= x_hi, y_lo <=
/// y_hi).
inline BoxBounds boxBounds(double x_lo, double x_hi, double y_lo, double y_hi)
{
  const double X = x_hi - x_lo, Y = y_hi - y_lo;
  const double product = X * Y; // bounds every |a.x - c.x| * |b.y - c.y|
  const double pair = product + product;
  const double lift = X * X + Y * Y;
  BoxBounds b;
  b.orient = CCW_ERR_BOUND_A * pair + UNDERFLOW_SLACK;
  const double permanent = pair * lift + pair * lift + pair * lift;
  b.incircle =
      ICC_ERR_BOUND_A * permanent + UNDERFLOW_SLACK * (1.0 + lift + lift + lift);
  return b;
}

/// orient2d(a, b, c) for points inside the box of `bound` (BoxBounds::orient).
inline Sign orient2dInBox(const Point2& a, const Point2& b, const Point2& c,
                          double bound)
{
  const double detleft = (a.x - c.x) * (b.y - c.y);
  const double detright = (a.y - c.y) * (b.x - c.x);
  const double det = detleft - detright;
  if (det > bound)
    return Sign::POSITIVE;
  if (-det > bound)
    return Sign::NEGATIVE;
  return orient2dOutOfLine(a, b, c);
}

/// incirclePerturbed(a, b, c, d) for points inside the box of `bound`
/// (BoxBounds::incircle).
inline Sign incirclePerturbedInBox(const Point2& a, const Point2& b, const Point2& c,
                                   const Point2& d, double bound)
{
  const double det = incircleDet(a, b, c, d);
  if (det > bound)
    return Sign::POSITIVE;
  if (-det > bound)
    return Sign::NEGATIVE;
  return incirclePerturbedOutOfLine(a, b, c, d);
}

/// The in-circle determinant of a fixed triangle as a function of the fourth point
/// (the cache blocks' cavity search tests each triangle against several points):
/// with c the origin, u = a - c, w = b - c, q' = q - c,
///   incircle(a, b, c, q) = Bx q'x + By q'y - A |q'|^2,
///   A = ux wy - uy wx (= orient2d(a, b, c)), Bx = |u|^2 wy - |w|^2 uy,
///   By = |w|^2 ux - |u|^2 wx
/// (the lifted 4 x 4 determinant | x y x^2+y^2 1 | of rows a, b, c, q is invariant
/// under translation; with c at the origin its row is (0 0 0 1) and the expansion
/// along q's row gives these cofactors). A and B are computed once per triangle; a
/// test is then a difference, two products, a difference, two products and a sum.
struct alignas(16) IncircleCoefficients {
  double b[2]; ///< (Bx, By)
  double a[2]; ///< (A, A)
};

/// A corner's offset from the triangle's corner c and its squared length: the two
/// triangles of a star that share a corner share it.
struct CornerOffset {
  double x, y, lift;
};
inline CornerOffset cornerOffset(const Point2& p, const Point2& c)
{
  const double x = p.x - c.x, y = p.y - c.y;
  return {x, y, x * x + y * y};
}

/// The coefficients from u = cornerOffset(a, c) and w = cornerOffset(b, c).
inline IncircleCoefficients incircleCoefficients(const CornerOffset& u,
                                                 const CornerOffset& w)
{
  IncircleCoefficients k;
  k.b[0] = u.lift * w.y - w.lift * u.y;
  k.b[1] = w.lift * u.x - u.lift * w.x;
  k.a[0] = k.a[1] = u.x * w.y - u.y * w.x;
  return k;
}

inline IncircleCoefficients incircleCoefficients(const Point2& a, const Point2& b,
                                                 const Point2& c)
{
  return incircleCoefficients(cornerOffset(a, c), cornerOffset(b, c));
}

/// The determinant from the coefficients of the triangle (a, b, c) and its corner c:
/// (Bx - A q'x) q'x + (By - A q'y) q'y.
inline double incircleFromCoefficients(const IncircleCoefficients& k, const Point2& c,
                                       const Point2& q)
{
#if defined(__SSE2__)
  const __m128d d = _mm_sub_pd(_mm_loadu_pd(&q.x), _mm_loadu_pd(&c.x));
  const __m128d e =
      _mm_mul_pd(_mm_sub_pd(_mm_load_pd(k.b), _mm_mul_pd(_mm_load_pd(k.a), d)), d);
  return _mm_cvtsd_f64(_mm_add_sd(e, _mm_unpackhi_pd(e, e)));
#else
  const double dx = q.x - c.x, dy = q.y - c.y;
  return (k.b[0] - k.a[0] * dx) * dx + (k.b[1] - k.a[1] * dy) * dy;
#endif
}

/// The bound for incircleFromCoefficients when a, b, c and q lie inside [x_lo, x_hi] x
/// [y_lo, y_hi]: |det - incircle(a, b, c, q)| <= bound, so det > bound certifies
/// POSITIVE and -det > bound NEGATIVE (incirclePerturbedInBoxFromCoefficients).
///
/// Proof. Let u = a - c, w = b - c, d = q - c (real differences). Expanded, the
/// determinant is a signed sum of 12 monomials of degree 4 in ux..dy:
///   d_x (ux^2 wy + uy^2 wy - uy wx^2 - uy wy^2) + d_y (ux wx^2 + ux wy^2 - ux^2 wx
///   - uy^2 wx) - (ux wy - uy wx)(d_x^2 + d_y^2).
/// Without underflow, every floating-point operation is exact times (1 + e), |e| <=
/// u = 2^-53 (negation exact). Following each monomial through the evaluation
/// (incircleCoefficients, then incircleFromCoefficients) it collects at most 11 such
/// factors: ux^2 wy d_x gets 2 from ux's difference, 1 from the square, 1 from the sum
/// |u|^2, 1 from wy's difference and 1 from the product |u|^2 wy, 1 from Bx's
/// difference, 1 from Bx - A d_x, 1 from d_x's difference and 1 from the product with
/// d_x, 1 from the final sum (11); uy wx^2 d_x the same count; ux wy d_x^2 gets 2 from
/// the differences, 1 from the product, 1 from A's sum, 2 from A d_x (difference,
/// product), 1 from Bx - A d_x, 2 from the product with d_x, 1 from the sum (10). So
/// the computed value is sum_m s_m M_m (1 + t_m), |t_m| <= gamma_11 = 11u / (1 - 11u)
/// (Higham, Accuracy and Stability, lemma 3.1), and |det - exact| <= gamma_11
/// sum_m |M_m|. With every |coordinate difference| <= W: each of the six groups
/// |d_x| |u|^2 |wy|, |d_x| |uy| |w|^2, |d_y| |ux| |w|^2, |d_y| |u|^2 |wx|,
/// |ux wy| |d|^2, |uy wx| |d|^2 is at most W W 2W^2, so sum_m |M_m| <= 12 W^4.
/// The real widths are at most fl(x_hi - x_lo) (1 + u) (rounding to nearest loses at
/// most a relative u), so W <= m (1 + u), m the larger computed width; 12 W^4 gamma_11
/// <= 132.01 u m^4 (1 + u)^4, below the computed 144 u m^4 (three roundings, each at
/// most a relative u low). Underflow: a product that underflows adds an absolute
/// error of at most 2^-1075 (sums of subnormals are exact), which the later operations
/// multiply by at most two differences (m^2 each way, at most 12 such errors per
/// monomial path), far below UNDERFLOW_SLACK (1 + 4 m^2). Overflow: every intermediate
/// (differences <= m, lifts <= 2m^2, B <= 4m^3, A d <= 2m^3, the terms <= 6m^4, the
/// sum <= 12m^4, rounding included) is below 16 max(m, 1)^4; where that is not finite
/// the bound is infinite and certifies nothing (nor does a NaN). Independent of how the
/// exact sign is obtained, the certified sign is incircle's, so incirclePerturbed's
/// (its tie-break only acts on ZERO). test_predicates (BoxFilters.Coefficients...)
/// checks it against exact arithmetic near circles at UTM magnitudes.
inline double coefficientBound(double x_lo, double x_hi, double y_lo, double y_hi)
{
  const double m = std::fmax(x_hi - x_lo, y_hi - y_lo);
  const double m1 = std::fmax(m, 1.0);
  const double guard = 16.0 * ((m1 * m1) * (m1 * m1));
  if (!std::isfinite(guard) || std::isnan(m))
    return HUGE_VAL;
  const double m2 = m * m;
  return 144.0 * UNIT_ROUNDOFF * (m2 * m2) + UNDERFLOW_SLACK * (1.0 + 4.0 * m2);
}

/// incirclePerturbed(a, b, c, q) from k = incircleCoefficients(a, b, c), for points
/// inside the box of `bound` (coefficientBound).
inline Sign incirclePerturbedFromCoefficients(const IncircleCoefficients& k,
                                              const Point2& a, const Point2& b,
                                              const Point2& c, const Point2& q,
                                              double bound)
{
  const double det = incircleFromCoefficients(k, c, q);
  if (det > bound)
    return Sign::POSITIVE;
  if (-det > bound)
    return Sign::NEGATIVE;
  return incirclePerturbedOutOfLine(a, b, c, q);
}
} // namespace detail

} // namespace pcl_vts
