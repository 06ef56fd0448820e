// orient2d, incircle and incirclePerturbed against exact rational arithmetic (every
// double is a dyadic rational, so the reference is exact). Inputs include points a few
// ulps off a line or circle where the plain double formula is shown to be wrong,
// huge, tiny (subnormal) and UTM-sized coordinates, and exactly cocircular integer
// points for the symbolic perturbation.
#include "support/generators.h"

#include <pcl_vts/core/predicates.h>

#include <boost/multiprecision/cpp_int.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace pcl_vts {
namespace {

using Rational = boost::multiprecision::cpp_rational;
using BigInt = boost::multiprecision::cpp_int;

Rational exact(double v)
{
  if (v == 0.0)
    return Rational(0);
  int e = 0;
  const double m = std::frexp(v, &e); // v = m 2^e, 0.5 <= |m| < 1
  const auto mantissa = static_cast<long long>(std::ldexp(m, 53));
  e -= 53;
  Rational r(mantissa);
  if (e > 0)
    r *= Rational(BigInt(1) << e);
  else if (e < 0)
    r /= Rational(BigInt(1) << -e);
  return r;
}

Sign toSign(int s)
{
  return s > 0 ? Sign::POSITIVE : (s < 0 ? Sign::NEGATIVE : Sign::ZERO);
}

Sign negate(Sign s)
{
  return toSign(-static_cast<int>(s));
}

Sign orientRational(const Point2& a, const Point2& b, const Point2& c)
{
  const Rational acx = exact(a.x) - exact(c.x), acy = exact(a.y) - exact(c.y);
  const Rational bcx = exact(b.x) - exact(c.x), bcy = exact(b.y) - exact(c.y);
  const Rational det = acx * bcy - acy * bcx;
  return toSign(det.sign());
}

/// v * 2^1074 as an integer: exact for every finite double (subnormals included).
BigInt scaledInteger(double v)
{
  const Rational r = exact(v) * Rational(BigInt(1) << 1074);
  return numerator(r);
}

/// Sign of det | X_i - X_d, Y_i - Y_d, W_i - W_d |, i = a, b, c: the 4x4 lifted
/// determinant | x y w 1 | (rows a, b, c, d) after subtracting row d, with x, y scaled
/// by 2^1074 and w by 2^W_SHIFT (both positive factors: the sign is unchanged).
constexpr int W_SHIFT = 8000;
constexpr int EPS_BITS = 2000; // eps = 2^-2000

Sign liftedDeterminant(const std::array<Point2, 4>& p,
                       const std::array<int, 4>& eps_power)
{
  std::array<BigInt, 4> x, y, w;
  for (int i = 0; i < 4; ++i) {
    x[i] = scaledInteger(p[i].x);
    y[i] = scaledInteger(p[i].y);
    // |p|^2 = (x^2 + y^2) 2^-2148; eps^k = 2^(-2000 k): both integers at 2^8000.
    w[i] = (x[i] * x[i] + y[i] * y[i]) << (W_SHIFT - 2 * 1074);
    if (eps_power[i] > 0)
      w[i] += BigInt(1) << (W_SHIFT - EPS_BITS * eps_power[i]);
  }
  BigInt m[3][3];
  for (int i = 0; i < 3; ++i) {
    m[i][0] = x[i] - x[3];
    m[i][1] = y[i] - y[3];
    m[i][2] = w[i] - w[3];
  }
  const BigInt det = m[0][0] * (m[1][1] * m[2][2] - m[2][1] * m[1][2]) -
                     m[1][0] * (m[0][1] * m[2][2] - m[2][1] * m[0][2]) +
                     m[2][0] * (m[0][1] * m[1][2] - m[1][1] * m[0][2]);
  return toSign(det.sign());
}

Sign incircleRational(const Point2& a, const Point2& b, const Point2& c,
                      const Point2& d)
{
  return liftedDeterminant({a, b, c, d}, {0, 0, 0, 0});
}

/// The perturbed lift |p|^2 + eps^rank(p), rank 1 for the lexicographically smallest
/// point (the largest perturbation), eps = 2^-2000: far below any cofactor of the
/// inputs used here (small dyadic coordinates).
Sign incirclePerturbedRational(const Point2& a, const Point2& b, const Point2& c,
                               const Point2& d)
{
  const std::array<Point2, 4> p = {a, b, c, d};
  std::array<int, 4> order = {0, 1, 2, 3};
  std::sort(order.begin(), order.end(),
            [&](int l, int r) { return lexLess(p[l], p[r]); });
  std::array<int, 4> rank{};
  for (int k = 0; k < 4; ++k)
    rank[order[k]] = k + 1;
  return liftedDeterminant(p, rank);
}

/// The textbook double formulas the predicates must improve on.
Sign naiveOrient(const Point2& a, const Point2& b, const Point2& c)
{
  const double det = (a.x - c.x) * (b.y - c.y) - (a.y - c.y) * (b.x - c.x);
  return det > 0 ? Sign::POSITIVE : (det < 0 ? Sign::NEGATIVE : Sign::ZERO);
}

Sign naiveIncircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d)
{
  const double adx = a.x - d.x, ady = a.y - d.y;
  const double bdx = b.x - d.x, bdy = b.y - d.y;
  const double cdx = c.x - d.x, cdy = c.y - d.y;
  const double det = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
                     (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
                     (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
  return det > 0 ? Sign::POSITIVE : (det < 0 ? Sign::NEGATIVE : Sign::ZERO);
}

double stepUlps(double v, int k)
{
  const double dir = k > 0 ? std::numeric_limits<double>::infinity()
                           : -std::numeric_limits<double>::infinity();
  for (int i = 0; i < std::abs(k); ++i)
    v = std::nextafter(v, dir);
  return v;
}

Point2 scaled(const Point2& p, int exponent)
{
  return {std::ldexp(p.x, exponent), std::ldexp(p.y, exponent)};
}

/// Checks orient2d and the exact slow path against rationals; returns whether the
/// naive formula was wrong.
bool expectOrientExact(const Point2& a, const Point2& b, const Point2& c)
{
  const Sign expected = orientRational(a, b, c);
  EXPECT_EQ(orient2d(a, b, c), expected)
      << "a=(" << a.x << "," << a.y << ") b=(" << b.x << "," << b.y << ") c=(" << c.x
      << "," << c.y << ")";
  EXPECT_EQ(detail::orient2dExact(a, b, c), expected);
  return naiveOrient(a, b, c) != expected;
}

/// What the naive formula got wrong: any answer, and strict sign flips.
struct NaiveErrors {
  int wrong = 0;
  int flipped = 0;
  NaiveErrors& operator+=(const NaiveErrors& o)
  {
    wrong += o.wrong;
    flipped += o.flipped;
    return *this;
  }
};

NaiveErrors expectIncircleExact(const Point2& a, const Point2& b, const Point2& c,
                                const Point2& d)
{
  const Sign expected = incircleRational(a, b, c, d);
  EXPECT_EQ(incircle(a, b, c, d), expected)
      << "a=(" << a.x << "," << a.y << ") b=(" << b.x << "," << b.y << ") c=(" << c.x
      << "," << c.y << ") d=(" << d.x << "," << d.y << ")";
  EXPECT_EQ(detail::incircleExact(a, b, c, d), expected);
  const Sign naive = naiveIncircle(a, b, c, d);
  NaiveErrors errors;
  errors.wrong = naive != expected;
  errors.flipped = naive != expected && naive != Sign::ZERO && expected != Sign::ZERO;
  return errors;
}

Point2 randomPoint(std::mt19937_64& rng, double lo, double hi)
{
  std::uniform_real_distribution<double> u(lo, hi);
  const double x = u(rng);
  return {x, u(rng)};
}

// Shewchuk's example: a walks a 64 x 64 ulp grid around a point of the line through b
// and c. Roughly half the naive answers are wrong there.
std::vector<std::array<Point2, 3>> nearLineTriples(const Point2& a0, const Point2& b,
                                                   const Point2& c)
{
  std::vector<std::array<Point2, 3>> triples;
  for (int i = -32; i < 32; ++i)
    for (int j = -32; j < 32; ++j)
      triples.push_back({Point2{stepUlps(a0.x, i), stepUlps(a0.y, j)}, b, c});
  return triples;
}

TEST(Orient2d, MatchesExactOnRandomPoints)
{
  std::mt19937_64 rng(1);
  for (double scale : {1e-3, 1.0, 1e3, 1e9}) {
    for (int k = 0; k < 2000; ++k)
      expectOrientExact(randomPoint(rng, -scale, scale),
                        randomPoint(rng, -scale, scale),
                        randomPoint(rng, -scale, scale));
  }
}

TEST(Orient2d, ExactWhereNaiveFormulaIsWrongNearALine)
{
  int naive_wrong = 0, zero = 0;
  for (const auto& t : nearLineTriples({0.5, 0.5}, {12.0, 12.0}, {24.0, 24.0})) {
    naive_wrong += expectOrientExact(t[0], t[1], t[2]);
    zero += orient2d(t[0], t[1], t[2]) == Sign::ZERO;
  }
  // The test proves something only if the naive formula actually fails here.
  EXPECT_GT(naive_wrong, 100);
  EXPECT_GT(zero, 0); // the points exactly on the line are found too
}

/// x, y with g = gcd(p, q) = p x + q y (extended Euclid).
long long extendedGcd(long long p, long long q, long long& x, long long& y)
{
  if (q == 0) {
    x = 1;
    y = 0;
    return p;
  }
  long long x1 = 0, y1 = 0;
  const long long g = extendedGcd(q, p % q, x1, y1);
  x = y1;
  y = x1 - (p / q) * y1;
  return g;
}

/// Triples {a, b, c} on the ulp grid U = 2^-30 around b = (5e5, 5.4e6): c = b + 3 U (p,
/// q) for a random coprime step (p, q) of about 1 m, and five points a = b + U (-y + j
/// p, x + j q) (j = -2..2, p x + q y = 1), each exactly one ulp^2 left of b -> c. At
/// these magnitudes every difference is exact (Sterbenz): only the products round.
std::vector<std::array<Point2, 3>> ulpOffLineTriples(std::mt19937_64& rng,
                                                     std::size_t count)
{
  const double U = 0x1p-30;
  const Point2 b = {5.0e5, 5.4e6};
  std::uniform_int_distribution<long long> step(1LL << 29, 1LL << 31);
  std::vector<std::array<Point2, 3>> triples;
  while (triples.size() < count) {
    const long long p = step(rng), q = step(rng);
    long long x = 0, y = 0;
    if (extendedGcd(p, q, x, y) != 1)
      continue;
    const Point2 c = {b.x + static_cast<double>(3 * p) * U,
                      b.y + static_cast<double>(3 * q) * U};
    for (long long j = -2; j <= 2; ++j) {
      const double ax = static_cast<double>(-y + j * p),
                   ay = static_cast<double>(x + j * q);
      const Point2 a = {b.x + ax * U, b.y + ay * U};
      EXPECT_EQ(a.x - b.x, ax * U); // on the grid: the construction is exact
      EXPECT_EQ(a.y - b.y, ay * U);
      triples.push_back({a, b, c});
    }
  }
  return triples;
}

TEST(Orient2d, ExactNearALineAtUtmMagnitudes)
{
  // At UTM magnitudes every difference of nearby coordinates is exact (Sterbenz), so
  // the naive formula fails only when the cross product, in ulp^2 units, is tiny
  // against the products. Build such points: on the ulp grid U = 2^-30 around
  // (5e5, 5.4e6), the line from b along the coprime step (p, q) ~ 1 m, and a at
  // integer offset (-y, x) with p x + q y = 1, i.e. exactly one ulp^2 off the line.
  std::mt19937_64 rng(2);
  int naive_wrong = 0, tested = 0;
  for (const auto& [a, b, c] : ulpOffLineTriples(rng, 250)) {
    EXPECT_EQ(orient2d(b, c, a), Sign::POSITIVE) << "cross product = +1 ulp^2";
    EXPECT_EQ(orient2d(c, b, a), Sign::NEGATIVE);
    naive_wrong += expectOrientExact(a, b, c);
    ++tested;
  }
  EXPECT_GT(naive_wrong, tested / 2);
}

TEST(Orient2d, ExactForHugeCoordinates)
{
  // Shewchuk's grid scaled by 2^990: exactly the same signs, but every naive product
  // overflows (1e300^2 = inf).
  int naive_wrong = 0;
  for (const auto& t : nearLineTriples({0.5, 0.5}, {12.0, 12.0}, {24.0, 24.0})) {
    const Point2 a = scaled(t[0], 990), b = scaled(t[1], 990), c = scaled(t[2], 990);
    naive_wrong += expectOrientExact(a, b, c);
    EXPECT_EQ(orient2d(a, b, c), orient2d(t[0], t[1], t[2]));
  }
  EXPECT_GT(naive_wrong, 0);
  std::mt19937_64 rng(3);
  for (int k = 0; k < 500; ++k)
    expectOrientExact(randomPoint(rng, -1e300, 1e300), randomPoint(rng, -1e300, 1e300),
                      randomPoint(rng, -1e300, 1e300));
  const double big = std::numeric_limits<double>::max();
  expectOrientExact({-big, -big}, {big, -big}, {big, big});
  expectOrientExact({-big, -big}, {0.0, 0.0}, {big, big});
}

TEST(Orient2d, ExactForTinyAndSubnormalCoordinates)
{
  int naive_wrong = 0;
  for (const auto& t : nearLineTriples({0.5, 0.5}, {12.0, 12.0}, {24.0, 24.0}))
    naive_wrong += expectOrientExact(scaled(t[0], -1000), scaled(t[1], -1000),
                                     scaled(t[2], -1000));
  EXPECT_GT(naive_wrong, 0);
  // Integer multiples of the smallest subnormal: the exact sign is the integer one,
  // while every naive product underflows to zero.
  const double tiny = std::numeric_limits<double>::denorm_min();
  std::mt19937_64 rng(4);
  std::uniform_int_distribution<int> coord(-1000, 1000), off(-1, 1);
  for (int k = 0; k < 2000; ++k) {
    const int ax = coord(rng), ay = coord(rng), dx = coord(rng), dy = coord(rng);
    const int t = coord(rng) % 7;
    const Point2 a = {ax * tiny, ay * tiny};
    const Point2 b = {(ax + dx) * tiny, (ay + dy) * tiny};
    const Point2 c = {(ax + t * dx + off(rng)) * tiny, (ay + t * dy + off(rng)) * tiny};
    const long long integer_det =
        static_cast<long long>(dx) * (static_cast<long long>(c.y / tiny) - ay) -
        static_cast<long long>(dy) * (static_cast<long long>(c.x / tiny) - ax);
    naive_wrong += expectOrientExact(a, b, c);
    EXPECT_EQ(orient2d(a, b, c),
              toSign(integer_det > 0 ? 1 : (integer_det < 0 ? -1 : 0)));
  }
  for (int k = 0; k < 500; ++k)
    expectOrientExact(randomPoint(rng, -1e-300, 1e-300),
                      randomPoint(rng, -1e-300, 1e-300),
                      randomPoint(rng, -1e-300, 1e-300));
}

TEST(Orient2d, AntisymmetricAndCyclic)
{
  std::mt19937_64 rng(5);
  for (const auto& t : nearLineTriples({0.5, 0.5}, {12.0, 12.0}, {24.0, 24.0})) {
    const Sign s = orient2d(t[0], t[1], t[2]);
    EXPECT_EQ(orient2d(t[1], t[2], t[0]), s);
    EXPECT_EQ(orient2d(t[1], t[0], t[2]), negate(s));
  }
}

/// a, b, c on a circle, d a few ulps around a fourth point of it. With the centre
/// off the origin and radius and coordinates of similar size, the differences in the
/// naive formula are rounded and its sign is often wrong.
NaiveErrors checkNearCircle(const Point2& centre, double radius, double t0, int ulps)
{
  const auto on = [&](double t) {
    return Point2{centre.x + radius * std::cos(t), centre.y + radius * std::sin(t)};
  };
  const Point2 a = on(t0), b = on(t0 + 2.1), c = on(t0 + 3.9);
  const Point2 d0 = on(t0 + 5.3);
  NaiveErrors errors;
  for (int i = -ulps; i <= ulps; ++i)
    for (int j = -ulps; j <= ulps; ++j)
      errors += expectIncircleExact(a, b, c, {stepUlps(d0.x, i), stepUlps(d0.y, j)});
  return errors;
}

TEST(Incircle, MatchesExactOnRandomPoints)
{
  std::mt19937_64 rng(6);
  for (double scale : {1e-3, 1.0, 1e3, 1e9}) {
    for (int k = 0; k < 1000; ++k)
      expectIncircleExact(
          randomPoint(rng, -scale, scale), randomPoint(rng, -scale, scale),
          randomPoint(rng, -scale, scale), randomPoint(rng, -scale, scale));
  }
}

TEST(Incircle, ExactWhereNaiveFormulaIsWrongNearACircle)
{
  NaiveErrors errors;
  for (int k = 0; k < 6; ++k)
    errors += checkNearCircle({0.7 + 0.1 * k, -0.3}, 1.3, 0.2 * k, 8);
  EXPECT_GT(errors.flipped, 0); // inside called outside or the reverse
}

TEST(Incircle, ExactNearACircleAtUtmMagnitudes)
{
  // Differences are exact at UTM magnitudes, so the naive formula errs only when the
  // determinant is tiny against the products: exactly cocircular points. Integer
  // points of one circle (radius 396,439 ulps), scaled by 2049 to ~0.75 m, on the
  // ulp grid U = 2^-30 around (5e5, 5.4e6); d exactly on the circle or 1 ulp off.
  const std::vector<double> xy =
      test::latticeCircle(5LL * 13 * 17 * 29 * 37 * 41 * 53 * 61);
  ASSERT_EQ(xy.size(), 2u * 1024u);
  const double U = 0x1p-30;
  const auto at = [&](std::size_t i) {
    return Point2{5.0e5 + 2049.0 * xy[2 * i] * U, 5.4e6 + 2049.0 * xy[2 * i + 1] * U};
  };
  std::mt19937_64 rng(12);
  std::uniform_int_distribution<std::size_t> pick(0, xy.size() / 2 - 1);
  NaiveErrors on_circle;
  for (int k = 0; k < 300; ++k) {
    const Point2 a = at(pick(rng)), b = at(pick(rng)), c = at(pick(rng)),
                 d = at(pick(rng));
    if (a == b || a == c || a == d || b == c || b == d || c == d)
      continue;
    ASSERT_EQ(incircle(a, b, c, d), Sign::ZERO);
    on_circle += expectIncircleExact(a, b, c, d);
    for (int i = -1; i <= 1; i += 2) {
      expectIncircleExact(a, b, c, {stepUlps(d.x, i), d.y});
      expectIncircleExact(a, b, c, {d.x, stepUlps(d.y, i)});
    }
  }
  EXPECT_GT(on_circle.wrong, 0); // the naive formula misses exact cocircularity
}

TEST(Incircle, ExactOnFloat32LatticesAtUtmMagnitudes)
{
  // float32 UTM coordinates (the ISPRS files): x on a 2^-5 lattice, y on a 2^-1 one,
  // differences exact, so incircleExact takes its integer path (differences of at
  // most 30 bits above their power of two) or, where the spread needs more bits, the
  // expansions; both against rationals. Lattice circles give exactly cocircular
  // quadruples, shifting d by one lattice step the near misses.
  std::mt19937_64 rng(31);
  const auto f32 = [](double x, double y) {
    return Point2{static_cast<float>(x), static_cast<float>(y)};
  };
  std::uniform_real_distribution<double> spread(-40.0, 40.0);
  for (int k = 0; k < 3000; ++k) {
    const double w = k % 3 == 0 ? 1.0 : (k % 3 == 1 ? 0.05 : 4000.0);
    const auto p = [&] {
      return f32(5.0e5 + w * spread(rng), 5.4e6 + w * spread(rng));
    };
    expectIncircleExact(p(), p(), p(), p());
  }
  const std::vector<double> xy = test::latticeCircle(5LL * 13 * 17 * 29);
  std::uniform_int_distribution<std::size_t> pick(0, xy.size() / 2 - 1);
  int zero = 0;
  for (int k = 0; k < 600; ++k) {
    // Steps of 2^-1 in both coordinates keep float32 exact at 5.4e6 (its ulp 2^-1).
    const double step = k % 2 == 0 ? 0.5 : 1.0;
    const auto at = [&](std::size_t i) {
      return f32(5.0e5 + step * xy[2 * i], 5.4e6 + step * xy[2 * i + 1]);
    };
    const Point2 a = at(pick(rng)), b = at(pick(rng)), c = at(pick(rng)),
                 d = at(pick(rng));
    if (a == b || a == c || a == d || b == c || b == d || c == d)
      continue;
    zero += incircleRational(a, b, c, d) == Sign::ZERO;
    expectIncircleExact(a, b, c, d);
    expectIncircleExact(a, b, c, {d.x + 0.5, d.y});
    expectIncircleExact(a, b, c, {d.x, d.y - 0.5});
  }
  EXPECT_GT(zero, 300);
}

TEST(Orient2d, ExactWhereTheRoundedProductsAreEqual)
{
  // acx bcy and acy bcx round to the same double and differ by a few units: the sign
  // comes from their rounding errors. (2^27 + 1)(2^27 - 1) = 2^54 - 1 rounds to 2^54.
  const double t = 0x1p27;
  int tied = 0;
  for (const Point2 c : {Point2{0.0, 0.0}, Point2{-t, 3.0 * t}})
    for (int i = -3; i <= 3; ++i)
      for (int j = -3; j <= 3; ++j)
        for (int l = -3; l <= 3; ++l) {
          const Point2 a{c.x + t + i, c.y + t + j}, b{c.x + t + l, c.y + t - i};
          tied += (a.x - c.x) * (b.y - c.y) == (a.y - c.y) * (b.x - c.x);
          expectOrientExact(a, b, c);
          expectOrientExact(b, a, c);
        }
  EXPECT_GT(tied, 20);
}

TEST(Orient2d, ExactOnSharedRowsAndColumns)
{
  // float32 UTM points from three x and three y values: many triples share a row or a
  // column, so a product of orient2d's determinant is exactly zero (orient2dExact
  // answers ZERO at once when both are), or only one is and the sign is the other's.
  const auto f32 = [](double x, double y) {
    return Point2{static_cast<float>(x), static_cast<float>(y)};
  };
  const double xs[3] = {5.0e5, 5.0e5 + 0.03125, 5.0e5 + 1.5};
  const double ys[3] = {5.4e6, 5.4e6 + 0.5, 5.4e6 + 2.0};
  std::vector<Point2> pts;
  for (const double x : xs)
    for (const double y : ys)
      pts.push_back(f32(x, y));
  // The box filter of the cache blocks' walk, with the box of these points and a
  // far wider one (no test decided by the filter there: the bound exceeds every
  // determinant), takes the same shortcut.
  const double bound = detail::boxBounds(xs[0], xs[2], ys[0], ys[2]).orient;
  const double wide =
      detail::boxBounds(xs[0] - 1e8, xs[2] + 1e8, ys[0] - 1e8, ys[2] + 1e8).orient;
  int both_zero = 0, one_zero = 0;
  for (const Point2& a : pts)
    for (const Point2& b : pts)
      for (const Point2& c : pts) {
        const bool left = a.x == c.x || b.y == c.y, right = a.y == c.y || b.x == c.x;
        both_zero += left && right;
        one_zero += left != right;
        expectOrientExact(a, b, c);
        EXPECT_EQ(detail::orient2dInBox(a, b, c, bound), orientRational(a, b, c));
        EXPECT_EQ(detail::orient2dInBox(a, b, c, wide), orientRational(a, b, c));
      }
  EXPECT_GT(both_zero, 100);
  EXPECT_GT(one_zero, 100);
}

/// The points of {0..side-1}^2, column by column: small grids are full of
/// cocircular quadruples and collinear triples.
std::vector<Point2> integerGrid(int side)
{
  std::vector<Point2> grid;
  for (int x = 0; x < side; ++x)
    for (int y = 0; y < side; ++y)
      grid.push_back({static_cast<double>(x), static_cast<double>(y)});
  return grid;
}

TEST(IncirclePerturbed, EqualPointsKeepTheirOrderInTheTieBreak)
{
  // Coordinates in {0..2}^2 with repeated points: the tie-break ranks equal points in
  // argument order (a stable sort), as the perturbed lift's reference does.
  const std::vector<Point2> grid = integerGrid(3);
  std::mt19937_64 rng(12);
  std::uniform_int_distribution<std::size_t> pick(0, grid.size() - 1);
  int repeated = 0;
  for (int k = 0; k < 3000; ++k) {
    const Point2 a = grid[pick(rng)], b = grid[pick(rng)], c = grid[pick(rng)],
                 d = grid[pick(rng)];
    repeated += a == b || a == c || a == d || b == c || b == d || c == d;
    EXPECT_EQ(incirclePerturbed(a, b, c, d), incirclePerturbedRational(a, b, c, d));
  }
  EXPECT_GT(repeated, 1000);
}

TEST(Incircle, ExactForHugeAndTinyCoordinates)
{
  NaiveErrors errors;
  std::mt19937_64 rng(7);
  for (int k = 0; k < 3; ++k) {
    const auto on = [&](double t) {
      return Point2{0.7 + 1.3 * std::cos(t), 1.3 * std::sin(t)};
    };
    const Point2 a = on(0.1 * k), b = on(2.0), c = on(4.0), d0 = on(5.5);
    for (int i = -3; i <= 3; ++i) {
      for (int j = -3; j <= 3; ++j) {
        const Point2 d = {stepUlps(d0.x, i), stepUlps(d0.y, j)};
        const Sign unscaled = incircle(a, b, c, d);
        // Scaling by 2^e multiplies the determinant by 2^4e: same sign, exact inputs.
        for (int e : {250, 900, 1010, -500, -1000}) {
          errors += expectIncircleExact(scaled(a, e), scaled(b, e), scaled(c, e),
                                        scaled(d, e));
          EXPECT_EQ(incircle(scaled(a, e), scaled(b, e), scaled(c, e), scaled(d, e)),
                    unscaled)
              << "scale 2^" << e;
        }
      }
    }
  }
  EXPECT_GT(errors.wrong, 0); // overflow to inf/nan, underflow to 0
  for (double scale : {1e300, 1e-300, 1e-310}) {
    for (int k = 0; k < 200; ++k)
      expectIncircleExact(
          randomPoint(rng, -scale, scale), randomPoint(rng, -scale, scale),
          randomPoint(rng, -scale, scale), randomPoint(rng, -scale, scale));
  }
}

TEST(Incircle, ZeroOnExactlyCocircularPoints)
{
  const std::vector<double> xy = test::latticeCircle(5LL * 13 * 17 * 29); // 64 points
  const std::size_t m = xy.size() / 2;
  ASSERT_EQ(m, 64u);
  std::mt19937_64 rng(8);
  std::uniform_int_distribution<std::size_t> pick(0, m - 1);
  for (int k = 0; k < 300; ++k) {
    const std::size_t i = pick(rng), j = pick(rng), l = pick(rng), q = pick(rng);
    if (i == j || i == l || i == q || j == l || j == q || l == q)
      continue;
    const auto p = [&](std::size_t s) {
      return Point2{xy[2 * s] + 4e6, xy[2 * s + 1] - 3e5};
    };
    EXPECT_EQ(incircle(p(i), p(j), p(l), p(q)), Sign::ZERO);
  }
}

TEST(IncirclePerturbed, EqualsIncircleWhenNotZero)
{
  std::mt19937_64 rng(9);
  for (int k = 0; k < 5000; ++k) {
    const Point2 a = randomPoint(rng, -1, 1), b = randomPoint(rng, -1, 1),
                 c = randomPoint(rng, -1, 1), d = randomPoint(rng, -1, 1);
    const Sign s = incircle(a, b, c, d);
    ASSERT_NE(s, Sign::ZERO);
    EXPECT_EQ(incirclePerturbed(a, b, c, d), s);
  }
  for (int k = 0; k < 6; ++k) {
    const auto on = [&](double t) {
      return Point2{0.7 + 1.3 * std::cos(t), 1.3 * std::sin(t)};
    };
    const Point2 a = on(0.1 * k), b = on(2.0), c = on(4.0), d0 = on(5.5);
    for (int i = -4; i <= 4; ++i)
      for (int j = -4; j <= 4; ++j) {
        const Point2 d = {stepUlps(d0.x, i), stepUlps(d0.y, j)};
        const Sign s = incircle(a, b, c, d);
        if (s != Sign::ZERO) {
          EXPECT_EQ(incirclePerturbed(a, b, c, d), s);
        }
      }
  }
}

/// Four distinct points: the perturbed sign must equal the perturbed lifted
/// determinant, be ZERO exactly when all four are collinear, and flip when two of
/// a, b, c are swapped.
void expectPerturbedConsistent(const Point2& a, const Point2& b, const Point2& c,
                               const Point2& d)
{
  const Sign s = incirclePerturbed(a, b, c, d);
  const bool all_collinear = orientRational(a, b, c) == Sign::ZERO &&
                             orientRational(a, b, d) == Sign::ZERO &&
                             orientRational(a, c, d) == Sign::ZERO;
  EXPECT_EQ(s == Sign::ZERO, all_collinear)
      << "a=(" << a.x << "," << a.y << ") b=(" << b.x << "," << b.y << ") c=(" << c.x
      << "," << c.y << ") d=(" << d.x << "," << d.y << ")";
  EXPECT_EQ(s, incirclePerturbedRational(a, b, c, d))
      << "a=(" << a.x << "," << a.y << ") b=(" << b.x << "," << b.y << ") c=(" << c.x
      << "," << c.y << ") d=(" << d.x << "," << d.y << ")";
  EXPECT_EQ(incirclePerturbed(b, a, c, d), negate(s));
  EXPECT_EQ(incirclePerturbed(a, c, b, d), negate(s));
  EXPECT_EQ(incirclePerturbed(c, b, a, d), negate(s));
  EXPECT_EQ(incirclePerturbed(b, c, a, d), s);
}

TEST(IncirclePerturbed, CocircularLatticePointsMatchPerturbedLift)
{
  const std::vector<double> xy = test::latticeCircle(5LL * 13 * 17 * 29);
  const std::size_t m = xy.size() / 2;
  std::mt19937_64 rng(10);
  std::uniform_int_distribution<std::size_t> pick(0, m - 1);
  int tested = 0;
  for (int k = 0; k < 400; ++k) {
    const std::size_t i = pick(rng), j = pick(rng), l = pick(rng), q = pick(rng);
    if (i == j || i == l || i == q || j == l || j == q || l == q)
      continue;
    // Integer shift and power-of-two scale keep the points exactly cocircular.
    const double ox = (k % 3 == 0) ? 5.0e5 : 0.0, oy = (k % 3 == 0) ? 5.4e6 : -7.0;
    const int e = (k % 5) - 2;
    const auto p = [&](std::size_t s) {
      return Point2{std::ldexp(xy[2 * s] + ox, e), std::ldexp(xy[2 * s + 1] + oy, e)};
    };
    ASSERT_EQ(incircle(p(i), p(j), p(l), p(q)), Sign::ZERO);
    expectPerturbedConsistent(p(i), p(j), p(l), p(q));
    EXPECT_NE(incirclePerturbed(p(i), p(j), p(l), p(q)), Sign::ZERO);
    ++tested;
  }
  EXPECT_GT(tested, 300);
}

TEST(IncirclePerturbed, SmallIntegerGridDegeneraciesMatchPerturbedLift)
{
  // Coordinates in {0..3}^2: cocircular squares, collinear triples and quadruples.
  const std::vector<Point2> grid = integerGrid(4);
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::size_t> pick(0, grid.size() - 1);
  int zero = 0, cocircular = 0;
  for (int k = 0; k < 3000; ++k) {
    const std::size_t i = pick(rng), j = pick(rng), l = pick(rng), q = pick(rng);
    if (i == j || i == l || i == q || j == l || j == q || l == q)
      continue;
    expectPerturbedConsistent(grid[i], grid[j], grid[l], grid[q]);
    zero += incirclePerturbed(grid[i], grid[j], grid[l], grid[q]) == Sign::ZERO;
    cocircular += incircle(grid[i], grid[j], grid[l], grid[q]) == Sign::ZERO;
  }
  EXPECT_GT(zero, 0);          // all-collinear quadruples were drawn
  EXPECT_GT(cocircular, zero); // and cocircular ones that are not collinear
  // The unit square both ways round: exactly one diagonal wins the tie.
  const Point2 p00{0, 0}, p10{1, 0}, p11{1, 1}, p01{0, 1};
  const Sign diag_a = incirclePerturbed(p00, p10, p11, p01); // edge 00-11
  const Sign diag_b = incirclePerturbed(p10, p11, p01, p00); // edge 10-01
  EXPECT_NE(diag_a, Sign::ZERO);
  EXPECT_NE(diag_b, Sign::ZERO);
  EXPECT_NE(diag_a == Sign::POSITIVE, diag_b == Sign::POSITIVE);
}

// The box filters (detail::boxBounds, orient2dInBox, incirclePerturbedInBox, used by
// the cache blocks' Bowyer-Watson) must return exactly what orient2d and
// incirclePerturbed return for every point inside the box. Each family below is
// checked against them with the tightest box of its points (the smallest bound, the
// hardest case), and is shown to be adversarial: the plain determinant (the naive
// formula, the same expression) gets some signs wrong there.
struct BoxCheck {
  int tested = 0;
  int plain_wrong = 0; ///< answers of the naive formula that differ
};

detail::BoxBounds tightBox(const std::vector<Point2>& points)
{
  double x_lo = points[0].x, x_hi = x_lo, y_lo = points[0].y, y_hi = y_lo;
  for (const Point2& q : points) {
    x_lo = std::min(x_lo, q.x);
    x_hi = std::max(x_hi, q.x);
    y_lo = std::min(y_lo, q.y);
    y_hi = std::max(y_hi, q.y);
  }
  return detail::boxBounds(x_lo, x_hi, y_lo, y_hi);
}

void checkOrientInBox(const std::vector<std::array<Point2, 3>>& triples, BoxCheck& out)
{
  std::vector<Point2> all;
  for (const auto& t : triples)
    all.insert(all.end(), t.begin(), t.end());
  const detail::BoxBounds box = tightBox(all);
  for (const auto& t0 : triples)
    for (int r = 0; r < 3; ++r) { // each rotation: another pivot, other roundings
      const std::array<Point2, 3> t = {t0[r], t0[(r + 1) % 3], t0[(r + 2) % 3]};
      const Sign expected = orient2d(t[0], t[1], t[2]);
      EXPECT_EQ(
          detail::orient2dInBox(t[0], t[1], t[2], tightBox({t[0], t[1], t[2]}).orient),
          expected);
      EXPECT_EQ(detail::orient2dInBox(t[0], t[1], t[2], box.orient), expected)
          << "a=(" << t[0].x << "," << t[0].y << ") b=(" << t[1].x << "," << t[1].y
          << ") c=(" << t[2].x << "," << t[2].y << ")";
      EXPECT_EQ(expected, orientRational(t[0], t[1], t[2]));
      out.plain_wrong += naiveOrient(t[0], t[1], t[2]) != expected;
      ++out.tested;
    }
}

/// Bit for bit (both NaN counts as equal: the payload is not specified).
bool sameDouble(double x, double y)
{
  if (std::isnan(x) || std::isnan(y))
    return std::isnan(x) && std::isnan(y);
  std::uint64_t bx = 0, by = 0;
  std::memcpy(&bx, &x, sizeof x);
  std::memcpy(&by, &y, sizeof y);
  return bx == by;
}

void checkIncircleInBox(const std::vector<std::array<Point2, 4>>& quads, BoxCheck& out)
{
  std::vector<Point2> all;
  for (const auto& q : quads)
    all.insert(all.end(), q.begin(), q.end());
  const detail::BoxBounds box = tightBox(all);
  for (const auto& q : quads) {
    const Sign expected = incirclePerturbed(q[0], q[1], q[2], q[3]);
    EXPECT_TRUE(sameDouble(detail::incircleDet(q[0], q[1], q[2], q[3]),
                           detail::incircleTerms(q[0], q[1], q[2], q[3]).det));
    EXPECT_EQ(detail::incirclePerturbedInBox(
                  q[0], q[1], q[2], q[3], tightBox({q[0], q[1], q[2], q[3]}).incircle),
              expected);
    EXPECT_EQ(detail::incirclePerturbedInBox(q[0], q[1], q[2], q[3], box.incircle),
              expected)
        << "a=(" << q[0].x << "," << q[0].y << ") b=(" << q[1].x << "," << q[1].y
        << ") c=(" << q[2].x << "," << q[2].y << ") d=(" << q[3].x << "," << q[3].y
        << ")";
    const Sign exact = incircleRational(q[0], q[1], q[2], q[3]);
    if (exact != Sign::ZERO) {
      EXPECT_EQ(expected, exact);
    }
    out.plain_wrong += naiveIncircle(q[0], q[1], q[2], q[3]) != expected;
    ++out.tested;
  }
}

TEST(BoxFilters, OrientEqualsOrient2dNearLines)
{
  BoxCheck check;
  // Shewchuk's ulp grid near a line, as is and at UTM-like magnitudes (2^19 ~ 5e5).
  checkOrientInBox(nearLineTriples({0.5, 0.5}, {12.0, 12.0}, {24.0, 24.0}), check);
  std::vector<std::array<Point2, 3>> utm;
  for (const auto& t : nearLineTriples({0.5, 0.5}, {12.0, 12.0}, {24.0, 24.0}))
    utm.push_back({Point2{t[0].x + 5.0e5, t[0].y + 5.0e6},
                   Point2{t[1].x + 5.0e5, t[1].y + 5.0e6},
                   Point2{t[2].x + 5.0e5, t[2].y + 5.0e6}});
  checkOrientInBox(utm, check);
  // Collinear and nearly collinear points of a 1e-3 m grid at UTM offsets: the
  // spacing is not a dyadic number, so the rows are only nearly straight.
  for (const double ox : {5.0e5, 5.0e6}) {
    std::vector<std::array<Point2, 3>> rows;
    const auto at = [&](int i, int j) {
      return Point2{ox + 1e-3 * i, 5.0e6 + 1e-3 * j};
    };
    for (int i = 0; i < 30; ++i)
      for (int j = 0; j < 30; ++j) {
        rows.push_back({at(i, j), at(i + 1, j), at(i + 7, j)});
        rows.push_back({at(i, j), at(i, j + 3), at(i, j + 11)});
        rows.push_back({at(i, j), at(i + 2, j + 2), at(i + 5, j + 5)});
        rows.push_back({at(i, j), at(i + 1, j + 2), at(i + 3, j + 6)});
      }
    checkOrientInBox(rows, check);
  }
  // One ulp^2 off a line at UTM magnitudes (as in ExactNearALineAtUtmMagnitudes): the
  // differences are exact, the products' rounding is far above the determinant.
  std::mt19937_64 rng(15);
  checkOrientInBox(ulpOffLineTriples(rng, 1000), check);
  // Near lines of 10 m to 10 km from points near the origin: the differences are
  // rounded, and the naive sign flips with |det| up to about half the bound.
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::array<Point2, 3>> mixed;
  for (int k = 0; k < 3000; ++k) {
    const Point2 s = {2 * unit(rng) - 1, 2 * unit(rng) - 1};
    const double length = std::pow(10.0, 1 + 3 * unit(rng)), angle = 6.28 * unit(rng);
    const Point2 e = {s.x + length * std::cos(angle), s.y + length * std::sin(angle)};
    const double t = unit(rng);
    const Point2 m = {stepUlps(s.x + t * (e.x - s.x), k % 5 - 2),
                      s.y + t * (e.y - s.y)};
    mixed.push_back({m, s, e});
  }
  const int wrong_before = check.plain_wrong;
  checkOrientInBox(mixed, check);
  EXPECT_GT(check.plain_wrong - wrong_before, 100);
  EXPECT_GT(check.plain_wrong, 100); // the families are adversarial
  EXPECT_GT(check.tested, 10000);
}

TEST(BoxFilters, IncircleEqualsIncirclePerturbedNearCircles)
{
  BoxCheck check;
  // Exactly cocircular lattice points at UTM magnitudes (the perturbation decides)
  // and d one ulp off the circle.
  const std::vector<double> xy =
      test::latticeCircle(5LL * 13 * 17 * 29 * 37 * 41 * 53 * 61);
  const double U = 0x1p-30;
  const auto at = [&](std::size_t i) {
    return Point2{5.0e5 + 2049.0 * xy[2 * i] * U, 5.4e6 + 2049.0 * xy[2 * i + 1] * U};
  };
  std::mt19937_64 rng(13);
  std::uniform_int_distribution<std::size_t> pick(0, xy.size() / 2 - 1);
  std::vector<std::array<Point2, 4>> quads;
  while (quads.size() < 900) {
    const std::size_t i = pick(rng), j = pick(rng), l = pick(rng), m = pick(rng);
    if (i == j || i == l || i == m || j == l || j == m || l == m)
      continue;
    const Point2 d = at(m);
    quads.push_back({at(i), at(j), at(l), d});
    quads.push_back({at(i), at(j), at(l), Point2{stepUlps(d.x, 1), d.y}});
    quads.push_back({at(i), at(j), at(l), Point2{d.x, stepUlps(d.y, -1)}});
  }
  checkIncircleInBox(quads, check);
  // A 1e-3 m grid at UTM offsets: unit squares (nearly cocircular after rounding),
  // and every small quadruple of a 4 x 4 patch.
  for (const double ox : {5.0e5, 5.0e6}) {
    const auto g = [&](int i, int j) {
      return Point2{ox + 1e-3 * i, 5.0e6 + 1e-3 * j};
    };
    std::vector<std::array<Point2, 4>> grid;
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 20; ++j) {
        grid.push_back({g(i, j), g(i + 1, j), g(i + 1, j + 1), g(i, j + 1)});
        grid.push_back({g(i, j), g(i + 2, j), g(i + 2, j + 1), g(i, j + 1)});
        grid.push_back({g(i, j), g(i + 3, j + 1), g(i + 2, j + 4), g(i - 1, j + 3)});
      }
    std::uniform_int_distribution<int> small(0, 3);
    for (int k = 0; k < 3000; ++k)
      grid.push_back({g(small(rng), small(rng)), g(small(rng), small(rng)),
                      g(small(rng), small(rng)), g(small(rng), small(rng))});
    checkIncircleInBox(grid, check);
  }
  // Near a circle in ulp steps (Shewchuk-style), small coordinates.
  std::vector<std::array<Point2, 4>> near;
  for (int k = 0; k < 6; ++k) {
    const auto on = [&](double t) {
      return Point2{0.7 + 1.3 * std::cos(t), 1.3 * std::sin(t)};
    };
    const Point2 a = on(0.2 * k), b = on(2.0), c = on(4.0), d0 = on(5.5);
    for (int i = -8; i <= 8; ++i)
      for (int j = -8; j <= 8; ++j)
        near.push_back({a, b, c, Point2{stepUlps(d0.x, i), stepUlps(d0.y, j)}});
  }
  checkIncircleInBox(near, check);
  EXPECT_GT(check.plain_wrong, 100);
  EXPECT_GT(check.tested, 10000);
}

TEST(BoxFilters, IncircleDetIsTheDeterminantOfIncircleTerms)
{
  // The two-lane evaluation the box filter uses gives the very double of the scalar
  // expression the bounds are proven for, at every magnitude (subnormal differences,
  // overflowing products, infinities) and with signed zeros.
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-1074, 1023);
  std::uniform_int_distribution<int> kind(0, 9);
  const auto coordinate = [&](double base) {
    switch (kind(rng)) {
    case 0:
      return 0.0;
    case 1:
      return -0.0;
    case 2:
      return std::ldexp(unit(rng), exponent(rng));
    case 3:
      return stepUlps(base, kind(rng) - 5);
    case 4:
      return kind(rng) == 0 ? std::numeric_limits<double>::infinity() : base;
    default:
      return base + std::ldexp(unit(rng), exponent(rng) / 16);
    }
  };
  int tested = 0;
  for (int k = 0; k < 200000; ++k) {
    const double bx = std::ldexp(unit(rng), exponent(rng) / 4),
                 by = std::ldexp(unit(rng), exponent(rng) / 4);
    std::array<Point2, 4> q;
    for (Point2& point : q)
      point = {coordinate(bx), coordinate(by)};
    ASSERT_TRUE(sameDouble(detail::incircleDet(q[0], q[1], q[2], q[3]),
                           detail::incircleTerms(q[0], q[1], q[2], q[3]).det))
        << k;
    ++tested;
  }
  EXPECT_EQ(tested, 200000);
}

