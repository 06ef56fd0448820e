// Whole-output checks of runVtsPipeline, shared by the property tests and the real
// DEM tests: every invariant of a Delaunay triangulation of the convex hull, decided
// with exact predicates, then equality with CGAL (cgal_oracle.h).
#pragma once

#include "support/cgal_oracle.h"

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <string>
#include <vector>

namespace pcl_vts {
namespace test {

struct PipelineRun {
  Status status;
  VtsResult result;
};

/// runVtsPipeline over xyz (3 doubles per point).
PipelineRun runPipeline(const std::vector<double>& xyz, const VtsOptions& options = {});

/// The status the pipeline must return for xyz, decided independently: EMPTY_INPUT
/// (no finite point), TOO_FEW_POINTS (< 3 distinct XY), ALL_COLLINEAR (exact), or OK.
StatusCode expectedStatusCode(const std::vector<double>& xyz);

struct ValidationSummary {
  bool cocircular_ties = false; ///< some Delaunay edge has 4 cocircular points
  std::size_t distinct_points = 0;
  std::size_t hull_vertices = 0;
};

/// Adds a GoogleTest failure for every broken invariant of a successful run:
/// vertices = the distinct finite XY positions (both id maps, duplicate rule),
/// 2n - h - 2 triangles, diagnostics, CCW, twins, edge manifold, every vertex used,
/// Euler number 1, Delaunay (exact incircle) and perturbed-Delaunay (tie-break),
/// hull = exact convex hull (collinear kept), CCW, containing every point, equal to
/// the mesh boundary, with the mesh's area; then the triangle set equals CGAL's:
/// always the mirrored oracle (same tie-break), and plain CGAL when no ties exist.
ValidationSummary expectValidTriangulation(const std::vector<double>& xyz,
                                           const PipelineRun& run,
                                           const VtsOptions& options = {});

/// Every interior edge strictly locally Delaunay under incirclePerturbed: then the
/// triangulation is the unique Delaunay triangulation of the perturbed point set.
bool isPerturbedDelaunay(const TriangleMesh& mesh, std::string* why = nullptr);

/// Canonical triangles with each vertex replaced by its lexicographic rank among the
/// mesh positions: equal for two meshes over the same positions, whatever the ids.
std::vector<IndexTriangle> trianglesByPosition(const TriangleMesh& mesh);

} // namespace test
} // namespace pcl_vts
