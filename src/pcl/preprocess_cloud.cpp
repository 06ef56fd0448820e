#include <pcl_vts/core/stopwatch.h>
#include <pcl_vts/preprocess_cloud.h>

#include <pcl/filters/grid_minimum.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/segmentation/progressive_morphological_filter.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace pcl_vts {
namespace {

std::size_t count(const std::vector<double>& xyz)
{
  return xyz.size() / 3;
}

/// Keeps the points whose indices are listed (ascending), in place.
void keep(std::vector<double>& xyz, const std::vector<std::size_t>& indices)
{
  std::size_t out = 0;
  for (const std::size_t k : indices) {
    for (int c = 0; c < 3; ++c)
      xyz[3 * out + c] = xyz[3 * k + c];
    ++out;
  }
  xyz.resize(3 * out);
}

/// A float copy shifted by the bounding-box centre (so float keeps the detail).
pcl::PointCloud<pcl::PointXYZ>::Ptr shiftedCloud(const std::vector<double>& xyz)
{
  std::array<double, 3> lo{xyz[0], xyz[1], xyz[2]}, hi = lo;
  for (std::size_t k = 0; k < count(xyz); ++k)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], xyz[3 * k + c]);
      hi[c] = std::max(hi[c], xyz[3 * k + c]);
    }
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(count(xyz));
  for (std::size_t k = 0; k < count(xyz); ++k) {
    pcl::PointXYZ& p = (*cloud)[k];
    p.x = static_cast<float>(xyz[3 * k] - 0.5 * (lo[0] + hi[0]));
    p.y = static_cast<float>(xyz[3 * k + 1] - 0.5 * (lo[1] + hi[1]));
    p.z = static_cast<float>(xyz[3 * k + 2] - 0.5 * (lo[2] + hi[2]));
  }
  return cloud;
}

std::vector<std::size_t> sortedIndices(const pcl::Indices& indices)
{
  std::vector<std::size_t> out(indices.begin(), indices.end());
  std::sort(out.begin(), out.end());
  return out;
}

/// One original point per cubic voxel: the one nearest the voxel centre (ties: the
/// first). Exact in double.
void voxelThin(std::vector<double>& xyz, double size)
{
  const std::size_t n = count(xyz);
  std::array<double, 3> lo{xyz[0], xyz[1], xyz[2]};
  for (std::size_t k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c)
      lo[c] = std::min(lo[c], xyz[3 * k + c]);
  std::vector<std::array<double, 3>> cell(n);
  for (std::size_t k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c)
      cell[k][c] = std::floor((xyz[3 * k + c] - lo[c]) / size);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return cell[a] < cell[b]; });
  const auto distance2 = [&](std::size_t k) {
    double d = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double centre = lo[c] + (cell[k][c] + 0.5) * size;
      d += (xyz[3 * k + c] - centre) * (xyz[3 * k + c] - centre);
    }
    return d;
  };
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1, best = order[i];
    while (j < n && cell[order[j]] == cell[order[i]]) {
      if (distance2(order[j]) < distance2(best))
        best = order[j];
      ++j;
    }
    kept.push_back(best);
    i = j;
  }
  std::sort(kept.begin(), kept.end());
  keep(xyz, kept);
}

} // namespace

Status validatePreprocessOptions(const PreprocessOptions& o)
{
  const auto bad = [](const std::string& what) {
    return Status::error(StatusCode::INVALID_PARAMETER, what);
  };
  if (o.crop && !(std::isfinite(o.crop_min_x) && std::isfinite(o.crop_min_y) &&
                  std::isfinite(o.crop_max_x) && std::isfinite(o.crop_max_y) &&
                  o.crop_min_x < o.crop_max_x && o.crop_min_y < o.crop_max_y))
    return bad("crop box " + formatValue(o.crop_min_x) + "," +
               formatValue(o.crop_min_y) + "," + formatValue(o.crop_max_x) + "," +
               formatValue(o.crop_max_y) +
               " must be finite with xmin < xmax and ymin < ymax");
  if (Status s = checkFiniteNonNegative("voxel", o.voxel); !s.ok())
    return s;
  if (Status s = checkFiniteNonNegative("grid_min", o.grid_min); !s.ok())
    return s;
  if (o.outlier_k < 0 ||
      (o.outlier_k > 0 && !(std::isfinite(o.outlier_std) && o.outlier_std > 0.0)))
    return bad("outliers k = " + std::to_string(o.outlier_k) + ", std = " +
               formatValue(o.outlier_std) + ": k must be >= 0 and std finite and > 0");
  if (o.ground_pmf &&
      !(std::isfinite(o.pmf_cell) && o.pmf_cell > 0.0 && o.pmf_max_window >= 1 &&
        std::isfinite(o.pmf_slope) && o.pmf_slope >= 0.0 &&
        std::isfinite(o.pmf_initial_distance) && o.pmf_initial_distance >= 0.0 &&
        std::isfinite(o.pmf_max_distance) && o.pmf_max_distance >= 0.0 &&
        std::isfinite(o.pmf_base) && o.pmf_base > 1.0))
    return bad("ground pmf: cell " + formatValue(o.pmf_cell) + ", window " +
               std::to_string(o.pmf_max_window) + ", slope " +
               formatValue(o.pmf_slope) + ", distances " +
               formatValue(o.pmf_initial_distance) + "/" +
               formatValue(o.pmf_max_distance) + ", base " + formatValue(o.pmf_base) +
               ": cell > 0, window >= 1, slope and distances >= 0, base > 1");
  return Status::success();
}

