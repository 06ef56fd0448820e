// The synthetic terrain of the reconstruction figures (docs/reconstruction.md): a
// jittered grid with a concave notch and disc voids over a known height function.
// Plain C++ (no GoogleTest): tools/docs_pictures.cpp draws it too.
#pragma once

#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace test {

struct Disc {
  double cx, cy, r;
};

/// Jittered grid over [0, size]^2 (cell centres + U(-0.3, 0.3)), keeping only the
/// points inside the footprint: the square minus a rectangular notch cut from the
/// top edge minus disc voids. z = height(x, y).
struct SyntheticTerrain {
  double size = 0.0;
  double notch_x0 = 0.0, notch_x1 = 0.0, notch_y0 = 0.0; ///< notch: [x0,x1] x [y0,size]
  std::vector<Disc> voids;
  std::vector<double> xyz;

  bool inFootprint(double x, double y) const;
  static double height(double x, double y);
};

/// The terrain of the measured figures (docs/reconstruction.md): size 400, notch
/// 100 x 150, voids of radius 2, 3, 6, 10 (filled under a 600 area limit) and 25
/// (left open).
SyntheticTerrain makeSyntheticTerrain(std::uint64_t seed);

} // namespace test
} // namespace pcl_vts
