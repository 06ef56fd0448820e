// Every figure of a comparison row, computed in one place with the same code for every
// method: topology (mesh_topology.h), XY overlap (xy_overlap.h) and Metro-style
// error against the input and, when known, the true surface (surface_error.h).
#pragma once

#include "compare_mesh.h"
#include "mesh_topology.h"
#include "surface_error.h"
#include "xy_overlap.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace pcl_vts {
namespace compare {

struct MetricsOptions {
  double samples_per_triangle = 10.0;
  std::size_t max_samples = 0; ///< 0 = no cap
  std::uint64_t seed = 1;
  unsigned threads = 1;
  /// True surface z = truth(x, y) over [0, truth_side]^2 (local frame), or null.
  double (*truth)(double, double) = nullptr;
  double truth_side = 0.0;
  std::size_t truth_samples = 0; ///< points of the true surface for truth -> mesh
};

struct MeshMetrics {
  TopologyCounts topology;
  long long unused_points = -1; ///< -1: not a vertex-based method
  XyOverlap overlap;
  std::size_t samples = 0;
  DistanceStats mesh_to_points;
  DistanceStats points_to_mesh;
  double hausdorff = 0.0; ///< max of both maxima
  bool has_truth = false;
  DistanceStats mesh_to_truth;
  DistanceStats truth_to_mesh;
  double hausdorff_truth = 0.0;
  double seconds = 0.0; ///< time spent computing all this
  /// Where that time went: "overlap 1.2 s, mesh->points 3.4 s, ...".
  std::string timing;
};

MeshMetrics computeMeshMetrics(const CompareMesh& mesh, const PointReference& input,
                               const MetricsOptions& options);

} // namespace compare
} // namespace pcl_vts
