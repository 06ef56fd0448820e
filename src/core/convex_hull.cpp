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
std::vector<VertexId> extremeOctagon(const std::vector<Point2>& p,
                                     const std::vector<VertexId>& ids)
{
  std::array<VertexId, 8> ext{};
  std::array<double, 8> best{};
  best.fill(-std::numeric_limits<double>::infinity());
  const auto score = [](const Point2& q, int d) {
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
    for (int d = 0; d < 8; ++d) {
      const double s = score(p[v], d);
      if (s > best[d]) {
        best[d] = s;
        ext[d] = v;
      }
    }
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

std::vector<VertexId> gridHullCandidates(const CellGrid& grid)
{
  // A cell whose four cells two steps away (left, right, below, above) all hold points
  // lies strictly inside the diamond of those points (margin: one cell), so its
  // points can be neither hull vertices nor on hull edges.
  const auto filled = [&grid](long i, long j) {
    if (i < 0 || j < 0 || i >= static_cast<long>(grid.nx) ||
        j >= static_cast<long>(grid.ny))
      return false;
    const CellId c =
        grid.cellId(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
    return grid.cell_start[c + 1] > grid.cell_start[c];
  };
  std::vector<VertexId> candidates;
  for (long j = 0; j < static_cast<long>(grid.ny); ++j)
    for (long i = 0; i < static_cast<long>(grid.nx); ++i) {
      if (filled(i - 2, j) && filled(i + 2, j) && filled(i, j - 2) && filled(i, j + 2))
        continue;
      const CellId c =
          grid.cellId(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
      for (std::uint32_t k = grid.cell_start[c]; k < grid.cell_start[c + 1]; ++k)
        candidates.push_back(k);
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
  // Collinear input has no hull polygon: detect it before the chain would double back.
  VertexId lo = 0, hi = 0;
  for (VertexId v = 1; v < n; ++v) {
    if (lexLess(points[v], points[lo]))
      lo = v;
    if (lexLess(points[hi], points[v]))
      hi = v;
  }
  bool has_area = false;
  for (VertexId v = 0; v < n && !has_area; ++v)
    has_area = orient2d(points[lo], points[hi], points[v]) != Sign::ZERO;
  if (!has_area)
    return Status::error(StatusCode::ALL_COLLINEAR,
                         "all " + std::to_string(n) +
                             " distinct XY positions lie on one line; a surface "
                             "needs points off that line");

  std::vector<VertexId> all;
  if (candidate_ids == nullptr) {
    all.resize(n);
    std::iota(all.begin(), all.end(), 0u);
    candidate_ids = &all;
  }
  std::vector<VertexId> candidates;
  const std::vector<VertexId> octagon = extremeOctagon(points, *candidate_ids);
  const bool filter = octagon.size() >= 3;
  for (const VertexId v : *candidate_ids)
    if (!filter || !strictlyInside(points, octagon, points[v]))
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
