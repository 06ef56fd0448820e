// Metro-style distances (surface_error.h).
#include "surface_error.h"

#include <pcl_vts/core/parallel_for.h>

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <random>

namespace pcl_vts {
namespace compare {

struct PointReference::Tree {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud{new pcl::PointCloud<pcl::PointXYZ>};
  pcl::KdTreeFLANN<pcl::PointXYZ> kdtree;
};

namespace {

pcl::PointXYZ toPoint(const double* p)
{
  return {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
}

/// Per-thread sums, then combined.
struct Accumulator {
  std::size_t count = 0;
  double sum = 0.0, sum2 = 0.0, max = 0.0;
  void add(double d)
  {
    ++count;
    sum += d;
    sum2 += d * d;
    max = std::max(max, d);
  }
};

DistanceStats combine(const std::vector<Accumulator>& parts)
{
  Accumulator all;
  for (const Accumulator& a : parts) {
    all.count += a.count;
    all.sum += a.sum;
    all.sum2 += a.sum2;
    all.max = std::max(all.max, a.max);
  }
  DistanceStats stats;
  stats.count = all.count;
  if (all.count) {
    stats.mean = all.sum / static_cast<double>(all.count);
    stats.rms = std::sqrt(all.sum2 / static_cast<double>(all.count));
    stats.max = all.max;
  }
  return stats;
}

} // namespace

PointReference::PointReference(const PointSet& points, int k, unsigned threads)
    : points_(points)
    , tree_(new Tree)
{
  const std::size_t n = points.size();
  tree_->cloud->resize(n);
  for (std::size_t i = 0; i < n; ++i)
    (*tree_->cloud)[i] = toPoint(&points.xyz[3 * i]);
  normal_.assign(3 * n, 0.0);
  radius_.assign(n, 0.0);
  if (n == 0)
    return;
  tree_->kdtree.setSortedResults(false); // order is never used
  tree_->kdtree.setInputCloud(tree_->cloud);
  const int kk =
      static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(k), n));
  std::vector<double> spacing(n, 0.0);
  parallelChunks(threads, n, [&](std::size_t begin, std::size_t end, unsigned) {
    std::vector<int> ids;
    std::vector<float> d2;
    for (std::size_t i = begin; i < end; ++i) {
      tree_->kdtree.nearestKSearch((*tree_->cloud)[i], kk, ids, d2);
      const double* p = &points.xyz[3 * i];
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int id : ids)
        mean += Eigen::Vector3d(&points.xyz[3 * static_cast<std::size_t>(id)]);
      mean /= static_cast<double>(ids.size());
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      double r2 = 0.0, nearest2 = 0.0;
      for (int id : ids) {
        const double* q = &points.xyz[3 * static_cast<std::size_t>(id)];
        const Eigen::Vector3d d = Eigen::Vector3d(q) - mean;
        cov += d * d.transpose();
        const double e2 = (q[0] - p[0]) * (q[0] - p[0]) +
                          (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]);
        r2 = std::max(r2, e2);
        if (e2 > 0.0 && (nearest2 == 0.0 || e2 < nearest2))
          nearest2 = e2;
      }
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(cov);
      Eigen::Vector3d normal = solver.eigenvectors().col(0);
      if (!normal.allFinite() || normal.norm() == 0.0)
        normal = Eigen::Vector3d::UnitZ();
      normal.normalize();
      for (int c = 0; c < 3; ++c)
        normal_[3 * i + c] = normal[c];
      radius_[i] = std::sqrt(r2);
      spacing[i] = std::sqrt(nearest2);
    }
  });
  std::nth_element(spacing.begin(), spacing.begin() + static_cast<long>(n / 2),
                   spacing.end());
  median_spacing_ = spacing[n / 2];
}

PointReference::~PointReference() = default;

std::size_t PointReference::nearest(const double* p, double* distance) const
{
  // Per-thread buffers: one allocation per thread, not per query.
  thread_local std::vector<int> ids(1);
  thread_local std::vector<float> d2(1);
  tree_->kdtree.nearestKSearch(toPoint(p), 1, ids, d2);
  const auto i = static_cast<std::size_t>(ids[0]);
  if (distance) {
    const double* q = &points_.xyz[3 * i];
    *distance =
        std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                  (p[2] - q[2]) * (p[2] - q[2]));
  }
  return i;
}

bool PointReference::within(const double* p, double radius, int max_count,
                            std::vector<int>& ids) const
{
  thread_local std::vector<float> d2;
  // Float kd-tree, double geometry: widen a little so rounding cannot drop a point.
  const double r = radius * (1.0 + 1e-5) + 1e-6;
  const int found = tree_->kdtree.radiusSearch(toPoint(p), r, ids, d2,
                                               static_cast<unsigned>(max_count));
  return found >= max_count;
}