TEST(BoxFilters, WideBoxesAndSmallIntegerGrids)
{
  // A super triangle 10 window widths away from small triangles (the cache blocks'
  // wide box), and exactly cocircular small integer points (ties everywhere).
  BoxCheck check;
  std::vector<std::array<Point2, 4>> quads;
  std::vector<std::array<Point2, 3>> triples;
  const Point2 s0{-300.0, -300.0}, s1{330.0, -300.0}, s2{15.0, 330.0};
  std::mt19937_64 rng(14);
  std::uniform_int_distribution<int> cell(0, 30);
  for (int k = 0; k < 4000; ++k) {
    const Point2 a{static_cast<double>(cell(rng)), static_cast<double>(cell(rng))};
    const Point2 b{a.x + 1, a.y}, c{a.x + 1, a.y + 1}, d{a.x, a.y + 1};
    quads.push_back({a, b, c, d});
    quads.push_back({s0, b, c, d});
    quads.push_back({s0, s1, c, d});
    quads.push_back({s0, s1, s2, d});
    triples.push_back({a, c, Point2{a.x + 2, a.y + 2}});
    triples.push_back({s0, a, c});
  }
  checkIncircleInBox(quads, check);
  checkOrientInBox(triples, check);
  EXPECT_EQ(check.tested, 4 * 4000 + 3 * 2 * 4000); // triples in 3 rotations
  // A box too wide for a finite bound certifies nothing; the answers stay exact.
  const double big = std::numeric_limits<double>::max();
  const detail::BoxBounds huge = detail::boxBounds(-big, big, -big, big);
  EXPECT_FALSE(std::isfinite(huge.incircle));
  const Point2 a{0, 0}, b{1, 0}, c{1, 1}, d{0, 1};
  EXPECT_EQ(detail::incirclePerturbedInBox(a, b, c, d, huge.incircle),
            incirclePerturbed(a, b, c, d));
  EXPECT_EQ(detail::orient2dInBox(a, b, c, huge.orient), Sign::POSITIVE);
}

