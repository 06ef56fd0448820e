// Filtered exact predicates. Fast path: Shewchuk's stage-A error bounds, widened by an
// absolute term that covers gradual underflow. Slow path: expansion arithmetic when
// every coordinate lies in [2^-200, 2^200] (then no product underflows or overflows),
// otherwise big integers (Boost.Multiprecision cpp_int on the doubles scaled by
// 2^1074), so any finite double is exact. Last, the floating-point error bounds of
// error_bounds.h (the safe circumdisk of the mediatrix search).
#include "expansion.h"

#include <pcl_vts/core/error_bounds.h>
#include <pcl_vts/core/predicates.h>

#include <boost/multiprecision/cpp_int.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace pcl_vts {
namespace {

Sign toSign(int s)
{
  return s > 0 ? Sign::POSITIVE : (s < 0 ? Sign::NEGATIVE : Sign::ZERO);
}

bool inExpansionRange(double v)
{
  const double a = std::fabs(v);
  return a == 0.0 || (a >= 0x1p-200 && a <= 0x1p+200);
}

template <std::size_t N>
bool allInExpansionRange(const std::array<const Point2*, N>& pts)
{
  return std::all_of(pts.begin(), pts.end(), [](const Point2* p) {
    return inExpansionRange(p->x) && inExpansionRange(p->y);
  });
}

using BigInt = boost::multiprecision::cpp_int;

/// v * 2^1074 as an integer: exact for every finite double (all are multiples of
/// 2^-1074), so the determinants below are evaluated exactly in integers.
BigInt scaledInteger(double v)
{
  int e = 0;
  const double m = std::frexp(v, &e);
  BigInt r = static_cast<long long>(std::ldexp(m, 53));
  const int shift = e - 53 + 1074;
  if (shift >= 0)
    r <<= shift;
  else
    r /= BigInt(1) << -shift; // exact: the low bits are zero
  return r;
}

int orientBigInt(const Point2& a, const Point2& b, const Point2& c)
{
  const BigInt cx = scaledInteger(c.x), cy = scaledInteger(c.y);
  const BigInt acx = scaledInteger(a.x) - cx, acy = scaledInteger(a.y) - cy;
  const BigInt bcx = scaledInteger(b.x) - cx, bcy = scaledInteger(b.y) - cy;
  const BigInt det = acx * bcy - acy * bcx;
  return det.sign();
}

int incircleBigInt(const Point2& a, const Point2& b, const Point2& c, const Point2& d)
{
  const BigInt dx = scaledInteger(d.x), dy = scaledInteger(d.y);
  const BigInt adx = scaledInteger(a.x) - dx, ady = scaledInteger(a.y) - dy;
  const BigInt bdx = scaledInteger(b.x) - dx, bdy = scaledInteger(b.y) - dy;
  const BigInt cdx = scaledInteger(c.x) - dx, cdy = scaledInteger(c.y) - dy;
  const BigInt alift = adx * adx + ady * ady;
  const BigInt blift = bdx * bdx + bdy * bdy;
  const BigInt clift = cdx * cdx + cdy * cdy;
  const BigInt det = alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) +
                     clift * (adx * bdy - bdx * ady);
  return det.sign();
}

/// Orientation from the raw coordinates (Shewchuk's orient2dexact), on the stack:
/// ax(by - cy) + bx(cy - ay) + cx(ay - by) as three exact 4-term cross products.
int orientExpansion(const Point2& a, const Point2& b, const Point2& c)
{
  double at[4], bt[4], ct[4], v[8], w[12];
  const int al = detail::crossZeroelim(a.x, b.y, a.x, c.y, at);
  const int bl = detail::crossZeroelim(b.x, c.y, b.x, a.y, bt);
  const int cl = detail::crossZeroelim(c.x, a.y, c.x, b.y, ct);
  const int vl = detail::sumZeroelim(al, at, bl, bt, v);
  const int wl = detail::sumZeroelim(vl, v, cl, ct, w);
  return detail::signOf(wl, w);
}

