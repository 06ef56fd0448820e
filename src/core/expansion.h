// Exact floating-point expansion arithmetic (Shewchuk 1997): a number is held as a
// sum of non-overlapping doubles in increasing magnitude. Internal to predicates.cpp;
// fixed-size arrays on the stack, no allocation.
#pragma once

#include <cmath>

namespace pcl_vts::detail {

/// x + y == a + b exactly, x = fl(a + b).
inline void twoSum(double a, double b, double& x, double& y)
{
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}

/// x + y == a * b exactly, x = fl(a * b) (no underflow assumed).
inline void twoProduct(double a, double b, double& x, double& y)
{
  x = a * b;
  y = std::fma(a, b, -x);
}

} // namespace pcl_vts::detail

namespace pcl_vts::detail {

// ---- Fixed-size variants for the common exact case: all coordinate differences
// are exact doubles. No allocation; sizes are bounded by the caller's arrays.

/// h = e + f (both non-overlapping, increasing magnitude); returns the length of h.
/// h must hold elen + flen doubles and must not alias e or f.
inline int sumZeroelim(int elen, const double* e, int flen, const double* f, double* h)
{
  int ei = 0, fi = 0, hi = 0;
  double q = 0.0;
  bool have_q = false;
  while (ei < elen || fi < flen) {
    double next;
    if (fi >= flen || (ei < elen && std::fabs(e[ei]) <= std::fabs(f[fi])))
      next = e[ei++];
    else
      next = f[fi++];
    if (!have_q) {
      q = next;
      have_q = true;
      continue;
    }
    double sum, err;
    twoSum(q, next, sum, err);
    if (err != 0.0)
      h[hi++] = err;
    q = sum;
  }
  if (q != 0.0 || hi == 0)
    h[hi++] = q;
  return hi;
}

/// h = e * b; h must hold 2 * elen doubles.
inline int scaleZeroelim(int elen, const double* e, double b, double* h)
{
  int hi = 0;
  double q, hh;
  twoProduct(e[0], b, q, hh);
  if (hh != 0.0)
    h[hi++] = hh;
  for (int i = 1; i < elen; ++i) {
    double p1, p0, sum;
    twoProduct(e[i], b, p1, p0);
    twoSum(q, p0, sum, hh);
    if (hh != 0.0)
      h[hi++] = hh;
    twoSum(p1, sum, q, hh);
    if (hh != 0.0)
      h[hi++] = hh;
  }
  if (q != 0.0 || hi == 0)
    h[hi++] = q;
  return hi;
}

/// a * b - c * d exactly, as at most 4 components in h.
inline int crossZeroelim(double a, double b, double c, double d, double* h)
{
  double p[2], m[2];
  twoProduct(a, b, p[1], p[0]);
  twoProduct(c, d, m[1], m[0]);
  m[0] = -m[0];
  m[1] = -m[1];
  const double pe[2] = {p[0], p[1]}, me[2] = {m[0], m[1]};
  return sumZeroelim(2, pe, 2, me, h);
}

inline int signOf(int len, const double* e)
{
  for (int i = len - 1; i >= 0; --i)
    if (e[i] != 0.0)
      return e[i] > 0.0 ? 1 : -1;
  return 0;
}

} // namespace pcl_vts::detail
