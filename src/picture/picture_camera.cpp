// Orthographic cameras of renderMesh. See picture_camera.h.
#include "bitmap_font.h"
#include "picture_camera.h"

#include <algorithm>
#include <cmath>

namespace pcl_vts {
namespace picture_detail {

namespace {

constexpr double ELEVATION_DEGREES = 35.0;
constexpr double RELIEF_SHARE = 0.25; // auto exaggeration: relief ~ 1/4 of the extent
constexpr double MAX_AUTO_Z_SCALE = 20.0;
constexpr double MAX_ASPECT = 2.0; // height <= 2 x width: thin strips are scaled down

int marginFor(int width)
{
  return std::max(4, width / 60);
}

} // namespace

int captionBandHeight(const std::string& caption, int width)
{
  if (caption.empty())
    return 0;
  return textHeight(caption, textScaleFor(width)) + 2 * marginFor(width);
}

PictureCamera::PictureCamera(const PictureFrame& frame, const PictureOptions& options)
    : view_(options.view)
{
  if (isEmpty(frame))
    return;
  const double dx = frame.max[0] - frame.min[0], dy = frame.max[1] - frame.min[1],
               dz = frame.max[2] - frame.min[2];
  if (!(dx > 0 || dy > 0))
    return; // one point, or a vertical segment: nothing to frame
  for (int k = 0; k < 3; ++k)
    centre_[k] = frame.min[k] + 0.5 * (frame.max[k] - frame.min[k]);
  z_min_ = frame.min[2];
  z_max_ = frame.max[2];
  if (std::isfinite(options.z_scale) && options.z_scale > 0)
    z_scale_ = options.z_scale;
  else if (dz > 0)
    z_scale_ = std::clamp(RELIEF_SHARE * std::max(dx, dy) / dz, 1.0, MAX_AUTO_Z_SCALE);

  // Extent of the frame box in view coordinates: its 8 corners.
  double u0 = HUGE_VAL, u1 = -HUGE_VAL, v0 = HUGE_VAL, v1 = -HUGE_VAL;
  for (int corner = 0; corner < 8; ++corner) {
    const double cx = (corner & 1 ? frame.max[0] : frame.min[0]) - centre_[0];
    const double cy = (corner & 2 ? frame.max[1] : frame.min[1]) - centre_[1];
    const double cz = (corner & 4 ? frame.max[2] : frame.min[2]) - centre_[2];
    double u, v, d;
    toView(cx, cy, cz, u, v, d);
    u0 = std::min(u0, u);
    u1 = std::max(u1, u);
    v0 = std::min(v0, v);
    v1 = std::max(v1, v);
  }
  width_ = std::clamp(options.width, MIN_PICTURE_WIDTH, MAX_PICTURE_WIDTH);
  const int margin = marginFor(width_);
  caption_height_ = captionBandHeight(options.caption, width_);
  const double inner_width = width_ - 2.0 * margin;
  const double max_inner_height = MAX_ASPECT * width_ - 2.0 * margin;
  scale_ = inner_width / std::max(u1 - u0, 1e-300);
  if (v1 - v0 > 0)
    scale_ = std::min(scale_, max_inner_height / (v1 - v0));
  if (!std::isfinite(scale_) || scale_ <= 0)
    return;
  height_ = caption_height_ + 2 * margin +
            std::max(1, static_cast<int>(std::ceil((v1 - v0) * scale_)));
  u_mid_ = 0.5 * (u0 + u1);
  v_mid_ = 0.5 * (v0 + v1);
  column_mid_ = 0.5 * width_;
  row_mid_ = caption_height_ + 0.5 * (height_ - caption_height_);
  valid_ = true;
}

void PictureCamera::toView(double dx, double dy, double dz, double& u, double& v,
                           double& d) const
{
  if (view_ == PictureView::TOP) {
    u = dx;
    v = dy;
    d = -dz; // higher is nearer
    return;
  }
  // From the south-west looking north-east: right is south-east, forward north-east.
  static const double c = std::cos(ELEVATION_DEGREES * M_PI / 180.0);
  static const double s = std::sin(ELEVATION_DEGREES * M_PI / 180.0);
  const double right = (dx - dy) * M_SQRT1_2;
  const double forward = (dx + dy) * M_SQRT1_2;
  const double up = dz * z_scale_;
  u = right;
  v = forward * s + up * c;
  d = forward * c - up * s;
}

ScreenPoint PictureCamera::project(double x, double y, double z) const
{
  double u, v, d;
  toView(x - centre_[0], y - centre_[1], z - centre_[2], u, v, d);
  return {column_mid_ + (u - u_mid_) * scale_, row_mid_ - (v - v_mid_) * scale_,
          d * scale_};
}

} // namespace picture_detail
} // namespace pcl_vts