/// x * (x * e) + y * (y * e) with the sign of `sign`, into out (at most 96 terms for
/// a 12-term e).
int liftTimes(const double* e, int elen, double x, double y, double sign, double* out)
{
  double ex[24], exx[48], ey[24], eyy[48];
  const int l1 = detail::scaleZeroelim(elen, e, x, ex);
  const int l2 = detail::scaleZeroelim(l1, ex, sign * x, exx);
  const int m1 = detail::scaleZeroelim(elen, e, y, ey);
  const int m2 = detail::scaleZeroelim(m1, ey, sign * y, eyy);
  return detail::sumZeroelim(l2, exx, m2, eyy, out);
}

/// In-circle from the raw coordinates (Shewchuk's incircleexact), on the stack.
int incircleExpansion(const Point2& a, const Point2& b, const Point2& c,
                      const Point2& d)
{
  using detail::crossZeroelim;
  using detail::sumZeroelim;
  double ab[4], bc[4], cd[4], da[4], ac[4], bd[4];
  const int abl = crossZeroelim(a.x, b.y, b.x, a.y, ab);
  const int bcl = crossZeroelim(b.x, c.y, c.x, b.y, bc);
  const int cdl = crossZeroelim(c.x, d.y, d.x, c.y, cd);
  const int dal = crossZeroelim(d.x, a.y, a.x, d.y, da);
  const int acl = crossZeroelim(a.x, c.y, c.x, a.y, ac);
  const int bdl = crossZeroelim(b.x, d.y, d.x, b.y, bd);
  double nac[4], nbd[4];
  for (int i = 0; i < 4; ++i) {
    nac[i] = -ac[i];
    nbd[i] = -bd[i];
  }
  double t8[8], cda[12], dab[12], abc[12], bcd[12];
  int t = sumZeroelim(cdl, cd, dal, da, t8);
  const int cdal = sumZeroelim(t, t8, acl, ac, cda);
  t = sumZeroelim(dal, da, abl, ab, t8);
  const int dabl = sumZeroelim(t, t8, bdl, bd, dab);
  t = sumZeroelim(abl, ab, bcl, bc, t8);
  const int abcl = sumZeroelim(t, t8, acl, nac, abc);
  t = sumZeroelim(bcl, bc, cdl, cd, t8);
  const int bcdl = sumZeroelim(t, t8, bdl, nbd, bcd);
  double adet[96], bdet[96], cdet[96], ddet[96], abdet[192], cddet[192], det[384];
  const int al = liftTimes(bcd, bcdl, a.x, a.y, 1.0, adet);
  const int bl = liftTimes(cda, cdal, b.x, b.y, -1.0, bdet);
  const int cl = liftTimes(dab, dabl, c.x, c.y, 1.0, cdet);
  const int dl = liftTimes(abc, abcl, d.x, d.y, -1.0, ddet);
  const int abdl = sumZeroelim(al, adet, bl, bdet, abdet);
  const int cddl = sumZeroelim(cl, cdet, dl, ddet, cddet);
  const int detl = sumZeroelim(abdl, abdet, cddl, cddet, det);
  return detail::signOf(detl, det);
}

/// True when a - b is exactly representable (its rounding error is zero).
bool exactDifference(double a, double b)
{
  double x, y;
  detail::twoSum(a, -b, x, y);
  return y == 0.0;
}

