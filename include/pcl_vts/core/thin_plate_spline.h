// Thin-plate spline z(x, y) through scattered samples: the smoothest surface (least
// bending energy) that interpolates them, i.e. the "minimum curvature" surface of
// terrain modelling (Duchon 1977; Briggs 1974). Used to give inserted hole points a
// z that continues the surrounding slope and curvature. docs/reconstruction.md.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/point2.h>

#include <cstddef>
#include <vector>

namespace pcl_vts {

class PCL_VTS_CORE_EXPORT ThinPlateSpline {
 public:
  /// Fits the spline through (xy[i], z[i]). Coordinates are centred and scaled
  /// internally. Falls back to a least-squares plane when the samples are too few
  /// (< 3), collinear or the system is singular, and to their mean if even the plane
  /// is undetermined. Returns false only when there is no sample (z = 0 then).
  /// O(n^3) in the sample count: callers keep n in the hundreds.
  bool fit(const std::vector<Point2>& xy, const std::vector<double>& z);

  /// Value at p.
  double evaluate(const Point2& p) const;

  /// True when the fit is a spline (not a plane or constant fallback).
  bool isSpline() const { return !weights_.empty(); }

 private:
  Point2 centre_{0.0, 0.0};
  double scale_ = 1.0;
  std::vector<Point2> centres_;        ///< normalised sample positions
  std::vector<double> weights_;        ///< one per centre (empty: plane only)
  double affine_[3] = {0.0, 0.0, 0.0}; ///< a + b x + c y (normalised x, y)
};

} // namespace pcl_vts
