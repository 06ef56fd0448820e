// Test support for the reconstruction post-passes: invariants of a trimmed or filled
// mesh (beyond mesh_checks.h: no pinch vertex, no duplicate triangle, loop
// classification checked independently), a synthetic terrain with a known footprint
// (concave notch, disc voids) and coverage / spill / z-error measures on a raster.
#pragma once

#include "support/synthetic_terrain.h"

#include <pcl_vts/core/mesh_arrays.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pcl_vts {
namespace test {

/// Adds a GoogleTest failure for each broken invariant: edge-manifold, twins
/// consistent, every triangle strictly CCW (so none degenerate), no duplicate
/// triangle (same vertex set), no pinch vertex (each used vertex has one fan),
/// boundary loops: per connected piece exactly one loop of positive area, the others
/// negative. Returns true when all hold.
bool expectValidSurfaceMesh(const TriangleMesh& mesh);

/// Vertices whose triangles form more than one fan (edge-connected around it).
std::size_t pinchVertexCount(const TriangleMesh& mesh);

/// Calls visit(x, y, triangle) for every raster sample (centres of the step x step
/// cells of a lattice anchored at the origin) inside a triangle first_triangle..;
/// shared edges count once. A non-null clip (x0, y0, x1, y1) skips the triangles
/// whose bounding box misses it.
void forEachCoveredSample(const TriangleMesh& mesh, std::size_t first_triangle,
                          double step,
                          const std::function<void(double, double, std::size_t)>& visit,
                          const double* clip = nullptr);

/// Mesh raster measures on a square raster of the given step over [0, size]^2.
struct CoverageFigures {
  double footprint_area = 0.0;
  double covered_footprint = 0.0; ///< footprint area under the mesh
  double spill = 0.0;             ///< mesh area outside the footprint
  double coverage() const { return covered_footprint / footprint_area; }
  double spillRatio() const { return spill / footprint_area; }
};
CoverageFigures measureCoverage(const TriangleMesh& mesh, const SyntheticTerrain& t,
                                double step);

/// Fraction of disc d's area covered by the mesh (raster of the given step).
double discCoverage(const TriangleMesh& mesh, const Disc& d, double step);

struct ZError {
  double rms = 0.0;
  double max = 0.0;
  std::size_t samples = 0;
};
/// z error against SyntheticTerrain::height at the flagged vertices.
ZError vertexZError(const TriangleMesh& mesh, const std::vector<std::uint8_t>& flags);
/// z error of the linear facets against the true surface, sampled on a raster over
/// the triangles first_triangle.. (the appended patches).
ZError patchZError(const TriangleMesh& mesh, std::size_t first_triangle, double step);

} // namespace test
} // namespace pcl_vts