/// Orientation when the coordinate differences are exact doubles: the sign of
/// p - q, p = acx bcy, q = acy bcx. Rounding to nearest is monotone (p <= q implies
/// fl(p) <= fl(q)), so fl(p) > fl(q) proves p > q and fl(p) < fl(q) proves p < q;
/// where they are equal, p - q = ep - eq, their exact rounding errors (twoProduct:
/// no underflow inside the expansion range, the differences being multiples of
/// 2^-252 below 2^201).
int orientExactDifferences(double acx, double acy, double bcx, double bcy)
{
  const double p = acx * bcy, q = acy * bcx;
  if (p != q)
    return p > q ? 1 : -1;
  double rp, ep, rq, eq;
  detail::twoProduct(acx, bcy, rp, ep);
  detail::twoProduct(acy, bcx, rq, eq);
  return ep > eq ? 1 : (ep < eq ? -1 : 0);
}

/// lift * cross, lift = dx^2 + dy^2, for one row of the in-circle determinant.
int liftedRow(double dx, double dy, const double* cross, int clen, double* out)
{
  double x1[8], x2[16], y1[8], y2[16];
  const int l1 = detail::scaleZeroelim(clen, cross, dx, x1);
  const int l2 = detail::scaleZeroelim(l1, x1, dx, x2);
  const int m1 = detail::scaleZeroelim(clen, cross, dy, y1);
  const int m2 = detail::scaleZeroelim(m1, y1, dy, y2);
  return detail::sumZeroelim(l2, x2, m2, y2, out);
}

#if defined(__SIZEOF_INT128__)
__extension__ using Int128 = __int128;

/// The in-circle determinant's sign in integers where the six exact differences are
/// integer multiples of one power of two, 2^(e - 30) for the largest |difference| in
/// [2^(e - 1), 2^e) (float32 input on its coarse lattice, integer grids): scaled by
/// 2^(30 - e) (exact: a power of two, no under- or overflow in the expansion range)
/// each is an integer below 2^30, the cross products and lifts are below 2^61 (64
/// bits) and the determinant, three lift * cross products, below 2^124 (128 bits):
/// exact. Returns false where a scaled difference is not an integer (then the
/// expansions decide).
bool incircleOnLattice(const double (&d)[6], int& sign)
{
  // The largest |difference| by comparisons (no NaN here) and its exponent and the
  // scale 2^(30 - e) from the bits: the differences of coordinates in the expansion
  // range are 0 or normal with e in [-251, 202], so the bit patterns are those of
  // frexp and ldexp, without their library calls (indirect, through the PLT).
  double m = 0.0;
  for (const double v : d) {
    const double a = std::fabs(v);
    m = a > m ? a : m;
  }
  if (m == 0.0) {
    sign = 0;
    return true;
  }
  std::uint64_t bits = 0;
  std::memcpy(&bits, &m, sizeof bits);
  const int e = static_cast<int>((bits >> 52) & 0x7ffu) - 1022; // m in [2^(e-1), 2^e)
  const std::uint64_t scale_bits = static_cast<std::uint64_t>(1023 + 30 - e) << 52;
  double scale = 0.0;
  std::memcpy(&scale, &scale_bits, sizeof scale);
  std::int64_t k[6];
  for (int i = 0; i < 6; ++i) {
    const double v = d[i] * scale;
    k[i] = static_cast<std::int64_t>(v); // |v| < 2^30: defined
    if (static_cast<double>(k[i]) != v)
      return false;
  }
  const std::int64_t adx = k[0], ady = k[1], bdx = k[2], bdy = k[3], cdx = k[4],
                     cdy = k[5];
  const std::int64_t bc = bdx * cdy - cdx * bdy;
  const std::int64_t ca = cdx * ady - adx * cdy;
  const std::int64_t ab = adx * bdy - bdx * ady;
  const std::int64_t alift = adx * adx + ady * ady;
  const std::int64_t blift = bdx * bdx + bdy * bdy;
  const std::int64_t clift = cdx * cdx + cdy * cdy;
  const Int128 det = static_cast<Int128>(alift) * bc + static_cast<Int128>(blift) * ca +
                     static_cast<Int128>(clift) * ab;
  sign = det > 0 ? 1 : (det < 0 ? -1 : 0);
  return true;
}
#else
bool incircleOnLattice(const double (&)[6], int&)
{
  return false;
}
#endif