double PointReference::discDistance(std::size_t i, const double* p) const
{
  const double* q = &points_.xyz[3 * i];
  const double* n = &normal_[3 * i];
  const double v[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
  const double h = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
  const double lateral =
      std::sqrt(std::max(0.0, v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - h * h));
  const double beyond = std::max(0.0, lateral - radius_[i]);
  return std::sqrt(h * h + beyond * beyond);
}

double PointReference::distance(const double* p) const
{
  if (points_.size() == 0)
    return std::numeric_limits<double>::infinity();
  return discDistance(nearest(p), p);
}

DistanceStats meshToPoints(const SurfaceSamples& samples, const CompareMesh& mesh,
                           const PointReference& input, unsigned threads)
{
  constexpr int MAX_CANDIDATES = 64;
  std::vector<Accumulator> parts(threads);
  const std::size_t n = samples.size();
  // Chunks start at a triangle's first sample, so no run is split between threads.
  parallelChunks(threads, n, [&](std::size_t begin, std::size_t end, unsigned thread) {
    while (begin > 0 && begin < n &&
           samples.triangle[begin] == samples.triangle[begin - 1])
      ++begin;
    while (end < n && end > 0 && samples.triangle[end] == samples.triangle[end - 1])
      ++end;
    std::vector<int> candidates;
    for (std::size_t i = begin; i < end;) {
      const std::uint32_t t = samples.triangle[i];
      std::size_t j = i + 1;
      while (j < end && samples.triangle[j] == t)
        ++j;
      bool per_sample = j - i < 3;
      if (!per_sample) {
        double c[3] = {0.0, 0.0, 0.0}, rho = 0.0, d_c = 0.0;
        for (int k = 0; k < 3; ++k)
          for (int a = 0; a < 3; ++a)
            c[a] += mesh.xyz[3 * mesh.triangles[3 * t + k] + a] / 3.0;
        for (int k = 0; k < 3; ++k) {
          const double* v = &mesh.xyz[3 * mesh.triangles[3 * t + k]];
          rho = std::max(rho, std::sqrt((v[0] - c[0]) * (v[0] - c[0]) +
                                        (v[1] - c[1]) * (v[1] - c[1]) +
                                        (v[2] - c[2]) * (v[2] - c[2])));
        }
        // A vertex that is an input point bounds the centroid's nearest distance
        // and saves a kd-tree query; otherwise ask the tree.
        d_c = std::numeric_limits<double>::infinity();
        if (!mesh.source.empty())
          for (int k = 0; k < 3; ++k) {
            const std::int32_t s = mesh.source[mesh.triangles[3 * t + k]];
            if (s < 0)
              continue;
            const double* q = &input.points().xyz[3 * static_cast<std::size_t>(s)];
            d_c = std::min(d_c, std::sqrt((q[0] - c[0]) * (q[0] - c[0]) +
                                          (q[1] - c[1]) * (q[1] - c[1]) +
                                          (q[2] - c[2]) * (q[2] - c[2])));
          }
        if (!std::isfinite(d_c))
          input.nearest(c, &d_c);
        per_sample = input.within(c, 2.0 * rho + d_c, MAX_CANDIDATES, candidates) ||
                     candidates.empty();
      }
      for (std::size_t s = i; s < j; ++s) {
        const double* p = &samples.xyz[3 * s];
        if (per_sample) {
          parts[thread].add(input.distance(p));
          continue;
        }
        std::size_t best = 0;
        double best_d2 = std::numeric_limits<double>::infinity();
        for (int id : candidates) {
          const double* q = &input.points().xyz[3 * static_cast<std::size_t>(id)];
          const double d2 = (p[0] - q[0]) * (p[0] - q[0]) +
                            (p[1] - q[1]) * (p[1] - q[1]) +
                            (p[2] - q[2]) * (p[2] - q[2]);
          if (d2 < best_d2) {
            best_d2 = d2;
            best = static_cast<std::size_t>(id);
          }
        }
        parts[thread].add(input.discDistance(best, p));
      }
      i = j;
    }
  });
  return combine(parts);
}

DistanceStats pointsToMesh(const std::vector<double>& xyz, const TriangleGrid& grid,
                           unsigned threads)
{
  std::vector<Accumulator> parts(threads);
  parallelChunks(threads, xyz.size() / 3,
                 [&](std::size_t begin, std::size_t end, unsigned thread) {
                   for (std::size_t i = begin; i < end; ++i)
                     parts[thread].add(grid.nearestDistance(&xyz[3 * i]));
                 });
  return combine(parts);
}

DistanceStats meshToTruth(const SurfaceSamples& samples,
                          double (*height)(double, double), unsigned threads)
{
  std::vector<Accumulator> parts(threads);
  parallelChunks(threads, samples.size(),
                 [&](std::size_t begin, std::size_t end, unsigned thread) {
                   for (std::size_t i = begin; i < end; ++i) {
                     const double* p = &samples.xyz[3 * i];
                     parts[thread].add(std::fabs(p[2] - height(p[0], p[1])));
                   }
                 });
  return combine(parts);
}

std::vector<double> truthSamples(double (*height)(double, double), double side,
                                 std::size_t count, std::uint64_t seed)
{
  std::vector<double> xyz;
  const std::size_t per_side = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::sqrt(static_cast<double>(count))));
  const double step = side / static_cast<double>(per_side);
  std::mt19937_64 engine(seed);
  auto uniform = [&] { return static_cast<double>(engine() >> 11) * 0x1p-53; };
  xyz.reserve(3 * per_side * per_side);
  for (std::size_t j = 0; j < per_side; ++j)
    for (std::size_t i = 0; i < per_side; ++i) {
      const double x = (static_cast<double>(i) + uniform()) * step;
      const double y = (static_cast<double>(j) + uniform()) * step;
      xyz.insert(xyz.end(), {x, y, height(x, y)});
    }
  return xyz;
}

} // namespace compare
} // namespace pcl_vts
