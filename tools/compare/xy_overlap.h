// Overlap in XY: a 2.5D surface covers each XY position at most once, so triangles
// whose XY interiors intersect are folds (GP3 and BPA make them; a Delaunay
// triangulation cannot). Two measures: the count of such triangles (an exact
// separating-axis test in double on every pair whose boxes share a grid cell), and
// the XY area covered more than once, estimated on the area-weighted samples.
// PCL-free.
#pragma once

#include "compare_mesh.h"
#include "surface_samples.h"
#include "triangle_grid.h"

#include <cstddef>

namespace pcl_vts {
namespace compare {

struct XyOverlap {
  /// Triangles whose XY interior intersects another's (touching along edges or at
  /// vertices does not count; zero-XY-area triangles are skipped).
  std::size_t overlapping_triangles = 0;
  /// XY area covered twice or more (each multiply covered region once), estimated:
  /// a sample covered by c triangles adds its XY area / c.
  double overlap_area = 0.0;
  double xy_area = 0.0; ///< sum of the triangles' XY areas
};

/// grid must index mesh's triangles.
XyOverlap measureXyOverlap(const CompareMesh& mesh, const TriangleGrid& grid,
                           const SurfaceSamples& samples, unsigned threads);

/// True when the XY interiors of triangles s and t intersect (the test above).
bool xyInteriorsIntersect(const CompareMesh& mesh, std::size_t s, std::size_t t);

} // namespace compare
} // namespace pcl_vts
