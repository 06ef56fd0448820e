// Poisson fits a closed implicit surface in the 1.1x bounding cube, so on an open
// terrain patch it extrapolates past the data (a skirt curling down to the cube, and
// bridges over data voids). For the error figures its mesh is trimmed to the data
// footprint: a triangle is kept when the XY distance from its centroid to the nearest
// input point is at most factor x spacing. What was cut is reported.
#pragma once

#include "compare_mesh.h"

#include <cstddef>

namespace pcl_vts {
namespace compare {

struct FootprintTrim {
  std::size_t triangles_before = 0;
  std::size_t triangles_after = 0;
  double area_before = 0.0;           ///< 3D area
  double area_cut = 0.0;              ///< 3D area of the triangles removed
  double max_centroid_distance = 0.0; ///< largest XY centroid-to-data distance before
  double threshold = 0.0;
  double box_min[3] = {0, 0, 0}; ///< box of the untrimmed mesh's used vertices
  double box_max[3] = {0, 0, 0};
};

/// Trims mesh in place (vertices are kept; only triangles go).
FootprintTrim trimToFootprint(CompareMesh& mesh, const PointSet& input, double spacing,
                              double factor);

} // namespace compare
} // namespace pcl_vts
