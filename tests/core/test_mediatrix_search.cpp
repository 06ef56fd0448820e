// The third-point search: its safe disk really contains the exact circle, and its
// work per search stays bounded on the inputs that make a plain grid search
// quadratic (clusters in a large empty box, big voids, rings around an empty centre,
// thin strips). Work is counted (cells visited), never timed.
#include "support/generators.h"

#include <pcl_vts/core/mediatrix_search.h>
#include <pcl_vts/core/predicates.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace pcl_vts {
namespace {

TEST(SafeCircumdisk, ContainsEveryPointInsideOrOnTheExactCircle)
{
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    // Mix of scales and offsets, including thin triangles and UTM magnitudes.
    const double scale = std::pow(10.0, std::floor(unit(rng) * 4.0));
    const double offset = trial % 3 == 0 ? 5e6 : 0.0;
    const Point2 a{offset + scale * unit(rng), offset + scale * unit(rng)};
    const Point2 b{offset + scale * unit(rng), offset + scale * unit(rng)};
    Point2 p{offset + scale * unit(rng), offset + scale * unit(rng)};
    if (orient2d(a, b, p) == Sign::ZERO)
      continue;
    // Order the triangle counter-clockwise: (first, second, c).
    const bool ccw = orient2d(a, b, p) == Sign::POSITIVE;
    const Point2 first = ccw ? a : b, second = ccw ? b : a, c = p;
    const SafeDisk disk = safeCircumdisk(first, second, c);
    if (!disk.valid)
      continue;
    ++checked;
    for (const Point2& v : {a, b, p}) {
      const double d = std::hypot(v.x - disk.cx, v.y - disk.cy);
      EXPECT_LE(d, disk.radius) << "vertex outside its own safe disk, trial " << trial;
    }
    // Points exactly inside (incircle POSITIVE) must be inside the safe disk.
    for (int k = 0; k < 20; ++k) {
      const Point2 q{disk.cx + disk.radius * unit(rng),
                     disk.cy + disk.radius * unit(rng)};
      if (incircle(first, second, c, q) != Sign::NEGATIVE) {
        EXPECT_LE(std::hypot(q.x - disk.cx, q.y - disk.cy), disk.radius)
            << "trial " << trial;
      }
    }
  }
  EXPECT_GT(checked, 1500);
}

TEST(SafeCircumdisk, ContainsExactlyCocircularPointsAtUtmOffsets)
{
  // 1105^2 has many integer points on its circle: exact cocircular sets that a disk
  // without an error margin would cut (points exactly on the boundary).
  const std::vector<double> circle = test::latticeCircle(1105LL * 1105LL);
  ASSERT_GE(circle.size() / 2, 40u);
  for (const double offset : {0.0, 1e6, 5e6, 4e7}) {
    SCOPED_TRACE(offset);
    const auto at = [&](std::size_t k) {
      return Point2{offset + circle[2 * k], offset + circle[2 * k + 1]};
    };
    const std::size_t m = circle.size() / 2;
    for (std::size_t k = 0; k + 2 < m; k += 3) {
      const SafeDisk disk = safeCircumdisk(at(k), at(k + 1), at(k + 2));
      ASSERT_TRUE(disk.valid);
      for (std::size_t j = 0; j < m; ++j)
        EXPECT_LE(std::hypot(at(j).x - disk.cx, at(j).y - disk.cy), disk.radius);
    }
  }
}

TEST(SafeCircumdisk, RefusesToBoundDegenerateTriangles)
{
  EXPECT_FALSE(safeCircumdisk({0, 0}, {1, 0}, {2, 0}).valid);        // collinear
  EXPECT_FALSE(safeCircumdisk({0, 0}, {1, 0}, {0.5, 1e-300}).valid); // far too thin
  EXPECT_TRUE(safeCircumdisk({0, 0}, {1, 0}, {0.5, 0.5}).valid);
}

/// Candidate points tested per search.
double pointsPerSearch(const std::vector<double>& xyz, Diagnostics* out = nullptr)
{
  VtsOptions options;
  options.cache_blocks = false; // every triangle by the search, whose work is measured
  VtsResult result;
  const Status status = runVtsPipeline(xyz.data(), xyz.size() / 3, options, result);
  EXPECT_TRUE(status.ok()) << status.toString();
  const Diagnostics& d = result.diagnostics;
  if (out)
    *out = d;
  return static_cast<double>(d.points_tested) /
         static_cast<double>(d.local_searches + d.widened_searches);
}

std::vector<double> tightClustersFarApart(std::size_t n, std::uint64_t seed)
{
  // Four clusters of unit spread, 1e4 apart: a density-sized uniform grid would put
  // each cluster in one cell.
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<double> xyz;
  for (std::size_t k = 0; k < n; ++k) {
    xyz.push_back(1e4 * static_cast<double>(k % 2) + gauss(rng));
    xyz.push_back(1e4 * static_cast<double>((k / 2) % 2) + gauss(rng));
    xyz.push_back(0.0);
  }
  return xyz;
}

std::vector<double> ringAroundEmptyCentre(std::size_t n, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> xyz;
  for (std::size_t k = 0; k < n; ++k) {
    const double angle = 6.283185307179586 * unit(rng),
                 radius = 1000.0 + 10.0 * unit(rng);
    xyz.push_back(radius * std::cos(angle));
    xyz.push_back(radius * std::sin(angle));
    xyz.push_back(0.0);
  }
  return xyz;
}

TEST(MediatrixSearch, WorkPerSearchStaysBoundedWhereAPlainGridIsQuadratic)
{
  using test::Distribution;
  struct Case {
    const char* name;
    std::vector<double> small, large;
  };
  const std::vector<Case> cases = {
      {"tight clusters far apart", tightClustersFarApart(4000, 1),
       tightClustersFarApart(32000, 1)},
      {"ring around an empty centre", ringAroundEmptyCentre(4000, 2),
       ringAroundEmptyCentre(32000, 2)},
      {"big voids", test::generatePoints(Distribution::BIG_VOIDS, 4000, 3),
       test::generatePoints(Distribution::BIG_VOIDS, 32000, 3)},
      {"clustered", test::generatePoints(Distribution::CLUSTERED, 4000, 4),
       test::generatePoints(Distribution::CLUSTERED, 32000, 4)},
      {"thin strip 1000:1", test::generatePoints(Distribution::THIN_STRIP, 4000, 5),
       test::generatePoints(Distribution::THIN_STRIP, 32000, 5)},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const double small = pointsPerSearch(c.small);
    const double large = pointsPerSearch(c.large);
    // Linear total work: the per-search cost does not grow with n (8x more points).
    EXPECT_LT(large, 1.5 * small + 2.0) << "small " << small << ", large " << large;
    EXPECT_LT(large, 128.0);
  }
}

TEST(MediatrixSearch, TerrainSearchesSettleInTheEdgeRectangle)
{
  Diagnostics d;
  pointsPerSearch(test::generatePoints(test::Distribution::JITTERED_GRID, 20000, 6),
                  &d);
  const double searches = static_cast<double>(d.local_searches + d.widened_searches);
  EXPECT_GT(static_cast<double>(d.local_searches) / searches, 0.99);
  EXPECT_LT(static_cast<double>(d.cells_visited) / searches, 16.0);
  EXPECT_LT(static_cast<double>(d.points_tested) / searches, 32.0);
}

} // namespace
} // namespace pcl_vts
