// Seeded point generators for property tests: xyz doubles, 3 per point, each a
// known hard case for a grid Delaunay triangulator (ties, voids, thin domains, big
// offsets, float rounding). Same (n, seed) -> same points on every platform that has
// IEEE doubles (std::mt19937_64; distributions are written here, not taken from
// <random>, whose output is implementation-defined).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {
namespace test {

enum class Distribution {
  UNIFORM,          ///< uniform in a 1000 x 1000 square
  CLUSTERED,        ///< gaussian blobs with large empty space between them
  JITTERED_GRID,    ///< unit grid, +-0.3 jitter, terrain z
  EXACT_GRID,       ///< integer lattice: every unit square is a cocircular tie
  ROTATED_LATTICE,  ///< lattice rotated by an irrational-ish angle, rounded (near ties)
  CIRCLE,           ///< integer points exactly on one circle (all cocircular)
  CONCENTRIC_RINGS, ///< integer multiples of one lattice circle, plus the centre
  COLLINEAR,        ///< all on one line (exactly representable)
  DUPLICATES,       ///< uniform XY, each position repeated 1-4 times with other z
  THREE_POINTS,     ///< exactly 3 points, whatever n is
  THIN_STRIP,       ///< uniform in 1000 x 1
  BIG_VOIDS,        ///< uniform minus several large empty discs
  ANISOTROPIC,      ///< lattice with dx = 100 dy
  UTM_OFFSET,       ///< x ~ 5e5, y ~ 5e6, millimetre spacing, jittered
  UTM_LARGE_OFFSET, ///< x ~ 5e6, y ~ 5e6, millimetre spacing, jittered
  FLOAT_ROUNDED     ///< UTM points rounded to float32: collinear rows, duplicates
};

/// Every distribution, for TEST_P generators.
const std::vector<Distribution>& allDistributions();

/// "UNIFORM", "EXACT_GRID", ...: readable test names.
std::string distributionName(Distribution distribution);

/// n points (about n for lattices and circles, which round to their shape; exactly 3
/// for THREE_POINTS) as xyz triples.
std::vector<double> generatePoints(Distribution distribution, std::size_t n,
                                   std::uint64_t seed);

/// The integer points on the circle x^2 + y^2 = r2 (r2 < 2^50), in angular order, as
/// (x, y) pairs (2 doubles per point): exactly cocircular, exactly representable.
std::vector<double> latticeCircle(std::int64_t r2);

/// A smooth terrain height for (x, y): sums of sines, |z| < 10.
double terrainHeight(double x, double y);

} // namespace test
} // namespace pcl_vts
