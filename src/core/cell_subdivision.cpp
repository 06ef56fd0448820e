#include "grid_internals.h"

#include <pcl_vts/core/cell_subdivision.h>

#include <algorithm>
#include <limits>
#include <numeric>

namespace pcl_vts {
namespace {

// A recursion guard: shrink-then-split halves a box per level, so reaching this
// needs point sets with a dynamic range beyond 2^200 inside one cell.
constexpr int MAX_DEPTH = 200;

struct Builder {
  const Point2* pts;
  std::uint32_t* slots; // slot permutation being built: slot k is slots[k - offset]
  std::uint32_t offset;
  std::vector<SubCell>& nodes;

  /// Shrinks node `id` to the bounding box of its points, then splits it at the box
  /// centre until leaves are small. Shrinking first skips the empty levels a plain
  /// quadtree would need below a far outlier (the extent can span 1e30 while a
  /// cluster spans metres), so the depth follows the points, not the coordinates.
  void split(std::uint32_t id, int depth)
  {
    SubCell node = nodes[id];
    node.x0 = node.y0 = std::numeric_limits<double>::infinity();
    node.x1 = node.y1 = -node.x0;
    for (std::uint32_t k = node.begin; k < node.end; ++k) {
      const Point2& p = pts[slots[k - offset]];
      node.x0 = std::min(node.x0, p.x);
      node.x1 = std::max(node.x1, p.x);
      node.y0 = std::min(node.y0, p.y);
      node.y1 = std::max(node.y1, p.y);
    }
    nodes[id] = node;
    if (node.end - node.begin <= CROWDED_CELL_POINTS || depth >= MAX_DEPTH)
      return;
    const double mx = node.x0 + 0.5 * (node.x1 - node.x0);
    const double my = node.y0 + 0.5 * (node.y1 - node.y0);
    // Partition by y, then each half by x: children in order SW, SE, NW, NE.
    const auto first = slots + (node.begin - offset),
               last = slots + (node.end - offset);
    const auto south = [&](std::uint32_t s) { return pts[s].y < my; };
    const auto west = [&](std::uint32_t s) { return pts[s].x < mx; };
    const auto mid_y = std::partition(first, last, south);
    const auto mid_sw = std::partition(first, mid_y, west);
    const auto mid_nw = std::partition(mid_y, last, west);
    const auto at = [&](auto it) {
      return static_cast<std::uint32_t>(it - slots) + offset;
    };
    const std::uint32_t cut[5] = {node.begin, at(mid_sw), at(mid_y), at(mid_nw),
                                  node.end};
    for (int c = 0; c < 4; ++c)
      if (cut[c] == node.begin && cut[c + 1] == node.end)
        return; // no progress: the box is a few ulps wide; keep a leaf
    const auto child0 = static_cast<std::uint32_t>(nodes.size());
    nodes[id].first_child = child0;
    for (int c = 0; c < 4; ++c)
      nodes.push_back(
          {node.x0, node.y0, node.x1, node.y1, cut[c], cut[c + 1], INVALID_ID});
    for (std::uint32_t c = child0; c < child0 + 4; ++c)
      if (nodes[c].end > nodes[c].begin)
        split(c, depth + 1);
  }
};

} // namespace

namespace detail {

void subdivideCell(const CellGrid& grid, std::uint32_t i, std::uint32_t j,
                   const Point2* points, std::uint32_t* slots, std::uint32_t offset,
                   std::uint32_t begin, std::uint32_t end, std::vector<SubCell>& nodes)
{
  const auto root = static_cast<std::uint32_t>(nodes.size());
  nodes.push_back({grid.origin_x + grid.cell_size * i,
                   grid.origin_y + grid.cell_size * j,
                   grid.origin_x + grid.cell_size * (i + 1),
                   grid.origin_y + grid.cell_size * (j + 1), begin, end, INVALID_ID});
  Builder{points, slots, offset, nodes}.split(root, 0);
}

} // namespace detail

void subdivideCrowdedCells(CellGrid& grid, CellSubdivision& sub,
                           std::vector<std::uint32_t>& old_slot)
{
  sub.nodes.clear();
  sub.root.clear();
  old_slot.clear();
  bool crowded = false;
  for (std::size_t c = 0; c < grid.cellCount() && !crowded; ++c)
    crowded = grid.cell_start[c + 1] - grid.cell_start[c] > CROWDED_CELL_POINTS;
  if (!crowded)
    return;
  sub.root.assign(grid.cellCount(), INVALID_ID);
  old_slot.resize(grid.points.size());
  std::iota(old_slot.begin(), old_slot.end(), 0u);
  for (std::uint32_t j = 0; j < grid.ny; ++j)
    for (std::uint32_t i = 0; i < grid.nx; ++i) {
      const CellId c = grid.cellId(i, j);
      const std::uint32_t begin = grid.cell_start[c], end = grid.cell_start[c + 1];
      if (end - begin <= CROWDED_CELL_POINTS)
        continue;
      sub.root[c] = static_cast<std::uint32_t>(sub.nodes.size());
      detail::subdivideCell(grid, i, j, grid.points.data(), old_slot.data(), 0, begin,
                            end, sub.nodes);
    }
  std::vector<Point2> reordered(grid.points.size());
  for (std::size_t k = 0; k < reordered.size(); ++k)
    reordered[k] = grid.points[old_slot[k]];
  grid.points.swap(reordered);
}

} // namespace pcl_vts
