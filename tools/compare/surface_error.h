// Metro-style distances between a mesh and the input points (and, for synthetic data,
// the true surface), in both directions.
//   mesh -> points: from each area-weighted sample to the input, measured to the
//     nearest input point's tangent disc (plane of its k nearest neighbours, radius
//     = distance to the k-th of them): a point cloud has no surface between its
//     points, and the plain nearest-point distance would charge a perfect mesh about
//     half the spacing; the disc is zero on the sampled surface and grows like the
//     distance to the data once the sample leaves the data's footprint.
//   points -> mesh: from each input point to the nearest triangle, exact
//     point-to-triangle distance (TriangleGrid).
//   truth: mesh -> truth is |z - f(x, y)| at the samples (vertical, an upper bound of
//     the true distance); truth -> mesh is the exact distance from points of the true
//     surface (a jittered lattice over the data's square) to the nearest triangle.
// The kd-tree is PCL's (KdTreeFLANN over float xyz in the local frame).
#pragma once

#include "compare_mesh.h"
#include "surface_samples.h"
#include "triangle_grid.h"

#include <cstddef>
#include <memory>
#include <vector>

namespace pcl_vts {
namespace compare {

struct DistanceStats {
  std::size_t count = 0;
  double mean = 0.0;
  double rms = 0.0;
  double max = 0.0;
};

/// The input as a reference surface: kd-tree plus one tangent disc per point.
class PointReference {
 public:
  /// k neighbours (the point itself included) for each tangent plane.
  PointReference(const PointSet& points, int k, unsigned threads);
  ~PointReference();
  PointReference(const PointReference&) = delete;
  PointReference& operator=(const PointReference&) = delete;

  /// Distance from p (local xyz) to the tangent disc of its nearest input point.
  double distance(const double* p) const;
  /// Distance from p to the tangent disc of input point i.
  double discDistance(std::size_t i, const double* p) const;
  /// Index of the nearest input point to (x, y, z), and its distance.
  std::size_t nearest(const double* p, double* distance = nullptr) const;
  /// Input points within radius of p (at most max_count; true when there may be more).
  bool within(const double* p, double radius, int max_count,
              std::vector<int>& ids) const;
  /// Median distance from a point to its nearest other point (0 when all coincide).
  double medianSpacing() const { return median_spacing_; }
  const PointSet& points() const { return points_; }

 private:
  struct Tree;
  const PointSet& points_;
  std::unique_ptr<Tree> tree_;
  std::vector<double> normal_; ///< 3 per point, unit
  std::vector<double> radius_; ///< per point
  double median_spacing_ = 0.0;
};

/// Samples -> input points (tangent discs). The samples of one triangle share one
/// radius search (the nearest point of any of them lies within 2 rho + d of the
/// centroid, rho = the triangle's centroid-to-corner reach, d = the centroid's
/// nearest-point distance), falling back to one query per sample when that ball
/// holds too many points; exact either way.
DistanceStats meshToPoints(const SurfaceSamples& samples, const CompareMesh& mesh,
                           const PointReference& input, unsigned threads);
/// Every point of xyz (3 per point) -> nearest triangle of the grid's mesh.
DistanceStats pointsToMesh(const std::vector<double>& xyz, const TriangleGrid& grid,
                           unsigned threads);
/// Samples -> true surface, vertically.
DistanceStats meshToTruth(const SurfaceSamples& samples,
                          double (*height)(double, double), unsigned threads);
/// About count points of the true surface on a jittered lattice over
/// [0, side] x [0, side], seeded.
std::vector<double> truthSamples(double (*height)(double, double), double side,
                                 std::size_t count, std::uint64_t seed);

} // namespace compare
} // namespace pcl_vts