/// In-circle determinant when the coordinate differences are exact doubles
/// (Shewchuk's stage B, which is then exact), on stack arrays.
int incircleExactDifferences(double adx, double ady, double bdx, double bdy, double cdx,
                             double cdy)
{
  double bc[4], ca[4], ab[4];
  const int bcl = detail::crossZeroelim(bdx, cdy, cdx, bdy, bc);
  const int cal = detail::crossZeroelim(cdx, ady, adx, cdy, ca);
  const int abl = detail::crossZeroelim(adx, bdy, bdx, ady, ab);
  double adet[32], bdet[32], cdet[32], abdet[64], fin[96];
  const int al = liftedRow(adx, ady, bc, bcl, adet);
  const int bl = liftedRow(bdx, bdy, ca, cal, bdet);
  const int cl = liftedRow(cdx, cdy, ab, abl, cdet);
  const int abl2 = detail::sumZeroelim(al, adet, bl, bdet, abdet);
  const int fl = detail::sumZeroelim(abl2, abdet, cl, cdet, fin);
  return detail::signOf(fl, fin);
}

} // namespace

namespace {

/// Both products of orient2d(a, b, c) = (a.x - c.x)(b.y - c.y) - (a.y - c.y)(b.x - c.x)
/// have a zero factor (equal coordinates: their difference is exactly 0), so the
/// determinant is exactly 0: points on one row or column of a lattice (the float32
/// UTM input's coarse y), most of the ties the filters leave.
bool bothProductsZero(const Point2& a, const Point2& b, const Point2& c)
{
  return (a.x == c.x || b.y == c.y) && (a.y == c.y || b.x == c.x);
}

} // namespace

namespace detail {

Sign orient2dExact(const Point2& a, const Point2& b, const Point2& c)
{
  if (bothProductsZero(a, b, c))
    return Sign::ZERO;
  const bool in_range = allInExpansionRange<3>({&a, &b, &c});
  if (in_range && exactDifference(a.x, c.x) && exactDifference(a.y, c.y) &&
      exactDifference(b.x, c.x) && exactDifference(b.y, c.y))
    return toSign(orientExactDifferences(a.x - c.x, a.y - c.y, b.x - c.x, b.y - c.y));
  if (in_range)
    return toSign(orientExpansion(a, b, c));
  return toSign(orientBigInt(a, b, c));
}

Sign incircleExact(const Point2& a, const Point2& b, const Point2& c, const Point2& d)
{
  const bool in_range = allInExpansionRange<4>({&a, &b, &c, &d});
  if (in_range && exactDifference(a.x, d.x) && exactDifference(a.y, d.y) &&
      exactDifference(b.x, d.x) && exactDifference(b.y, d.y) &&
      exactDifference(c.x, d.x) && exactDifference(c.y, d.y)) {
    const double diff[6] = {a.x - d.x, a.y - d.y, b.x - d.x,
                            b.y - d.y, c.x - d.x, c.y - d.y};
    int sign = 0;
    if (incircleOnLattice(diff, sign))
      return toSign(sign);
    return toSign(
        incircleExactDifferences(diff[0], diff[1], diff[2], diff[3], diff[4], diff[5]));
  }
  if (in_range)
    return toSign(incircleExpansion(a, b, c, d));
  return toSign(incircleBigInt(a, b, c, d));
}

Sign orient2dOutOfLine(Point2 a, Point2 b, Point2 c)
{
  // orient2dExact's first case before the dynamic filter: the box filters' callers
  // (the cache blocks' walk) meet it on every lattice row and column.
  if (bothProductsZero(a, b, c))
    return Sign::ZERO;
  return orient2d(a, b, c);
}

Sign incirclePerturbedOutOfLine(Point2 a, Point2 b, Point2 c, Point2 d)
{
  return incirclePerturbed(a, b, c, d);
}

} // namespace detail