Status preprocessCloud(std::vector<double>& xyz, const PreprocessOptions& options,
                       std::vector<PreprocessStep>& steps)
{
  steps.clear();
  if (Status s = validatePreprocessOptions(options); !s.ok())
    return s;
  if (!options.any())
    return Status::success();
  const auto step = [&](const char* name, auto&& apply) {
    PreprocessStep st{name, count(xyz), 0, 0.0};
    const Stopwatch watch;
    apply();
    st.after = count(xyz);
    st.ms = watch.milliseconds();
    steps.push_back(st);
    return st.after > 0;
  };
  const auto empty = [&](const char* name) {
    return Status::error(StatusCode::EMPTY_INPUT,
                         std::string("no point left after preprocessing step '") +
                             name + "'");
  };
  if (!step("non-finite", [&] {
        std::vector<std::size_t> finite;
        for (std::size_t k = 0; k < count(xyz); ++k)
          if (std::isfinite(xyz[3 * k]) && std::isfinite(xyz[3 * k + 1]) &&
              std::isfinite(xyz[3 * k + 2]))
            finite.push_back(k);
        keep(xyz, finite);
      }))
    return empty("non-finite");
  if (options.crop && !step("crop", [&] {
        std::vector<std::size_t> inside;
        for (std::size_t k = 0; k < count(xyz); ++k) {
          const double x = xyz[3 * k], y = xyz[3 * k + 1];
          if (x >= options.crop_min_x && x <= options.crop_max_x &&
              y >= options.crop_min_y && y <= options.crop_max_y)
            inside.push_back(k);
        }
        keep(xyz, inside);
      }))
    return empty("crop");
  if (options.voxel > 0.0 && !step("voxel", [&] { voxelThin(xyz, options.voxel); }))
    return empty("voxel");
  if (options.grid_min > 0.0 && !step("grid-min", [&] {
        pcl::GridMinimum<pcl::PointXYZ> filter(static_cast<float>(options.grid_min));
        filter.setInputCloud(shiftedCloud(xyz));
        pcl::Indices indices;
        filter.filter(indices);
        keep(xyz, sortedIndices(indices));
      }))
    return empty("grid-min");
  if (options.outlier_k > 0 && !step("outliers", [&] {
        pcl::StatisticalOutlierRemoval<pcl::PointXYZ> filter;
        filter.setInputCloud(shiftedCloud(xyz));
        filter.setMeanK(options.outlier_k);
        filter.setStddevMulThresh(options.outlier_std);
        pcl::Indices indices;
        filter.filter(indices);
        keep(xyz, sortedIndices(indices));
      }))
    return empty("outliers");
  if (options.ground_pmf && !step("ground", [&] {
        pcl::ProgressiveMorphologicalFilter<pcl::PointXYZ> filter;
        filter.setInputCloud(shiftedCloud(xyz));
        filter.setCellSize(static_cast<float>(options.pmf_cell));
        filter.setMaxWindowSize(options.pmf_max_window);
        filter.setSlope(static_cast<float>(options.pmf_slope));
        filter.setInitialDistance(static_cast<float>(options.pmf_initial_distance));
        filter.setMaxDistance(static_cast<float>(options.pmf_max_distance));
        filter.setBase(static_cast<float>(options.pmf_base));
        filter.setExponential(true);
        pcl::Indices ground;
        filter.extract(ground);
        keep(xyz, sortedIndices(ground));
      }))
    return empty("ground");
  return Status::success();
}

} // namespace pcl_vts
