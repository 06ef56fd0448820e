#include <pcl_vts/core/grid_triangulator.h>

#include <string>

namespace pcl_vts {
namespace {

/// The growing triangulation: flat arrays plus, per vertex, the list of its outgoing
/// open halfedges (those still waiting for the triangle on their right).
class RegionGrowth {
 public:
  RegionGrowth(std::size_t vertices, std::size_t expected_triangles,
               std::vector<VertexId>& triangles, std::vector<HalfedgeId>& halfedges)
      : triangles_(triangles)
      , halfedges_(halfedges)
      , open_head_(vertices, INVALID_ID)
  {
    triangles_.clear();
    halfedges_.clear();
    triangles_.reserve(3 * expected_triangles);
    halfedges_.reserve(3 * expected_triangles);
    open_next_.reserve(3 * expected_triangles);
  }

  HalfedgeId addTriangle(VertexId v0, VertexId v1, VertexId v2)
  {
    const auto e = static_cast<HalfedgeId>(triangles_.size());
    for (VertexId v : {v0, v1, v2}) {
      triangles_.push_back(v);
      halfedges_.push_back(INVALID_ID);
      open_next_.push_back(INVALID_ID);
    }
    return e;
  }

  VertexId origin(HalfedgeId e) const { return triangles_[e]; }
  VertexId target(HalfedgeId e) const { return triangles_[nextHalfedge(e)]; }
  bool hasTwin(HalfedgeId e) const { return halfedges_[e] != INVALID_ID; }

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
    HalfedgeId prev = INVALID_ID;
    for (HalfedgeId h = open_head_[to]; h != INVALID_ID; prev = h, h = open_next_[h])
      if (target(h) == from) {
        unlink(to, prev, h);
        link(e, h);
        return false;
      }
    open_next_[e] = open_head_[from];
    open_head_[from] = e;
    return true;
  }

  void close(HalfedgeId e)
  {
    const VertexId from = origin(e);
    HalfedgeId prev = INVALID_ID;
    for (HalfedgeId h = open_head_[from]; h != INVALID_ID; prev = h, h = open_next_[h])
      if (h == e) {
        unlink(from, prev, h);
        return;
      }
  }

 private:
  void unlink(VertexId v, HalfedgeId prev, HalfedgeId h)
  {
    if (prev == INVALID_ID)
      open_head_[v] = open_next_[h];
    else
      open_next_[prev] = open_next_[h];
  }

  std::vector<VertexId>& triangles_;
  std::vector<HalfedgeId>& halfedges_;
  std::vector<HalfedgeId> open_head_;
  std::vector<HalfedgeId> open_next_;
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
  stats = search.stats();
  if (triangles.size() != 3 * expected)
    return Status::error(
        StatusCode::INTERNAL_ERROR,
        "region growing produced " + std::to_string(triangles.size() / 3) +
            " triangles, expected 2n - h - 2 = " + std::to_string(expected));
  return Status::success();
}

} // namespace pcl_vts
