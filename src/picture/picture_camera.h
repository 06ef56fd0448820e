// The camera of renderMesh: world point -> (column, row, depth) in output pixels. Built
// from the frame and the options only, so one frame gives one camera for every mesh.
// Coordinates go to the frame centre in double first: UTM-sized values keep their
// millimetres before any scaling.
#pragma once

#include <pcl_vts/picture/view.h>

namespace pcl_vts {
namespace picture_detail {

struct ScreenPoint {
  double column; ///< pixels from the left edge
  double row;    ///< pixels from the top edge
  double depth;  ///< pixels along the view direction: smaller is nearer
};

class PictureCamera {
 public:
  /// valid() is false for an empty frame or one without horizontal extent.
  PictureCamera(const PictureFrame& frame, const PictureOptions& options);

  bool valid() const { return valid_; }
  int width() const { return width_; }
  int height() const { return height_; }
  /// Vertical exaggeration used for OBLIQUE geometry and for shading in both views.
  double zScale() const { return z_scale_; }
  /// Lowest and highest z of the frame, for the colour ramp.
  double zMin() const { return z_min_; }
  double zMax() const { return z_max_; }
  /// First row below the caption band.
  int captionHeight() const { return caption_height_; }

  ScreenPoint project(double x, double y, double z) const;

 private:
  /// View coordinates of a point relative to the frame centre: right, up, depth.
  void toView(double dx, double dy, double dz, double& u, double& v, double& d) const;

  bool valid_ = false;
  PictureView view_ = PictureView::TOP;
  double centre_[3] = {0, 0, 0};
  double z_scale_ = 1.0;
  double z_min_ = 0, z_max_ = 0;
  double scale_ = 1.0;           // pixels per world unit
  double u_mid_ = 0, v_mid_ = 0; // view coordinates shown at the picture centre
  double column_mid_ = 0, row_mid_ = 0;
  int width_ = 0, height_ = 0, caption_height_ = 0;
};

/// Height in pixels of the band a caption takes at the top of a picture this wide.
int captionBandHeight(const std::string& caption, int width);

/// Width limits renderMesh applies (memory: 2x2 supersampled buffers).
constexpr int MIN_PICTURE_WIDTH = 16;
constexpr int MAX_PICTURE_WIDTH = 8192;

} // namespace picture_detail
} // namespace pcl_vts
