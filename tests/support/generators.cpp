// Generators: std::mt19937_64 (its output sequence is fixed by the standard) with
// hand-written uniform/normal maps, so a seed names the same points everywhere.
// Output order is shuffled: sorted input hides bugs.
#include "support/generators.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

namespace pcl_vts {
namespace test {
namespace {

constexpr double PI = 3.14159265358979323846;

class Rng {
 public:
  explicit Rng(std::uint64_t seed)
      : engine_(seed * 0x9E3779B97F4A7C15ull + 1)
  {}

  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n).
  std::size_t index(std::size_t n)
  {
    return static_cast<std::size_t>(uniform() * static_cast<double>(n));
  }
  /// Standard normal (Box-Muller).
  double normal()
  {
    const double u = 1.0 - uniform(); // (0, 1]
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * PI * uniform());
  }

 private:
  std::mt19937_64 engine_;
};

void push(std::vector<double>& xyz, double x, double y, double z)
{
  xyz.push_back(x);
  xyz.push_back(y);
  xyz.push_back(z);
}

/// Fisher-Yates over points (triples).
void shufflePoints(std::vector<double>& xyz, Rng& rng)
{
  const std::size_t n = xyz.size() / 3;
  for (std::size_t i = n; i > 1; --i) {
    const std::size_t j = rng.index(i);
    for (int k = 0; k < 3; ++k)
      std::swap(xyz[3 * (i - 1) + k], xyz[3 * j + k]);
  }
}

std::size_t side(std::size_t n)
{
  return static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
}

std::vector<double> uniformSquare(std::size_t n, Rng& rng, double w, double h)
{
  std::vector<double> xyz;
  xyz.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = rng.uniform(0.0, w), y = rng.uniform(0.0, h);
    push(xyz, x, y, terrainHeight(x, y));
  }
  return xyz;
}

std::vector<double> clustered(std::size_t n, Rng& rng)
{
  const std::size_t k = std::max<std::size_t>(3, n / 500);
  std::vector<double> cx(k), cy(k), sigma(k);
  for (std::size_t c = 0; c < k; ++c) {
    cx[c] = rng.uniform(0.0, 1000.0);
    cy[c] = rng.uniform(0.0, 1000.0);
    sigma[c] = rng.uniform(2.0, 12.0);
  }
  std::vector<double> xyz;
  xyz.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c = rng.index(k);
    const double x = cx[c] + sigma[c] * rng.normal();
    const double y = cy[c] + sigma[c] * rng.normal();
    push(xyz, x, y, terrainHeight(x, y));
  }
  return xyz;
}

/// First n points of a side x side lattice (i*dx + jitter, j*dy + jitter) + origin.
std::vector<double> lattice(std::size_t n, Rng& rng, double dx, double dy,
                            double jitter, double x0, double y0)
{
  const std::size_t s = side(n);
  std::vector<double> xyz;
  xyz.reserve(3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const double i = static_cast<double>(k % s), j = static_cast<double>(k / s);
    const double x = (i + (jitter > 0 ? rng.uniform(-jitter, jitter) : 0.0)) * dx;
    const double y = (j + (jitter > 0 ? rng.uniform(-jitter, jitter) : 0.0)) * dy;
    push(xyz, x0 + x, y0 + y, terrainHeight(x, y));
  }
  return xyz;
}

std::vector<double> rotatedLattice(std::size_t n, Rng& rng)
{
  const double angle = rng.uniform(0.1, 1.4);
  const double c = std::cos(angle), s = std::sin(angle);
  const double scale = rng.uniform(0.5, 3.0);
  const std::size_t m = side(n);
  std::vector<double> xyz;
  xyz.reserve(3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const double i = static_cast<double>(k % m), j = static_cast<double>(k / m);
    const double x = scale * (c * i - s * j) + 100.0;
    const double y = scale * (s * i + c * j) + 100.0;
    push(xyz, x, y, terrainHeight(x, y));
  }
  return xyz;
}

/// Products of primes 1 mod 4: the circle x^2 + y^2 = r2 holds 4 * 2^k lattice points.
constexpr std::int64_t CIRCLE_R2[] = {
    5LL * 13,                                   // 16 points
    5LL * 13 * 17,                              // 32
    5LL * 13 * 17 * 29,                         // 64
    5LL * 13 * 17 * 29 * 37,                    // 128
    5LL * 13 * 17 * 29 * 37 * 41,               // 256
    5LL * 13 * 17 * 29 * 37 * 41 * 53,          // 512
    5LL * 13 * 17 * 29 * 37 * 41 * 53 * 61,     // 1024
    5LL * 13 * 17 * 29 * 37 * 41 * 53 * 61 * 73 // 2048
};

