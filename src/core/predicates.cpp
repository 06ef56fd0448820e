// Filtered exact predicates. Fast path: Shewchuk's stage-A error bounds, widened by an
// absolute term that covers gradual underflow. Slow path: expansion arithmetic when
// every coordinate lies in [2^-200, 2^200] (then no product underflows or overflows),
// otherwise exact rationals (Boost.Multiprecision), so any finite double is exact.
#include <pcl_vts/core/predicates.h>

#include <boost/multiprecision/cpp_int.hpp>

#include <algorithm>
#include <array>
#include <cmath>

#include "expansion.h"

namespace pcl_vts {
namespace {

constexpr double EPS = 0x1p-53;
constexpr double CCW_ERR_BOUND_A = (3.0 + 16.0 * EPS) * EPS;
constexpr double ICC_ERR_BOUND_A = (10.0 + 96.0 * EPS) * EPS;
// Bound on the absolute error a subnormal intermediate can add (see file comment).
constexpr double UNDERFLOW_SLACK = 0x1p-1060;

Sign
toSign(int s)
{
  return s > 0 ? Sign::POSITIVE : (s < 0 ? Sign::NEGATIVE : Sign::ZERO);
}

bool
inExpansionRange(double v)
{
  const double a = std::fabs(v);
  return a == 0.0 || (a >= 0x1p-200 && a <= 0x1p+200);
}

template <std::size_t N>
bool
allInExpansionRange(const std::array<const Point2*, N>& pts)
{
  return std::all_of(pts.begin(), pts.end(), [](const Point2* p) {
    return inExpansionRange(p->x) && inExpansionRange(p->y);
  });
}

using Rational = boost::multiprecision::cpp_rational;

Rational
exactRational(double v)
{
  // v = m * 2^e with an integer m of at most 53 bits: exact in a rational.
  int e = 0;
  const double m = std::frexp(v, &e);
  const auto mi = static_cast<long long>(std::ldexp(m, 53));
  Rational r(mi);
  e -= 53;
  if (e > 0)
    r *= Rational(boost::multiprecision::cpp_int(1) << e);
  else if (e < 0)
    r /= Rational(boost::multiprecision::cpp_int(1) << -e);
  return r;
}

int
rationalSign(const Rational& r)
{
  return r.sign();
}

int
orientRational(const Point2& a, const Point2& b, const Point2& c)
{
  const Rational acx = exactRational(a.x) - exactRational(c.x);
  const Rational acy = exactRational(a.y) - exactRational(c.y);
  const Rational bcx = exactRational(b.x) - exactRational(c.x);
  const Rational bcy = exactRational(b.y) - exactRational(c.y);
  return rationalSign(acx * bcy - acy * bcx);
}

int
incircleRational(const Point2& a, const Point2& b, const Point2& c, const Point2& d)
{
  const Rational dx = exactRational(d.x), dy = exactRational(d.y);
  const Rational adx = exactRational(a.x) - dx, ady = exactRational(a.y) - dy;
  const Rational bdx = exactRational(b.x) - dx, bdy = exactRational(b.y) - dy;
  const Rational cdx = exactRational(c.x) - dx, cdy = exactRational(c.y) - dy;
  const Rational alift = adx * adx + ady * ady;
  const Rational blift = bdx * bdx + bdy * bdy;
  const Rational clift = cdx * cdx + cdy * cdy;
  const Rational det = alift * (bdx * cdy - cdx * bdy) +
                       blift * (cdx * ady - adx * cdy) +
                       clift * (adx * bdy - bdx * ady);
  return rationalSign(det);
}

using detail::Expansion;

Expansion
crossExact(const Expansion& ux, const Expansion& uy, const Expansion& vx,
           const Expansion& vy)
{
  return detail::expansionSum(detail::expansionProduct(ux, vy),
                              detail::negate(detail::expansionProduct(uy, vx)));
}

int
orientExpansion(const Point2& a, const Point2& b, const Point2& c)
{
  const Expansion acx = detail::exactDiff(a.x, c.x), acy = detail::exactDiff(a.y, c.y);
  const Expansion bcx = detail::exactDiff(b.x, c.x), bcy = detail::exactDiff(b.y, c.y);
  return detail::expansionSign(crossExact(acx, acy, bcx, bcy));
}

int
incircleExpansion(const Point2& a, const Point2& b, const Point2& c, const Point2& d)
{
  using detail::exactDiff;
  using detail::expansionProduct;
  using detail::expansionSum;
  const Expansion adx = exactDiff(a.x, d.x), ady = exactDiff(a.y, d.y);
  const Expansion bdx = exactDiff(b.x, d.x), bdy = exactDiff(b.y, d.y);
  const Expansion cdx = exactDiff(c.x, d.x), cdy = exactDiff(c.y, d.y);
  const auto lift = [](const Expansion& x, const Expansion& y) {
    return expansionSum(expansionProduct(x, x), expansionProduct(y, y));
  };
  const Expansion det = expansionSum(
      expansionSum(expansionProduct(lift(adx, ady), crossExact(bdx, bdy, cdx, cdy)),
                   expansionProduct(lift(bdx, bdy), crossExact(cdx, cdy, adx, ady))),
      expansionProduct(lift(cdx, cdy), crossExact(adx, ady, bdx, bdy)));
  return detail::expansionSign(det);
}

} // namespace

namespace detail {

PredicateCounters&
predicateCounters()
{
  thread_local PredicateCounters counters;
  return counters;
}

Sign
orient2dExact(const Point2& a, const Point2& b, const Point2& c)
{
  if (allInExpansionRange<3>({&a, &b, &c}))
    return toSign(orientExpansion(a, b, c));
  return toSign(orientRational(a, b, c));
}

Sign
incircleExact(const Point2& a, const Point2& b, const Point2& c, const Point2& d)
{
  if (allInExpansionRange<4>({&a, &b, &c, &d}))
    return toSign(incircleExpansion(a, b, c, d));
  return toSign(incircleRational(a, b, c, d));
}

} // namespace detail

Sign
orient2d(const Point2& a, const Point2& b, const Point2& c)
{
  const double detleft = (a.x - c.x) * (b.y - c.y);
  const double detright = (a.y - c.y) * (b.x - c.x);
  const double det = detleft - detright;
  const double errbound =
      CCW_ERR_BOUND_A * (std::fabs(detleft) + std::fabs(detright)) + UNDERFLOW_SLACK;
  if (det > errbound)
    return Sign::POSITIVE;
  if (-det > errbound)
    return Sign::NEGATIVE;
  ++detail::predicateCounters().orient_exact;
  return detail::orient2dExact(a, b, c);
}

Sign
incircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d)
{
  const double adx = a.x - d.x, ady = a.y - d.y;
  const double bdx = b.x - d.x, bdy = b.y - d.y;
  const double cdx = c.x - d.x, cdy = c.y - d.y;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double alift = adx * adx + ady * ady;
  const double blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  const double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) +
                     clift * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * alift +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * blift +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * clift;
  // The lifts bound the squared differences, hence how far an underflowed product
  // can be amplified.
  const double errbound = ICC_ERR_BOUND_A * permanent +
                          UNDERFLOW_SLACK * (1.0 + alift + blift + clift);
  if (det > errbound)
    return Sign::POSITIVE;
  if (-det > errbound)
    return Sign::NEGATIVE;
  ++detail::predicateCounters().incircle_exact;
  return detail::incircleExact(a, b, c, d);
}

Sign
incirclePerturbed(const Point2& a, const Point2& b, const Point2& c, const Point2& d)
{
  const Sign s = incircle(a, b, c, d);
  if (s != Sign::ZERO)
    return s;
  // Lifting p to |p|^2 + eps_p changes the determinant by eps_p times p's cofactor in
  // the lift column; the largest eps with a non-zero cofactor decides the sign.
  struct Term {
    const Point2* p;
    int which;
  };
  std::array<Term, 4> terms{{{&a, 0}, {&b, 1}, {&c, 2}, {&d, 3}}};
  std::sort(terms.begin(), terms.end(),
            [](const Term& l, const Term& r) { return lexLess(*l.p, *r.p); });
  for (const Term& t : terms) {
    Sign cof = Sign::ZERO;
    switch (t.which) {
    case 0: cof = orient2d(b, c, d); break;
    case 1: cof = static_cast<Sign>(-static_cast<int>(orient2d(a, c, d))); break;
    case 2: cof = orient2d(a, b, d); break;
    default: cof = static_cast<Sign>(-static_cast<int>(orient2d(a, b, c))); break;
    }
    if (cof != Sign::ZERO)
      return cof;
  }
  return Sign::ZERO;
}

} // namespace pcl_vts
