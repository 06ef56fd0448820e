// Known-space queries over the block pyramid (known_space.h).
#include "known_space.h"

#include <pcl_vts/core/predicates.h>

#include <algorithm>
#include <cmath>

namespace pcl_vts {

/// Distance from p to a convex polygon (0 inside); +inf for an empty polygon.
static double distanceToPolygon(const std::vector<Point2>& polygon, const Point2& p)
{
  if (polygon.empty())
    return HUGE_VAL;
  bool inside = polygon.size() >= 3;
  double best = HUGE_VAL;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Point2& a = polygon[i];
    const Point2& b = polygon[(i + 1) % polygon.size()];
    const double ex = b.x - a.x, ey = b.y - a.y;
    if (ex * (p.y - a.y) - ey * (p.x - a.x) < 0)
      inside = false;
    const double length2 = ex * ex + ey * ey;
    double t = length2 > 0 ? ((p.x - a.x) * ex + (p.y - a.y) * ey) / length2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    const double dx = a.x + t * ex - p.x, dy = a.y + t * ey - p.y;
    best = std::min(best, std::sqrt(dx * dx + dy * dy));
  }
  return inside ? 0.0 : best;
}

KnownSpace::KnownSpace(const TileFrame& frame, int level,
                       const std::vector<std::uint64_t>& occupied,
                       const std::vector<Rect>& bounds, const std::vector<Point2>& hull)
    : frame_(frame)
    , level_(level)
    , counts_(static_cast<std::size_t>(level) + 1)
    , bounds_(bounds)
{
  counts_[level].resize(occupied.size());
  for (std::size_t b = 0; b < occupied.size(); ++b)
    counts_[level][b] = occupied[b] != 0;
  // Boxes along the hull: what they keep inside it. The margin (far above the
  // rounding of the clipping, far below any point spacing) keeps points on the hull
  // strictly inside the float polygon.
  const double margin =
      1e-9 * (frame.side + std::fabs(frame.min_x) + std::fabs(frame.min_y));
  for (std::size_t b = 0; b < occupied.size(); ++b)
    if (occupied[b] != 0) {
      ClippedBox c = clipBox(hull, bounds[b], margin);
      if (!c.inside)
        clipped_.emplace(static_cast<std::uint32_t>(b), std::move(c));
    }
  for (int l = level - 1; l >= 0; --l) {
    counts_[l].assign(std::size_t{1} << (2 * l), 0);
    for (std::size_t n = 0; n < counts_[l + 1].size(); ++n)
      counts_[l][n >> 2] += counts_[l + 1][n];
  }
}

template <typename MeetsNode, typename MeetsBlock>
void KnownSpace::collect(int level, std::uint32_t node, const MeetsNode& meets_node,
                         const MeetsBlock& meets_block, const LoadedBlocks& loaded,
                         std::vector<std::uint32_t>& hits) const
{
  if (counts_[level][node] == 0)
    return;
  if (level == level_) {
    if (!loaded[node] && meets_block(node))
      hits.push_back(node);
    return;
  }
  if (!meets_node(frame_.nodeRect(level, node)))
    return;
  for (std::uint32_t k = 0; k < 4; ++k)
    collect(level + 1, (node << 2) | k, meets_node, meets_block, loaded, hits);
}

void KnownSpace::unknownInDisk(const CircumdiskBound& disk, const LoadedBlocks& loaded,
                               std::vector<std::uint32_t>& hits) const
{
  const double r2 = disk.radius * disk.radius;
  const auto meets = [&](const Rect& r) {
    if (disk.unbounded)
      return true;
    const double dx = std::max({r.x0 - disk.center.x, 0.0, disk.center.x - r.x1});
    const double dy = std::max({r.y0 - disk.center.y, 0.0, disk.center.y - r.y1});
    return dx * dx + dy * dy <= r2;
  };
  const auto meets_block = [&](std::uint32_t block) {
    if (!meets(bounds_[block]))
      return false;
    const auto clipped = clipped_.find(block);
    if (clipped == clipped_.end() || disk.unbounded)
      return true;
    return distanceToPolygon(clipped->second.polygon, disk.center) <= disk.radius;
  };
  if (!disk.unbounded) {
    // A small disk: its blocks directly, not by a descent from the root (most disks
    // of a tile's triangles lie inside one block or four). column() is monotone and
    // the slack exceeds the rounding of `meets`, so every block whose box the disk
    // meets is among these; the same blocks as the descent, in its (Morton) order.
    const double slack = 1e-9 * (frame_.side + std::fabs(frame_.min_x) +
                                 std::fabs(frame_.min_y) + disk.radius);
    const double reach = disk.radius + slack;
    const int shift = TileFrame::CODE_LEVEL - level_;
    const std::uint32_t x0 = frame_.column(disk.center.x - reach) >> shift,
                        x1 = frame_.column(disk.center.x + reach) >> shift,
                        y0 = frame_.row(disk.center.y - reach) >> shift,
                        y1 = frame_.row(disk.center.y + reach) >> shift;
    if ((x1 - x0 + 1) * (y1 - y0 + 1) <= 16) {
      const std::size_t before = hits.size();
      const std::vector<std::uint32_t>& blocks = counts_[level_];
      for (std::uint32_t y = y0; y <= y1; ++y)
        for (std::uint32_t x = x0; x <= x1; ++x) {
          const std::uint32_t b = spreadBits(x) | (spreadBits(y) << 1);
          if (blocks[b] != 0 && !loaded[b] && meets_block(b))
            hits.push_back(b);
        }
      std::sort(hits.begin() + static_cast<std::ptrdiff_t>(before), hits.end());
      return;
    }
  }
  collect(0, 0, meets, meets_block, loaded, hits);
}

void KnownSpace::unknownRightOf(const Point2& a, const Point2& b,
                                const LoadedBlocks& loaded,
                                std::vector<std::uint32_t>& hits) const
{
  const double ex = b.x - a.x, ey = b.y - a.y;
  const double length = std::sqrt(ex * ex + ey * ey);
  // Pruning only: a node is skipped when all its (slack-widened) corners are left
  // of the line by far more than the rounding of the cross product.
  const auto meets_node = [&](const Rect& r) {
    const double tolerance = 1e-9 * length *
                             (std::fabs(r.x0 - a.x) + std::fabs(r.x1 - a.x) +
                              std::fabs(r.y0 - a.y) + std::fabs(r.y1 - a.y));
    const double xs[2] = {r.x0, r.x1}, ys[2] = {r.y0, r.y1};
    for (double x : xs)
      for (double y : ys)
        if (ex * (y - a.y) - ey * (x - a.x) < tolerance)
          return true;
    return false;
  };
  // A block's box corners are extreme points: if any of its points is strictly
  // right of the line, a corner is. Decided exactly (collinear points keep the edge).
  const auto meets_block = [&](std::uint32_t block) {
    const auto clipped = clipped_.find(block);
    if (clipped != clipped_.end()) {
      // Exact points spanning the box's part inside the hull.
      for (const Point2& p : clipped->second.spanning)
        if (orient2d(a, b, p) == Sign::NEGATIVE)
          return true;
      return false;
    }
    const Rect& r = bounds_[block];
    const double xs[2] = {r.x0, r.x1}, ys[2] = {r.y0, r.y1};
    for (double x : xs)
      for (double y : ys)
        if (orient2d(a, b, Point2{x, y}) == Sign::NEGATIVE)
          return true;
    return false;
  };
  collect(0, 0, meets_node, meets_block, loaded, hits);
}

} // namespace pcl_vts