std::vector<double> circle(std::size_t n, Rng& rng)
{
  std::vector<double> xy;
  for (const std::int64_t r2 : CIRCLE_R2) {
    xy = latticeCircle(r2);
    if (xy.size() / 2 >= n)
      break;
  }
  // A random subset of a cocircular set is cocircular; shift by an integer (exact).
  const double ox = std::floor(rng.uniform(-1000.0, 1000.0));
  const double oy = std::floor(rng.uniform(-1000.0, 1000.0));
  std::vector<double> xyz;
  for (std::size_t i = 0; i < xy.size() / 2; ++i)
    push(xyz, xy[2 * i] + ox, xy[2 * i + 1] + oy,
         terrainHeight(xy[2 * i], xy[2 * i + 1]));
  shufflePoints(xyz, rng);
  xyz.resize(3 * std::min(n, xyz.size() / 3));
  return xyz;
}

std::vector<double> concentricRings(std::size_t n)
{
  const std::vector<double> base = latticeCircle(5LL * 13 * 17); // 32 points
  std::vector<double> xyz;
  push(xyz, 0.0, 0.0, 0.0);
  for (double k = 1.0; xyz.size() / 3 < n; k += 1.0)
    for (std::size_t i = 0; i < base.size() / 2 && xyz.size() / 3 < n; ++i)
      push(xyz, k * base[2 * i], k * base[2 * i + 1], k);
  return xyz;
}

std::vector<double> collinear(std::size_t n, Rng& rng)
{
  const double y0 = std::floor(rng.uniform(-100.0, 100.0));
  std::vector<double> xyz;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    push(xyz, 0.5 * t, y0 - 0.25 * t, rng.uniform());
  }
  return xyz;
}

std::vector<double> duplicates(std::size_t n, Rng& rng)
{
  std::vector<double> xyz;
  xyz.reserve(3 * n + 12);
  while (xyz.size() / 3 < n) {
    const double x = rng.uniform(0.0, 1000.0), y = rng.uniform(0.0, 1000.0);
    const std::size_t copies = 1 + rng.index(4);
    for (std::size_t c = 0; c < copies; ++c)
      push(xyz, x, y, rng.uniform(0.0, 30.0));
  }
  return xyz;
}

std::vector<double> bigVoids(std::size_t n, Rng& rng)
{
  constexpr int DISCS = 5;
  double cx[DISCS], cy[DISCS], r[DISCS];
  for (int d = 0; d < DISCS; ++d) {
    cx[d] = rng.uniform(0.0, 1000.0);
    cy[d] = rng.uniform(0.0, 1000.0);
    r[d] = rng.uniform(100.0, 220.0);
  }
  std::vector<double> xyz;
  xyz.reserve(3 * n);
  while (xyz.size() / 3 < n) {
    const double x = rng.uniform(0.0, 1000.0), y = rng.uniform(0.0, 1000.0);
    bool inside = false;
    for (int d = 0; d < DISCS; ++d)
      inside =
          inside || (x - cx[d]) * (x - cx[d]) + (y - cy[d]) * (y - cy[d]) < r[d] * r[d];
    if (!inside)
      push(xyz, x, y, terrainHeight(x, y));
  }
  return xyz;
}

std::vector<double> floatRounded(std::size_t n, Rng& rng)
{
  // About 4 points per square metre, as in the ISPRS urban samples.
  const double extent = std::sqrt(static_cast<double>(n) / 4.0) + 1.0;
  const double x0 = std::floor(rng.uniform(4.0e5, 6.0e5));
  const double y0 = std::floor(rng.uniform(5.3e6, 5.5e6));
  std::vector<double> xyz;
  xyz.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = rng.uniform(0.0, extent), y = rng.uniform(0.0, extent);
    push(xyz, static_cast<double>(static_cast<float>(x0 + x)),
         static_cast<double>(static_cast<float>(y0 + y)),
         static_cast<double>(static_cast<float>(terrainHeight(x, y) + 250.0)));
  }
  return xyz;
}

} // namespace

const std::vector<Distribution>& allDistributions()
{
  static const std::vector<Distribution> all = {
      Distribution::UNIFORM,          Distribution::CLUSTERED,
      Distribution::JITTERED_GRID,    Distribution::EXACT_GRID,
      Distribution::ROTATED_LATTICE,  Distribution::CIRCLE,
      Distribution::CONCENTRIC_RINGS, Distribution::COLLINEAR,
      Distribution::DUPLICATES,       Distribution::THREE_POINTS,
      Distribution::THIN_STRIP,       Distribution::BIG_VOIDS,
      Distribution::ANISOTROPIC,      Distribution::UTM_OFFSET,
      Distribution::UTM_LARGE_OFFSET, Distribution::FLOAT_ROUNDED};
  return all;
}

