#include <pcl_vts/core/convex_hull.h>
#include <pcl_vts/core/predicates.h>

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>
#include <string>

namespace pcl_vts {
namespace {

/// Extreme points in 8 directions, in counter-clockwise order (W, SW, S, SE, E, NE,
/// N, NW). They are input points, so their polygon lies inside the hull.
/// `inner` (x0, x1, y0, y1): a box whose open interior lies strictly inside the
/// quadrilateral of the SW, SE, NE and NW extremes, so strictly inside the octagon
/// (empty when x0 >= x1 or y0 >= y1): the bottom edge SW-SE spans x0 < x < x1 below
/// y0, and so on around.
std::vector<VertexId> extremeOctagon(const std::vector<Point2>& p,
                                     const std::vector<VertexId>& ids,
                                     std::array<double, 4>& inner)
{
  std::array<VertexId, 8> ext{};
  std::array<double, 8> best{};
  best.fill(-std::numeric_limits<double>::infinity());
  const auto score = [](const Point2& q, std::size_t d) {
    switch (d) {
    case 0:
      return -q.x;
    case 1:
      return -(q.x + q.y);
    case 2:
      return -q.y;
    case 3:
      return q.x - q.y;
    case 4:
      return q.x;
    case 5:
      return q.x + q.y;
    case 6:
      return q.y;
    default:
      return q.y - q.x;
    }
  };
  for (const VertexId v : ids)
    for (std::size_t d = 0; d < 8; ++d) {
      const double s = score(p[v], d);
      if (s > best[d]) {
        best[d] = s;
        ext[d] = v;
      }
    }
  const Point2 &sw = p[ext[1]], &se = p[ext[3]], &ne = p[ext[5]], &nw = p[ext[7]];
  inner = {std::max(sw.x, nw.x), std::min(se.x, ne.x), std::max(sw.y, se.y),
           std::min(nw.y, ne.y)};
  std::vector<VertexId> poly;
  for (VertexId v : ext)
    if (poly.empty() || (v != poly.back() && v != poly.front()))
      poly.push_back(v);
  return poly;
}

/// True when q lies strictly inside the polygon (strictly left of every edge).
bool strictlyInside(const std::vector<Point2>& p, const std::vector<VertexId>& poly,
                    const Point2& q)
{
  for (std::size_t k = 0; k < poly.size(); ++k)
    if (orient2d(p[poly[k]], p[poly[(k + 1) % poly.size()]], q) != Sign::POSITIVE)
      return false;
  return true;
}

} // namespace

std::vector<VertexId> gridHullCandidates(const CellGrid& grid,
                                         const CellPyramid* pyramid)
{
  // A cell with filled cells two or more steps away on both sides in its row (at
  // columns i - a and i + b, a, b >= 2) and in its column (rows j - c and j + d) lies
  // strictly inside the quadrilateral of any four points of those cells: the edge from
  // the left point (x < i - 1, y >= j) to the lower one (i <= x < i + 1, y < j - 1)
  // crosses x = i below y = j (the left point weighs less than 1/2 there), and so on
  // around; so its points can be neither hull vertices nor on hull edges. Only the
  // cells near the ends of their row or column remain: about the perimeter's cells.
  // Each row's first and last filled cells are found from the row's ends, each
  // column's from the bottom and top rows over the columns not found yet, and only the
  // cells within one step of those ends are read: about the perimeter's cells, not
  // every cell (the same cells, in the same row-major order, as a test of every cell).
  // The ends are found 64 cells at a time in the occupancy bits (the pyramid's level
  // 0): clustered input has long empty runs at the ends of its rows and columns.
  const std::uint32_t nx = grid.nx, ny = grid.ny;
  CellPyramid own;
  if (pyramid == nullptr) {
    buildCellPyramid(grid, own);
    pyramid = &own;
  }
  const CellPyramid::Level& bits = pyramid->levels[0];
  const std::size_t words = bits.row_words;
  const auto rowBits = [&bits, words](std::uint32_t j) {
    return &bits.occupied[j * words];
  };
  std::vector<std::uint32_t> row_first(ny, nx), row_last(ny, 0), column_first(nx, ny),
      column_last(nx, 0);
  for (std::uint32_t j = 0; j < ny; ++j) {
    const std::uint64_t* row = rowBits(j);
    std::size_t k = 0;
    while (k < words && row[k] == 0)
      ++k;
    if (k == words)
      continue; // an empty row
    row_first[j] = static_cast<std::uint32_t>(
        64 * k + static_cast<unsigned>(__builtin_ctzll(row[k])));
    k = words - 1;
    while (row[k] == 0)
      --k;
    row_last[j] = static_cast<std::uint32_t>(
        64 * k + 63 - static_cast<unsigned>(__builtin_clzll(row[k])));
  }
  // The columns whose end is not found yet, a bit each (bits past nx are 0 in rows).
  std::vector<std::uint64_t> open(words);
  for (int from_top = 0; from_top < 2; ++from_top) {
    std::fill(open.begin(), open.end(), ~std::uint64_t{0});
    std::size_t left = nx;
    std::vector<std::uint32_t>& end = from_top != 0 ? column_last : column_first;
    for (std::uint32_t step = 0; step < ny && left > 0; ++step) {
      const std::uint32_t j = from_top != 0 ? ny - 1 - step : step;
      const std::uint64_t* row = rowBits(j);
      for (std::size_t k = 0; k < words; ++k) {
        std::uint64_t found = open[k] & row[k];
        open[k] &= ~found;
        for (; found != 0; found &= found - 1, --left)
          end[64 * k + static_cast<unsigned>(__builtin_ctzll(found))] = j;
      }
    }
  }
  // The columns whose first or last two rows include row j, listed per row.
  std::vector<std::uint32_t> row_start(static_cast<std::size_t>(ny) + 1, 0);
  const auto forEachEndRow = [&](std::uint32_t i, const auto& visit) {
    if (column_first[i] == ny)
      return; // an empty column
    const std::uint32_t f = column_first[i], l = column_last[i];
    visit(f);
    if (f + 1 <= l)
      visit(f + 1);
    if (l > f + 1)
      visit(l);
    if (l > f + 2)
      visit(l - 1);
  };
  for (std::uint32_t i = 0; i < nx; ++i)
    forEachEndRow(i, [&](std::uint32_t j) { ++row_start[j + 1]; });
  for (std::uint32_t j = 0; j < ny; ++j)
    row_start[j + 1] += row_start[j];
  std::vector<std::uint32_t> end_columns(row_start[ny]);
  {
    std::vector<std::uint32_t> at(row_start.begin(), row_start.end() - 1);
    for (std::uint32_t i = 0; i < nx; ++i) // ascending columns in each row's list
      forEachEndRow(i, [&](std::uint32_t j) { end_columns[at[j]++] = i; });
  }
  std::vector<VertexId> candidates;
  std::vector<std::uint32_t> columns;
  for (std::uint32_t j = 0; j < ny; ++j) {
    if (row_first[j] == nx)
      continue;
    // The row's two first and two last cells, and the column ends: the row's only
    // candidate cells (a filled cell lies between its row's and its column's ends).
    columns.assign(end_columns.begin() + row_start[j],
                   end_columns.begin() + row_start[j + 1]);
    const std::uint32_t f = row_first[j], l = row_last[j];
    for (const std::uint32_t i : {f, f + 1, l - 1, l})
      if (i >= f && i <= l)
        columns.push_back(i);
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    for (const std::uint32_t i : columns) {
      const CellId c = grid.cellId(i, j);
      for (std::uint32_t k = grid.cell_start[c]; k < grid.cell_start[c + 1]; ++k)
        candidates.push_back(k);
    }
  }
  return candidates;
}

Status convexHull(const std::vector<Point2>& points, std::vector<VertexId>& hull,
                  const std::vector<VertexId>* candidate_ids)
{
  hull.clear();
  const std::size_t n = points.size();
  if (n < 3)
    return Status::error(StatusCode::TOO_FEW_POINTS,
                         "need at least 3 distinct XY positions, got " +
                             std::to_string(n));
  std::vector<VertexId> all;
  if (candidate_ids == nullptr) {
    all.resize(n);
    std::iota(all.begin(), all.end(), 0u);
    candidate_ids = &all;
  }
  // Collinear input has no hull polygon: detect it before the chain would double back.
  // The candidates decide it: the lexicographic extremes are hull vertices, and a hull
  // with area has a vertex off the line through them.
  const std::vector<VertexId>& ids = *candidate_ids;
  if (ids.empty())
    return Status::error(StatusCode::INVALID_PARAMETER, "no hull candidates given");
  VertexId lo = ids.front(), hi = ids.front();
  for (const VertexId v : ids) {
    if (lexLess(points[v], points[lo]))
      lo = v;
    if (lexLess(points[hi], points[v]))
      hi = v;
  }
  bool has_area = false;
  for (std::size_t k = 0; k < ids.size() && !has_area; ++k)
    has_area = orient2d(points[lo], points[hi], points[ids[k]]) != Sign::ZERO;
  if (!has_area)
    return Status::error(StatusCode::ALL_COLLINEAR,
                         "all " + std::to_string(n) +
                             " distinct XY positions lie on one line; a surface "
                             "needs points off that line");

  std::vector<VertexId> candidates;
  std::array<double, 4> inner{};
  const std::vector<VertexId> octagon = extremeOctagon(points, *candidate_ids, inner);
  const bool filter = octagon.size() >= 3;
  // Most candidates of a small grid are inside: the box (plain comparisons) first.
  const auto inBox = [&inner](const Point2& q) {
    return q.x > inner[0] && q.x < inner[1] && q.y > inner[2] && q.y < inner[3];
  };
  for (const VertexId v : *candidate_ids)
    if (!filter || (!inBox(points[v]) && !strictlyInside(points, octagon, points[v])))
      candidates.push_back(v);
  std::sort(candidates.begin(), candidates.end(), [&points](VertexId a, VertexId b) {
    return lexLess(points[a], points[b]);
  });

  // Andrew's monotone chain, popping only on a strict right turn so that points on a
  // hull edge stay.
  std::vector<VertexId> chain;
  const auto build = [&](auto first, auto last) {
    const std::size_t base = chain.size();
    for (auto it = first; it != last; ++it) {
      while (chain.size() >= base + 2 &&
             orient2d(points[chain[chain.size() - 2]], points[chain.back()],
                      points[*it]) == Sign::NEGATIVE)
        chain.pop_back();
      chain.push_back(*it);
    }
    chain.pop_back(); // the last point starts the other chain
  };
  build(candidates.begin(), candidates.end());
  build(candidates.rbegin(), candidates.rend());
  hull = std::move(chain);
  return Status::success();
}

} // namespace pcl_vts