// The cache blocks' in-circle filter from per-triangle coefficients
// (incircleCoefficients, incircleFromCoefficients, coefficientBound): on each family
// the computed determinant is compared with the exact one in rational arithmetic, its
// error must stay below the bound of the family's tightest box, and the filtered
// predicate must return incirclePerturbed's sign. The families are adversarial for the
// bound: points spread over the whole box with the fourth one within ulps of the
// circle, so the error reaches a sizeable share of the bound (max_ratio: 1/64 of it;
// dividing the bound by 64 makes this test fail, tried when it was written).
struct CoefficientCheck {
  int tested = 0;
  int filtered = 0;       ///< signs the filter decided alone
  double max_ratio = 0.0; ///< the largest |computed - exact| / bound (power of 2 below)
};

Rational incircleValue(const Point2& a, const Point2& b, const Point2& c,
                       const Point2& d)
{
  const Rational adx = exact(a.x) - exact(d.x), ady = exact(a.y) - exact(d.y);
  const Rational bdx = exact(b.x) - exact(d.x), bdy = exact(b.y) - exact(d.y);
  const Rational cdx = exact(c.x) - exact(d.x), cdy = exact(c.y) - exact(d.y);
  return (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
         (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
         (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
}

void checkCoefficients(const std::vector<std::array<Point2, 4>>& quads,
                       CoefficientCheck& out)
{
  double x_lo = quads[0][0].x, x_hi = x_lo, y_lo = quads[0][0].y, y_hi = y_lo;
  for (const auto& q : quads)
    for (const Point2& point : q) {
      x_lo = std::min(x_lo, point.x);
      x_hi = std::max(x_hi, point.x);
      y_lo = std::min(y_lo, point.y);
      y_hi = std::max(y_hi, point.y);
    }
  const double bound = detail::coefficientBound(x_lo, x_hi, y_lo, y_hi);
  ASSERT_TRUE(std::isfinite(bound));
  for (const auto& q : quads)
    for (int r = 0; r < 3; ++r) { // each corner as the origin c, and both orientations
      const Point2 a = q[r], b = q[(r + 1) % 3], c = q[(r + 2) % 3], d = q[3];
      for (const bool flip : {false, true}) {
        const Point2& u = flip ? b : a;
        const Point2& w = flip ? a : b;
        const detail::IncircleCoefficients k = detail::incircleCoefficients(u, w, c);
        const double det = detail::incircleFromCoefficients(k, c, d);
        const Rational value = incircleValue(u, w, c, d);
        // |error| / bound, to a power of two (2^-16 at least).
        const Rational error = exact(det) - value, minus = value - exact(det);
        for (double ratio = 1.0; ratio > out.max_ratio && ratio >= 0x1p-16; ratio /= 2)
          if (error > exact(ratio * bound) || minus > exact(ratio * bound)) {
            out.max_ratio = ratio;
            break;
          }
        const Sign expected = incirclePerturbed(u, w, c, d);
        EXPECT_EQ(detail::incirclePerturbedFromCoefficients(k, u, w, c, d, bound),
                  expected)
            << "a=(" << u.x << "," << u.y << ") b=(" << w.x << "," << w.y << ") c=("
            << c.x << "," << c.y << ") d=(" << d.x << "," << d.y << ")";
        if (value.sign() != 0) {
          EXPECT_EQ(expected, toSign(value.sign()));
        }
        out.filtered += std::fabs(det) > bound;
        ++out.tested;
      }
    }
}

TEST(BoxFilters, CoefficientsBoundTheErrorNearCircles)
{
  CoefficientCheck check;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Circles spanning the box at UTM magnitudes, three corners on the rounded circle
  // and the fourth point within a few ulps of it: the error bound's worst case.
  for (const double radius : {0.3, 40.0, 2500.0}) {
    std::vector<std::array<Point2, 4>> quads;
    const double cx = 5.0e5 + 0.37, cy = 5.4e6 - 0.61;
    const auto on = [&](double t) {
      return Point2{cx + radius * std::cos(t), cy + radius * std::sin(t)};
    };
    for (int k = 0; k < 700; ++k) {
      const double t0 = 6.283 * unit(rng);
      const Point2 d0 = on(t0 + 3.1 + 0.2 * unit(rng));
      quads.push_back({on(t0), on(t0 + 2.0 + 0.3 * unit(rng)),
                       on(t0 + 4.0 + 0.3 * unit(rng)),
                       Point2{stepUlps(d0.x, k % 7 - 3), stepUlps(d0.y, k % 5 - 2)}});
    }
    checkCoefficients(quads, check);
  }
  // Exactly cocircular lattice points at UTM magnitudes (the perturbation decides)
  // and d one ulp off the circle.
  const std::vector<double> xy =
      test::latticeCircle(5LL * 13 * 17 * 29 * 37 * 41 * 53 * 61);
  const double U = 0x1p-30;
  const auto at = [&](std::size_t i) {
    return Point2{5.0e5 + 2049.0 * xy[2 * i] * U, 5.4e6 + 2049.0 * xy[2 * i + 1] * U};
  };
  std::uniform_int_distribution<std::size_t> pick(0, xy.size() / 2 - 1);
  std::vector<std::array<Point2, 4>> lattice;
  while (lattice.size() < 600) {
    const std::size_t i = pick(rng), j = pick(rng), l = pick(rng), m = pick(rng);
    if (i == j || i == l || i == m || j == l || j == m || l == m)
      continue;
    const Point2 d = at(m);
    lattice.push_back({at(i), at(j), at(l), d});
    lattice.push_back({at(i), at(j), at(l), Point2{stepUlps(d.x, 1), d.y}});
    lattice.push_back({at(i), at(j), at(l), Point2{d.x, stepUlps(d.y, -1)}});
  }
  checkCoefficients(lattice, check);
  // A 1e-3 m grid at UTM offsets: nearly cocircular unit squares after rounding.
  std::vector<std::array<Point2, 4>> grid;
  const auto g = [&](int i, int j) {
    return Point2{5.0e5 + 1e-3 * i, 5.0e6 + 1e-3 * j};
  };
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      grid.push_back({g(i, j), g(i + 1, j), g(i + 1, j + 1), g(i, j + 1)});
      grid.push_back({g(i, j), g(i + 3, j + 1), g(i + 2, j + 4), g(i - 1, j + 3)});
    }
  checkCoefficients(grid, check);
  // Random points of a window (the common case): the filter decides nearly all.
  std::vector<std::array<Point2, 4>> random;
  for (int k = 0; k < 1000; ++k) {
    std::array<Point2, 4> quad;
    for (Point2& point : quad)
      point = {5.0e5 + 64.0 * unit(rng), 5.4e6 + 64.0 * unit(rng)};
    random.push_back(quad);
  }
  const int filtered_before = check.filtered;
  checkCoefficients(random, check);
  EXPECT_GT(check.filtered - filtered_before, 5900);
  EXPECT_GT(check.tested, 20000);
  EXPECT_LT(check.max_ratio, 1.0); // the bound holds
  // Not vacuous: the computed determinant's error comes within a factor 128 of it
  // (1/64 here: with the bound divided by 64 the error check fails, by 128 wrong signs
  // come out too; both tried).
  EXPECT_GE(check.max_ratio, 1.0 / 128.0) << check.max_ratio;
}

TEST(BoxFilters, CoefficientBoundOfHugeBoxesCertifiesNothing)
{
  const double big = std::numeric_limits<double>::max();
  EXPECT_FALSE(std::isfinite(detail::coefficientBound(-big, big, -big, big)));
  EXPECT_FALSE(std::isfinite(detail::coefficientBound(0.0, 1e300, 0.0, 1.0)));
  const Point2 a{0, 0}, b{1, 0}, c{1, 1}, d{0, 1};
  const double huge = detail::coefficientBound(-big, big, -big, big);
  EXPECT_EQ(detail::incirclePerturbedFromCoefficients(
                detail::incircleCoefficients(a, b, c), a, b, c, d, huge),
            incirclePerturbed(a, b, c, d));
  EXPECT_EQ(detail::incirclePerturbedFromCoefficients(
                detail::incircleCoefficients(a, b, c), a, b, c, Point2{0.5, 0.5}, huge),
            Sign::POSITIVE);
}

} // namespace
} // namespace pcl_vts
