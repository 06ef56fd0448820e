// One comparison row's figures (mesh_metrics.h).
#include "mesh_metrics.h"
#include "surface_samples.h"
#include "triangle_grid.h"

#include <pcl_vts/core/stopwatch.h>

#include <algorithm>
#include <cstdio>
#include <limits>

namespace pcl_vts {
namespace compare {

MeshMetrics computeMeshMetrics(const CompareMesh& mesh, const PointReference& input,
                               const MetricsOptions& options)
{
  const Stopwatch total;
  Stopwatch step;
  MeshMetrics m;
  auto lap = [&](const char* what) {
    char text[64];
    std::snprintf(text, sizeof(text), "%s%s %.1f s", m.timing.empty() ? "" : ", ", what,
                  step.seconds());
    m.timing += text;
    step.restart();
  };
  const PointSet& points = input.points();
  m.topology = countTopology(mesh);
  m.unused_points = countUnusedPoints(mesh, points);

  double box[4] = {std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity()};
  for (std::size_t i = 0; i < points.size(); ++i) {
    box[0] = std::min(box[0], points.xyz[3 * i]);
    box[1] = std::min(box[1], points.xyz[3 * i + 1]);
    box[2] = std::max(box[2], points.xyz[3 * i]);
    box[3] = std::max(box[3], points.xyz[3 * i + 1]);
  }
  const TriangleGrid grid(mesh, box[0], box[1], box[2], box[3]);
  const SurfaceSamples samples = sampleSurface(mesh, options.samples_per_triangle,
                                               options.max_samples, options.seed);
  m.samples = samples.size();
  lap("topology, grid, samples");
  m.overlap = measureXyOverlap(mesh, grid, samples, options.threads);
  lap("overlap");
  m.mesh_to_points = meshToPoints(samples, mesh, input, options.threads);
  lap("mesh->points");
  m.points_to_mesh = pointsToMesh(points.xyz, grid, options.threads);
  lap("points->mesh");
  m.hausdorff = std::max(m.mesh_to_points.max, m.points_to_mesh.max);
  if (options.truth) {
    m.has_truth = true;
    m.mesh_to_truth = meshToTruth(samples, options.truth, options.threads);
    const std::vector<double> truth = truthSamples(
        options.truth, options.truth_side, options.truth_samples, options.seed + 1);
    m.truth_to_mesh = pointsToMesh(truth, grid, options.threads);
    m.hausdorff_truth = std::max(m.mesh_to_truth.max, m.truth_to_mesh.max);
    lap("truth");
  }
  m.seconds = total.seconds();
  return m;
}

} // namespace compare
} // namespace pcl_vts
