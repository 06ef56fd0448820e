// Optional preprocessing of the input points before the triangulation, in this order:
// crop (XY box, exact in double), voxel thinning (one original point per cubic voxel,
// the one nearest the voxel centre), grid minimum (pcl::GridMinimum: the lowest
// original point per XY cell) and statistical outlier removal
// (pcl::StatisticalOutlierRemoval). Every step keeps original points: the doubles of
// the survivors are untouched (PCL's float types see offset-shifted copies only).
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/export.h>

#include <cstddef>
#include <string>
#include <vector>

namespace pcl_vts {

struct PreprocessOptions {
  bool crop = false;
  double crop_min_x = 0.0, crop_min_y = 0.0, crop_max_x = 0.0, crop_max_y = 0.0;
  double voxel = 0.0;       ///< voxel edge length; 0 = off
  double grid_min = 0.0;    ///< GridMinimum resolution; 0 = off
  int outlier_k = 0;        ///< neighbours for the outlier statistics; 0 = off
  double outlier_std = 0.0; ///< standard-deviation multiplier (> 0 when k > 0)
  /// Ground extraction, last: pcl::ProgressiveMorphologicalFilter keeps the points
  /// it classifies as bare earth (Zhang et al. 2003). The defaults fit airborne
  /// LiDAR of about a point per square metre in metres (docs/ground.md).
  bool ground_pmf = false;
  double pmf_cell = 1.0;             ///< cell size of the morphological grid
  int pmf_max_window = 33;           ///< largest window, cells: wider than any building
  double pmf_slope = 1.0;            ///< terrain slope (rise over run) tolerated
  double pmf_initial_distance = 0.5; ///< height threshold of the first window
  double pmf_max_distance = 3.0;     ///< height threshold cap
  double pmf_base = 2.0;             ///< window growth base: 1, base, base^2, ... cells
  /// The PCL filters see float copies shifted by this point (xyz). Unset (the
  /// default): the centre of the bounding box of the points they see. The tiled PMF
  /// ground filter sets the whole cloud's centre in every pre-tile, so that PCL sees
  /// the floats of the in-memory run (ground_tiles.h).
  bool fixed_shift = false;
  double shift[3] = {0.0, 0.0, 0.0};

  bool any() const
  {
    return crop || voxel > 0.0 || grid_min > 0.0 || outlier_k > 0 || ground_pmf;
  }
};

/// One preprocessing step as reported in the summary.
struct PreprocessStep {
  std::string name; ///< "crop", "voxel", "grid-min", "outliers", "ground", "non-finite"
  std::size_t before = 0;
  std::size_t after = 0;
  double ms = 0.0;
};

/// The window sizes (XY units) of the ground filter's rounds, computed exactly as
/// pcl::ProgressiveMorphologicalFilter::extract computes them (float arithmetic).
PCL_VTS_EXPORT std::vector<float> pmfWindowSizes(const PreprocessOptions& options);

/// How far (L-infinity in XY) the ground filter looks: a point's class depends only
/// on the points within this distance of it. Each round opens (erodes, then
/// dilates) with boxes of half its window, so it reaches one window: the sum of the
/// windows, plus one cell for the float rounding.
PCL_VTS_EXPORT double pmfReach(const PreprocessOptions& options);

/// Checks the options; the message names the value.
PCL_VTS_EXPORT Status validatePreprocessOptions(const PreprocessOptions& options);

/// Applies the enabled steps to xyz (3 doubles per point) in place. Points with a
/// non-finite coordinate are dropped first (reported as a "non-finite" step) when any
/// step is enabled. EMPTY_INPUT when nothing survives.
PCL_VTS_EXPORT Status preprocessCloud(std::vector<double>& xyz,
                                      const PreprocessOptions& options,
                                      std::vector<PreprocessStep>& steps);

} // namespace pcl_vts