std::string distributionName(Distribution distribution)
{
  switch (distribution) {
  case Distribution::UNIFORM:
    return "UNIFORM";
  case Distribution::CLUSTERED:
    return "CLUSTERED";
  case Distribution::JITTERED_GRID:
    return "JITTERED_GRID";
  case Distribution::EXACT_GRID:
    return "EXACT_GRID";
  case Distribution::ROTATED_LATTICE:
    return "ROTATED_LATTICE";
  case Distribution::CIRCLE:
    return "CIRCLE";
  case Distribution::CONCENTRIC_RINGS:
    return "CONCENTRIC_RINGS";
  case Distribution::COLLINEAR:
    return "COLLINEAR";
  case Distribution::DUPLICATES:
    return "DUPLICATES";
  case Distribution::THREE_POINTS:
    return "THREE_POINTS";
  case Distribution::THIN_STRIP:
    return "THIN_STRIP";
  case Distribution::BIG_VOIDS:
    return "BIG_VOIDS";
  case Distribution::ANISOTROPIC:
    return "ANISOTROPIC";
  case Distribution::UTM_OFFSET:
    return "UTM_OFFSET";
  case Distribution::UTM_LARGE_OFFSET:
    return "UTM_LARGE_OFFSET";
  case Distribution::FLOAT_ROUNDED:
    return "FLOAT_ROUNDED";
  }
  return "UNKNOWN";
}

std::vector<double> generatePoints(Distribution distribution, std::size_t n,
                                   std::uint64_t seed)
{
  Rng rng(seed);
  std::vector<double> xyz;
  switch (distribution) {
  case Distribution::UNIFORM:
    xyz = uniformSquare(n, rng, 1000.0, 1000.0);
    break;
  case Distribution::CLUSTERED:
    xyz = clustered(n, rng);
    break;
  case Distribution::JITTERED_GRID:
    xyz = lattice(n, rng, 1.0, 1.0, 0.3, 0.0, 0.0);
    break;
  case Distribution::EXACT_GRID:
    xyz = lattice(n, rng, 1.0, 1.0, 0.0, 0.0, 0.0);
    break;
  case Distribution::ROTATED_LATTICE:
    xyz = rotatedLattice(n, rng);
    break;
  case Distribution::CIRCLE:
    xyz = circle(n, rng);
    break;
  case Distribution::CONCENTRIC_RINGS:
    xyz = concentricRings(n);
    break;
  case Distribution::COLLINEAR:
    xyz = collinear(n, rng);
    break;
  case Distribution::DUPLICATES:
    xyz = duplicates(n, rng);
    break;
  case Distribution::THREE_POINTS:
    xyz = uniformSquare(3, rng, 10.0, 10.0);
    break;
  case Distribution::THIN_STRIP:
    xyz = uniformSquare(n, rng, 1000.0, 1.0);
    break;
  case Distribution::BIG_VOIDS:
    xyz = bigVoids(n, rng);
    break;
  case Distribution::ANISOTROPIC:
    xyz = lattice(n, rng, 100.0, 1.0, 0.0, 0.0, 0.0);
    break;
  case Distribution::UTM_OFFSET:
    xyz = lattice(n, rng, 0.001, 0.001, 0.3, std::floor(rng.uniform(4e5, 6e5)),
                  std::floor(rng.uniform(4.9e6, 5.1e6)));
    break;
  case Distribution::UTM_LARGE_OFFSET:
    xyz = lattice(n, rng, 0.001, 0.001, 0.3, std::floor(rng.uniform(4.9e6, 5.1e6)),
                  std::floor(rng.uniform(4.9e6, 5.1e6)));
    break;
  case Distribution::FLOAT_ROUNDED:
    xyz = floatRounded(n, rng);
    break;
  }
  shufflePoints(xyz, rng);
  return xyz;
}

std::vector<double> latticeCircle(std::int64_t r2)
{
  std::vector<std::pair<double, std::pair<double, double>>> points;
  const auto r = static_cast<std::int64_t>(std::sqrt(static_cast<double>(r2)));
  for (std::int64_t x = -r - 1; x <= r + 1; ++x) {
    const std::int64_t rest = r2 - x * x;
    if (rest < 0)
      continue;
    auto y = static_cast<std::int64_t>(std::sqrt(static_cast<double>(rest)));
    while (y * y > rest)
      --y;
    while ((y + 1) * (y + 1) <= rest)
      ++y;
    if (y * y != rest)
      continue;
    const auto dx = static_cast<double>(x), dy = static_cast<double>(y);
    points.push_back({std::atan2(dy, dx), {dx, dy}});
    if (y != 0)
      points.push_back({std::atan2(-dy, dx), {dx, -dy}});
  }
  std::sort(points.begin(), points.end());
  std::vector<double> xy;
  xy.reserve(2 * points.size());
  for (const auto& p : points) {
    xy.push_back(p.second.first);
    xy.push_back(p.second.second);
  }
  return xy;
}

double terrainHeight(double x, double y)
{
  return 4.0 * std::sin(0.013 * x) * std::cos(0.017 * y) +
         2.0 * std::sin(0.05 * x + 0.03 * y) + 0.5 * std::cos(0.21 * y);
}

} // namespace test
} // namespace pcl_vts
