#include <pcl_vts/core/grid_triangulator.h>

#include <string>

namespace pcl_vts {
namespace {

/// The growing triangulation: flat arrays plus, per vertex, the list of its outgoing
/// open halfedges (those still waiting for the triangle on their right). An open
/// halfedge has no twin yet, so its slot in `halfedges` holds the list link instead,
/// tagged with OPEN: no extra array.
class RegionGrowth {
 public:
  static constexpr HalfedgeId OPEN = 0x80000000u;
  static constexpr HalfedgeId NIL = 0x7ffffffeu; ///< end of an open list
  /// Halfedge ids must stay below NIL.
  static constexpr std::size_t MAX_TRIANGLES = NIL / 3;

  RegionGrowth(std::size_t vertices, std::size_t expected_triangles,
               std::vector<VertexId>& triangles, std::vector<HalfedgeId>& halfedges)
      : triangles_(triangles)
      , halfedges_(halfedges)
      , open_head_(vertices, NIL)
  {
    triangles_.clear();
    halfedges_.clear();
    triangles_.reserve(3 * expected_triangles);
    halfedges_.reserve(3 * expected_triangles);
  }

  HalfedgeId addTriangle(VertexId v0, VertexId v1, VertexId v2)
  {
    const auto e = static_cast<HalfedgeId>(triangles_.size());
    for (VertexId v : {v0, v1, v2}) {
      triangles_.push_back(v);
      halfedges_.push_back(INVALID_ID);
    }
    return e;
  }

  VertexId origin(HalfedgeId e) const { return triangles_[e]; }
  VertexId target(HalfedgeId e) const { return triangles_[nextHalfedge(e)]; }
  bool hasTwin(HalfedgeId e) const { return halfedges_[e] < OPEN; }

  void link(HalfedgeId e, HalfedgeId f)
  {
    halfedges_[e] = f;
    halfedges_[f] = e;
  }

  /// Links e with its open twin if that exists; otherwise e becomes open.
  /// Returns true when e is new open work.
  bool linkOrOpen(HalfedgeId e)
  {
    const VertexId from = origin(e), to = target(e);
    HalfedgeId prev = NIL;
    for (HalfedgeId h = open_head_[to]; h != NIL; prev = h, h = nextOpen(h))
      if (target(h) == from) {
        unlink(to, prev, h);
        link(e, h);
        return false;
      }
    halfedges_[e] = OPEN | open_head_[from];
    open_head_[from] = e;
    return true;
  }

  void close(HalfedgeId e)
  {
    const VertexId from = origin(e);
    HalfedgeId prev = NIL;
    for (HalfedgeId h = open_head_[from]; h != NIL; prev = h, h = nextOpen(h))
      if (h == e) {
        unlink(from, prev, h);
        halfedges_[e] = INVALID_ID;
        return;
      }
  }

  /// Halfedges still open at the end lie on the hull: they have no twin.
  void finish()
  {
    for (HalfedgeId& t : halfedges_)
      if (t >= OPEN)
        t = INVALID_ID;
  }

 private:
  HalfedgeId nextOpen(HalfedgeId h) const { return halfedges_[h] & ~OPEN; }

  void unlink(VertexId v, HalfedgeId prev, HalfedgeId h)
  {
    if (prev == NIL)
      open_head_[v] = nextOpen(h);
    else
      halfedges_[prev] = OPEN | nextOpen(h);
  }

  std::vector<VertexId>& triangles_;
  std::vector<HalfedgeId>& halfedges_;
  std::vector<HalfedgeId> open_head_;
};

} // namespace

Status triangulateGrid(const CellGrid& grid, const CellPyramid& pyramid,
                       const CellSubdivision& subdivision,
                       const std::vector<VertexId>& hull,
                       std::vector<VertexId>& triangles,
                       std::vector<HalfedgeId>& halfedges, SearchStats& stats)
{
  const std::size_t n = grid.points.size();
  const std::size_t h = hull.size();
  const std::size_t expected = 2 * n - h - 2;
  if (expected > RegionGrowth::MAX_TRIANGLES)
    return Status::error(StatusCode::INVALID_PARAMETER,
                         std::to_string(n) + " points need " +
                             std::to_string(expected) +
                             " triangles, beyond the 32-bit halfedge range");
  // hull_next[v] = w when v->w is a hull edge (interior on its left).
  std::vector<VertexId> hull_next(n, INVALID_ID);
  for (std::size_t k = 0; k < h; ++k)
    hull_next[hull[k]] = hull[(k + 1) % h];

  MediatrixSearch search(grid, pyramid, subdivision);
  RegionGrowth growth(n, expected, triangles, halfedges);
  std::vector<HalfedgeId> pool;

  // Seed: the first hull edge is Delaunay in every triangulation of the points.
  const VertexId a = hull[0], b = hull[1];
  const VertexId c = search.findThirdPoint(a, b);
  if (c == INVALID_ID)
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "no point found left of the seed hull edge");
  const HalfedgeId seed = growth.addTriangle(a, b, c);
  for (HalfedgeId e : {seed + 1, seed + 2})
    if (growth.linkOrOpen(e))
      pool.push_back(e);

  while (!pool.empty()) {
    const HalfedgeId e = pool.back();
    pool.pop_back();
    if (growth.hasTwin(e))
      continue;
    const VertexId x = growth.origin(e), y = growth.target(e);
    if (hull_next[x] == y)
      continue; // the right side of a hull edge is outside
    const VertexId p = search.findThirdPoint(y, x);
    if (p == INVALID_ID)
      return Status::error(StatusCode::INTERNAL_ERROR,
                           "no Delaunay triangle found across interior edge " +
                               std::to_string(x) + "-" + std::to_string(y));
    growth.close(e);
    const HalfedgeId f = growth.addTriangle(y, x, p);
    growth.link(f, e);
    for (HalfedgeId g : {f + 1, f + 2})
      if (growth.linkOrOpen(g))
        pool.push_back(g);
  }
  growth.finish();
  stats = search.stats();
  if (triangles.size() != 3 * expected)
    return Status::error(
        StatusCode::INTERNAL_ERROR,
        "region growing produced " + std::to_string(triangles.size() / 3) +
            " triangles, expected 2n - h - 2 = " + std::to_string(expected));
  return Status::success();
}

} // namespace pcl_vts
