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

/// A float copy shifted by the bounding-box centre (so float keeps the detail), or
/// by the options' fixed shift.
pcl::PointCloud<pcl::PointXYZ>::Ptr shiftedCloud(const std::vector<double>& xyz,
                                                 const PreprocessOptions& options)
{
  std::array<double, 3> centre{options.shift[0], options.shift[1], options.shift[2]};
  if (!options.fixed_shift) {
    std::array<double, 3> lo{xyz[0], xyz[1], xyz[2]}, hi = lo;
    for (std::size_t k = 0; k < count(xyz); ++k)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], xyz[3 * k + c]);
        hi[c] = std::max(hi[c], xyz[3 * k + c]);
      }
    for (int c = 0; c < 3; ++c)
      centre[c] = 0.5 * (lo[c] + hi[c]);
  }
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(count(xyz));
  for (std::size_t k = 0; k < count(xyz); ++k) {
    pcl::PointXYZ& p = (*cloud)[k];
    p.x = static_cast<float>(xyz[3 * k] - centre[0]);
    p.y = static_cast<float>(xyz[3 * k + 1] - centre[1]);
    p.z = static_cast<float>(xyz[3 * k + 2] - centre[2]);
  }
  return cloud;
}

/// More rounds than this: a base so close to 1 (in float) that PCL's window loop
/// would not end.
constexpr std::size_t MAX_PMF_ROUNDS = 64;

std::vector<float> windowSizes(const PreprocessOptions& o, std::size_t cap)
{
  // pcl::ProgressiveMorphologicalFilter::extract's loop, expression for expression
  // (std::pow(float, int) is a double: the same promotions)
  const float cell_size = static_cast<float>(o.pmf_cell);
  const float base = static_cast<float>(o.pmf_base);
  std::vector<float> sizes;
  int iteration = 0;
  float window_size = 0.0f;
  // (The casts spell out PCL's implicit conversions.)
  while (window_size < static_cast<float>(o.pmf_max_window) && sizes.size() <= cap) {
    window_size =
        static_cast<float>(cell_size * (2.0f * std::pow(base, iteration) + 1.0f));
    sizes.push_back(window_size);
    iteration++;
  }
  return sizes;
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

std::vector<float> pmfWindowSizes(const PreprocessOptions& options)
{
  return windowSizes(options, MAX_PMF_ROUNDS);
}

double pmfReach(const PreprocessOptions& options)
{
  double reach = options.pmf_cell;
  for (const float w : pmfWindowSizes(options))
    reach += static_cast<double>(w);
  return reach;
}

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
  if (o.ground_pmf && windowSizes(o, MAX_PMF_ROUNDS).size() > MAX_PMF_ROUNDS)
    return bad("ground pmf: base " + formatValue(o.pmf_base) + ", cell " +
               formatValue(o.pmf_cell) + " and window " +
               std::to_string(o.pmf_max_window) + " make more than " +
               std::to_string(MAX_PMF_ROUNDS) +
               " window sizes (in float): raise the base or the cell");
  if (o.fixed_shift && !(std::isfinite(o.shift[0]) && std::isfinite(o.shift[1]) &&
                         std::isfinite(o.shift[2])))
    return bad("preprocessing shift must be finite");
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
        filter.setInputCloud(shiftedCloud(xyz, options));
        pcl::Indices indices;
        filter.filter(indices);
        keep(xyz, sortedIndices(indices));
      }))
    return empty("grid-min");
  if (options.outlier_k > 0 && !step("outliers", [&] {
        pcl::StatisticalOutlierRemoval<pcl::PointXYZ> filter;
        filter.setInputCloud(shiftedCloud(xyz, options));
        filter.setMeanK(options.outlier_k);
        filter.setStddevMulThresh(options.outlier_std);
        pcl::Indices indices;
        filter.filter(indices);
        keep(xyz, sortedIndices(indices));
      }))
    return empty("outliers");
  if (options.ground_pmf && !step("ground", [&] {
        pcl::ProgressiveMorphologicalFilter<pcl::PointXYZ> filter;
        filter.setInputCloud(shiftedCloud(xyz, options));
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
