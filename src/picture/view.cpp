// Frame arithmetic of view.h: the world boxes renderMesh and its camera frame.
#include <pcl_vts/picture/view.h>

#include <algorithm>
#include <cmath>

namespace pcl_vts {

bool isEmpty(const PictureFrame& frame)
{
  for (int k = 0; k < 3; ++k)
    if (!(frame.min[k] <= frame.max[k]) || !std::isfinite(frame.min[k]) ||
        !std::isfinite(frame.max[k]))
      return true;
  return false;
}

PictureFrame unionOf(const PictureFrame& a, const PictureFrame& b)
{
  if (isEmpty(a))
    return b;
  if (isEmpty(b))
    return a;
  PictureFrame u = a;
  for (int d = 0; d < 3; ++d) {
    u.min[d] = std::min(a.min[d], b.min[d]);
    u.max[d] = std::max(a.max[d], b.max[d]);
  }
  return u;
}

} // namespace pcl_vts
