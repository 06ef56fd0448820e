// Frame arithmetic for the tiled path (tile_frame.h).
#include <pcl_vts/tiling/tile_frame.h>

#include <algorithm>
#include <cmath>

namespace pcl_vts {

std::uint32_t gatherBits(std::uint32_t v)
{
  v &= 0x55555555u;
  v = (v | (v >> 1)) & 0x33333333u;
  v = (v | (v >> 2)) & 0x0F0F0F0Fu;
  v = (v | (v >> 4)) & 0x00FF00FFu;
  v = (v | (v >> 8)) & 0x0000FFFFu;
  return v;
}

TileFrame TileFrame::fromBounds(double min_x, double min_y, double max_x, double max_y)
{
  TileFrame frame;
  frame.min_x = min_x;
  frame.min_y = min_y;
  frame.side = std::max(max_x - min_x, max_y - min_y);
  if (!(frame.side > 0))
    frame.side = 1.0;
  frame.scale = CODE_CELLS / frame.side;
  return frame;
}

Rect TileFrame::nodeRect(int level, std::uint32_t node) const
{
  const int shift = CODE_LEVEL - level;
  const std::uint32_t cells = 1u << shift;
  const double ix = gatherBits(node) * static_cast<double>(cells);
  const double iy = gatherBits(node >> 1) * static_cast<double>(cells);
  const double cell = side / CODE_CELLS;
  // Every point lies in the bounding box, so the clamping in column() moves none
  // outside its node's rectangle.
  // column() rounds (x - min_x) and the product: a relative error of a few ulps of
  // the frame's magnitude. 1e-9 of it is far beyond that and far below a cell.
  const double slack = 1e-9 * (side + std::fabs(min_x) + std::fabs(min_y)) + 1e-300;
  Rect r;
  r.x0 = min_x + ix * cell - slack;
  r.y0 = min_y + iy * cell - slack;
  r.x1 = min_x + (ix + cells) * cell + slack;
  r.y1 = min_y + (iy + cells) * cell + slack;
  return r;
}

} // namespace pcl_vts
