// Local point spacing of a triangulated point set, the length scale of the
// reconstruction post-passes: per vertex the median length of its incident edges,
// smoothed by the median over the vertex and its edge neighbours so that one
// isolated or crowded point, or a few edges into a void, do not set the scale of its
// neighbourhood. docs/reconstruction.md, "Spacing".
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/mesh_arrays.h>

#include <vector>

namespace pcl_vts {

struct PointSpacing {
  /// Per vertex: median, over the vertex and its neighbours, of their median
  /// incident edge length; 0 for a vertex without triangle.
  std::vector<double> local;
  /// Median over the vertices used by triangles of their median incident edge
  /// length; 0 when there is no triangle.
  double global_median = 0.0;
};

/// Measures the spacing of the vertices of mesh (triangles and halfedges read). With
/// `local_for`, the local spacing is only computed for the vertices it flags (the
/// others read 0); the global median is always the whole mesh's.
PCL_VTS_CORE_EXPORT PointSpacing measurePointSpacing(
    const TriangleMesh& mesh, const std::vector<bool>* local_for = nullptr);

/// Median of values (copied; 0 when empty). Upper median for an even count.
PCL_VTS_CORE_EXPORT double medianOf(std::vector<double> values);

} // namespace pcl_vts