Sign incirclePerturbedTie(const Point2& a, const Point2& b, const Point2& c,
                          const Point2& d)
{
  // Lifting p to |p|^2 + eps_p changes the determinant by eps_p times p's cofactor in
  // the lift column; the largest eps with a non-zero cofactor decides the sign.
  struct Term {
    const Point2* p;
    int which;
  };
  std::array<Term, 4> terms{{{&a, 0}, {&b, 1}, {&c, 2}, {&d, 3}}};
  // Sorted by a stable insertion sort (equal points keep their order, as std::sort
  // does on four elements: its insertion sort), written out: the library's cost more
  // than the rest of the tie-break on float32 lattices, where ties are frequent.
  for (std::size_t i = 1; i < terms.size(); ++i) {
    const Term t = terms[i];
    std::size_t j = i;
    for (; j > 0 && lexLess(*t.p, *terms[j - 1].p); --j)
      terms[j] = terms[j - 1];
    terms[j] = t;
  }
  for (const Term& t : terms) {
    Sign cof = Sign::ZERO;
    switch (t.which) {
    case 0:
      cof = orient2d(b, c, d);
      break;
    case 1:
      cof = static_cast<Sign>(-static_cast<int>(orient2d(a, c, d)));
      break;
    case 2:
      cof = orient2d(a, b, d);
      break;
    default:
      cof = static_cast<Sign>(-static_cast<int>(orient2d(a, b, c)));
      break;
    }
    if (cof != Sign::ZERO)
      return cof;
  }
  return Sign::ZERO;
}

namespace {
// Below this |D| / (|u| |v|) the centre cannot be bounded usefully: no pruning.
constexpr double MIN_SINE = 1e-12;
// Edge-vector lengths for which no intermediate product under- or overflows.
constexpr double MIN_LENGTH = 1e-90;
constexpr double MAX_LENGTH = 1e90;
} // namespace

SafeDisk safeCircumdisk(const Point2& a, const Point2& b, const Point2& p)
{
  SafeDisk disk;
  const double ux = b.x - a.x, uy = b.y - a.y;
  const double vx = p.x - a.x, vy = p.y - a.y;
  const double u2 = ux * ux + uy * uy, v2 = vx * vx + vy * vy;
  // Upper bounds of |u| and |v| (within a factor sqrt 2), no square root: they only
  // loosen the error bound and the conditioning test.
  const double ulen = std::fabs(ux) + std::fabs(uy),
               vlen = std::fabs(vx) + std::fabs(vy);
  if (!(ulen >= 2.0 * MIN_LENGTH && ulen <= MAX_LENGTH && vlen >= 2.0 * MIN_LENGTH &&
        vlen <= MAX_LENGTH))
    return disk;
  const double uv = ulen * vlen;
  const double d = ux * vy - uy * vx;
  if (!(d > MIN_SINE * uv))
    return disk;
  // Centre relative to a: (vy |u|^2 - uy |v|^2, ux |v|^2 - vx |u|^2) / 2d.
  const double ox = (vy * u2 - uy * v2) / (2.0 * d);
  const double oy = (ux * v2 - vx * u2) / (2.0 * d);
  const double r = std::sqrt(ox * ox + oy * oy);
  // First-order bound: rounding of the differences, numerators and d, amplified by
  // the conditioning |u||v| / d (docs/algorithm.md).
  const double err =
      32.0 * detail::UNIT_ROUNDOFF * (uv * (ulen + vlen) / d + r * (uv / d + 1.0));
  disk.cx = a.x + ox;
  disk.cy = a.y + oy;
  disk.radius =
      r + err +
      8.0 * detail::UNIT_ROUNDOFF * (std::fabs(disk.cx) + std::fabs(disk.cy) + r);
  disk.valid =
      std::isfinite(disk.radius) && std::isfinite(disk.cx) && std::isfinite(disk.cy);
  return disk;
}

} // namespace pcl_vts
