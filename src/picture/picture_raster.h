// A z-buffered colour raster: triangles by edge functions, lines and dots by stamps,
// then a box filter down to the output size (supersampling for clean edges).
#pragma once

#include "picture_camera.h"

#include <pcl_vts/picture/image.h>

#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace picture_detail {

class Raster {
 public:
  /// width x height samples, every one background and infinitely far.
  Raster(int width, int height, PictureColour background);

  int width() const { return width_; }
  int height() const { return height_; }

  /// False when the bounding box of a, b, c holds no sample: nothing to fill, so the
  /// caller can skip colouring it (most triangles of a big mesh are sub-sample).
  bool mayCover(const ScreenPoint& a, const ScreenPoint& b, const ScreenPoint& c) const;

  /// Fills the samples (pixel centres) inside the closed triangle a, b, c of either
  /// orientation where it is nearer than what is there. Two triangles sharing an edge
  /// evaluate it with the same arithmetic, so a sample on it is never missed by both.
  void fillTriangle(const ScreenPoint& a, const ScreenPoint& b, const ScreenPoint& c,
                    PictureColour colour);

  /// A line of square stamps brush samples wide; a stamp sample is drawn when the
  /// line's depth minus depth_bias is not behind the surface there.
  void drawLine(ScreenPoint a, ScreenPoint b, int brush, double depth_bias,
                PictureColour colour);

  /// A disc of the given radius (samples), depth-tested like drawLine.
  void drawDot(const ScreenPoint& p, double radius, double depth_bias,
               PictureColour colour);

  /// Averages factor x factor blocks into an output picture.
  Picture downsample(int factor) const;

 private:
  void stamp(int column, int row, double depth, PictureColour colour);

  int width_, height_;
  std::vector<float> depth_;
  std::vector<std::uint8_t> rgb_;
};

} // namespace picture_detail
} // namespace pcl_vts
