// Pictures of the compared meshes (pcl_vts/picture/mesh_picture.h): one strip per view
// with the methods side by side, every method through the same frame (the input's
// box), so the camera is the same. Boundary edges red, non-manifold edges magenta,
// hole-filling triangles in the renderer's "filled" colour, input points left out
// as dark dots (none when more than 1500 are: they would hide the surface), back
// faces (flipped triangles) orange.
#pragma once

#include "compare_mesh.h"
#include "mesh_topology.h"

#include <pcl_vts/core/status.h>
#include <pcl_vts/picture/mesh_picture.h>

#include <string>
#include <vector>

namespace pcl_vts {
namespace compare {

struct MethodPictures {
  Picture top;
  Picture oblique;
};

/// The input's box as the common frame.
PictureFrame frameOfPoints(const PointSet& points);

/// Renders mesh (or, when mesh is null, a placeholder whose caption gives the
/// reason). The view from above is at most width pixels wide and about as tall
/// (narrower for a frame taller than wide, so the PNGs stay small); the oblique view
/// is width pixels wide.
MethodPictures renderMethod(const CompareMesh* mesh, const TopologyCounts* topology,
                            const PictureFrame& frame, int width,
                            const std::string& caption);

/// Writes <dir>/<name>_top.png and <dir>/<name>_oblique.png.
Status writePictureStrips(const std::string& dir, const std::string& name,
                          const std::vector<MethodPictures>& pictures);

} // namespace compare
} // namespace pcl_vts
