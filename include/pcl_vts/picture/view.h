// How renderMesh looks at a mesh: the view direction, the world box it frames and the
// picture options. The bottom of the picture module with image.h: the private
// camera builds on these types alone, never on mesh_picture.h.
#pragma once

#include <pcl_vts/picture/export.h>

#include <cstdint>
#include <string>

namespace pcl_vts {

enum class PictureView : std::uint8_t {
  TOP,    ///< orthographic from above, north (+y) up
  OBLIQUE ///< orthographic from the south-west, ~35 degrees above the horizon
};

/// World box the camera frames; the same frame for several meshes gives the same
/// camera.
struct PictureFrame {
  double min[3];
  double max[3];
};

/// True when the box holds no point or is not finite.
PCL_VTS_PICTURE_EXPORT bool isEmpty(const PictureFrame& frame);
/// Smallest box holding both (an empty box is the neutral element).
PCL_VTS_PICTURE_EXPORT PictureFrame unionOf(const PictureFrame& a,
                                            const PictureFrame& b);

struct PictureOptions {
  PictureView view = PictureView::TOP;
  int width = 800;     ///< pixels; height follows from the frame's aspect
  double z_scale = 0;  ///< vertical exaggeration for OBLIQUE; 0 = automatic
  std::string caption; ///< drawn at the top-left in a small bitmap font; empty = none
};

} // namespace pcl_vts
