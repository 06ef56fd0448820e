// Synthetic terrain with a known surface, so that errors can be measured against the
// truth and not only against the points: z = syntheticHeight(x, y) over a square of
// side sqrt(n) metres (density 1 point per m^2), uniform random XY like an airborne
// scan, at UTM-like world coordinates. PCL-free.
#pragma once

#include "compare_mesh.h"

#include <cstddef>
#include <cstdint>

namespace pcl_vts {
namespace compare {

/// Where the synthetic square sits in world coordinates (UTM zone 32U-like).
constexpr double SYNTHETIC_ORIGIN_X = 500000.0;
constexpr double SYNTHETIC_ORIGIN_Y = 5400000.0;

/// The true surface in local coordinates (metres from the square's corner): rolling
/// hills (wavelengths 100-400 m, +-18 m), two gaussian peaks and a 20 m ripple of
/// 0.3 m, so interpolation error is visible at 1 m spacing.
double syntheticHeight(double x, double y);

/// Side of the square for n points: sqrt(n) metres.
double syntheticSide(std::size_t n);

/// n points, seeded (same seed = same points everywhere: std::mt19937_64 and
/// hand-written maps), exactly on the surface. points.offset is the world origin;
/// points.xyz is local.
PointSet syntheticTerrain(std::size_t n, std::uint64_t seed);

} // namespace compare
} // namespace pcl_vts
