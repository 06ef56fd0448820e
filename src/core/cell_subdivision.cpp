#include <pcl_vts/core/cell_subdivision.h>

#include <algorithm>
#include <numeric>

namespace pcl_vts {
namespace {

// Deeper than any split that still separates distinct doubles in one cell.
constexpr int MAX_DEPTH = 60;

struct Builder {
  CellGrid& grid;
  CellSubdivision& sub;
  std::vector<std::uint32_t>& slots; // grid slot permutation being built

  /// Splits node `id` (its range already in place) until leaves are small.
  void split(std::uint32_t id, int depth)
  {
    const SubCell node = sub.nodes[id];
    const double mx = node.x0 + 0.5 * (node.x1 - node.x0);
    const double my = node.y0 + 0.5 * (node.y1 - node.y0);
    if (node.end - node.begin <= CROWDED_CELL_POINTS || depth >= MAX_DEPTH ||
        !(mx > node.x0 && mx < node.x1 && my > node.y0 && my < node.y1))
      return;
    // Partition by y, then each half by x: children in order SW, SE, NW, NE.
    const auto first = slots.begin() + node.begin, last = slots.begin() + node.end;
    const auto& pts = grid.points;
    const auto south = [&](std::uint32_t s) { return pts[s].y < my; };
    const auto west = [&](std::uint32_t s) { return pts[s].x < mx; };
    const auto mid_y = std::partition(first, last, south);
    const auto mid_sw = std::partition(first, mid_y, west);
    const auto mid_nw = std::partition(mid_y, last, west);
    const auto at = [&](auto it) {
      return static_cast<std::uint32_t>(it - slots.begin());
    };
    const auto child0 = static_cast<std::uint32_t>(sub.nodes.size());
    sub.nodes[id].first_child = child0;
    sub.nodes.push_back({node.x0, node.y0, mx, my, node.begin, at(mid_sw), INVALID_ID});
    sub.nodes.push_back({mx, node.y0, node.x1, my, at(mid_sw), at(mid_y), INVALID_ID});
    sub.nodes.push_back({node.x0, my, mx, node.y1, at(mid_y), at(mid_nw), INVALID_ID});
    sub.nodes.push_back({mx, my, node.x1, node.y1, at(mid_nw), node.end, INVALID_ID});
    for (std::uint32_t c = child0; c < child0 + 4; ++c)
      split(c, depth + 1);
  }
};

} // namespace

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
  Builder builder{grid, sub, old_slot};
  for (std::uint32_t j = 0; j < grid.ny; ++j)
    for (std::uint32_t i = 0; i < grid.nx; ++i) {
      const CellId c = grid.cellId(i, j);
      const std::uint32_t begin = grid.cell_start[c], end = grid.cell_start[c + 1];
      if (end - begin <= CROWDED_CELL_POINTS)
        continue;
      sub.root[c] = static_cast<std::uint32_t>(sub.nodes.size());
      sub.nodes.push_back(
          {grid.origin_x + grid.cell_size * i, grid.origin_y + grid.cell_size * j,
           grid.origin_x + grid.cell_size * (i + 1),
           grid.origin_y + grid.cell_size * (j + 1), begin, end, INVALID_ID});
      builder.split(sub.root[c], 0);
    }
  std::vector<Point2> reordered(grid.points.size());
  for (std::size_t k = 0; k < reordered.size(); ++k)
    reordered[k] = grid.points[old_slot[k]];
  grid.points.swap(reordered);
}

} // namespace pcl_vts
