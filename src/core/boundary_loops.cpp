// Boundary loops: one walk per twin-less halfedge not yet visited; components by a
// flood over twins. See boundary_loops.h.
#include "post_pass_spacing.h"

#include <pcl_vts/core/boundary_loops.h>

#include <algorithm>
#include <string>

namespace pcl_vts {

std::size_t BoundaryLoops::holeCount() const
{
  return static_cast<std::size_t>(std::count_if(
      loops.begin(), loops.end(), [](const BoundaryLoop& l) { return !l.is_outer; }));
}

HalfedgeId nextBoundaryHalfedge(const TriangleMesh& mesh, HalfedgeId e)
{
  // e = a->b. Outgoing halfedges of b in e's fan: next(e), next(twin(next(e))), ...
  // The first without twin is the boundary halfedge leaving b on the same fan.
  HalfedgeId f = nextHalfedge(e);
  for (std::size_t steps = 0; steps <= mesh.halfedges.size(); ++steps) {
    const HalfedgeId twin = mesh.halfedges[f];
    if (twin == INVALID_ID)
      return f;
    f = nextHalfedge(twin);
  }
  return INVALID_ID;
}

namespace {

double twiceSignedArea(const TriangleMesh& mesh, const std::vector<VertexId>& cycle)
{
  // Relative to the first vertex: keeps the shoelace sum well conditioned far from
  // the origin (georeferenced coordinates).
  const Point2 o = mesh.xy[cycle.front()];
  double sum = 0.0;
  for (std::size_t i = 0; i < cycle.size(); ++i) {
    const Point2& p = mesh.xy[cycle[i]];
    const Point2& q = mesh.xy[cycle[(i + 1) % cycle.size()]];
    sum += (p.x - o.x) * (q.y - o.y) - (q.x - o.x) * (p.y - o.y);
  }
  return sum;
}

/// Rotates the loop to start at its vertex smallest in (x, y) (of two visits of one
/// vertex, the one followed by the smaller vertex): where a walk starts depends on the
/// halfedge ids, this does not, and the area sum is then the same for any ids.
void startAtSmallestVertex(const TriangleMesh& mesh, BoundaryLoop& loop)
{
  const std::size_t n = loop.vertices.size();
  auto before = [&](std::size_t i, std::size_t j) {
    const Point2& a = mesh.xy[loop.vertices[i]];
    const Point2& b = mesh.xy[loop.vertices[j]];
    if (lexLess(a, b) || lexLess(b, a))
      return lexLess(a, b);
    return lexLess(mesh.xy[loop.vertices[(i + 1) % n]],
                   mesh.xy[loop.vertices[(j + 1) % n]]);
  };
  std::size_t first = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (before(i, first))
      first = i;
  const auto shift = static_cast<std::ptrdiff_t>(first);
  std::rotate(loop.vertices.begin(), loop.vertices.begin() + shift,
              loop.vertices.end());
  std::rotate(loop.halfedges.begin(), loop.halfedges.begin() + shift,
              loop.halfedges.end());
}

void labelComponents(const TriangleMesh& mesh, BoundaryLoops& loops)
{
  const std::size_t count = mesh.triangleCount();
  loops.triangle_component.assign(count, INVALID_ID);
  loops.component_triangles.clear();
  std::vector<TriangleId> stack;
  for (TriangleId seed = 0; seed < count; ++seed) {
    if (loops.triangle_component[seed] != INVALID_ID)
      continue;
    const auto component = static_cast<std::uint32_t>(loops.component_triangles.size());
    std::size_t size = 0;
    loops.triangle_component[seed] = component;
    stack.push_back(seed);
    while (!stack.empty()) {
      const TriangleId t = stack.back();
      stack.pop_back();
      ++size;
      for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e) {
        const HalfedgeId twin = mesh.halfedges[e];
        if (twin == INVALID_ID)
          continue;
        const TriangleId u = triangleOf(twin);
        if (loops.triangle_component[u] == INVALID_ID) {
          loops.triangle_component[u] = component;
          stack.push_back(u);
        }
      }
    }
    loops.component_triangles.push_back(size);
  }
}

} // namespace

Status traceBoundaryLoops(const TriangleMesh& mesh, std::vector<BoundaryLoop>& loops)
{
  return detail::traceBoundaryLoops(mesh, loops, nullptr);
}

Status detail::traceBoundaryLoops(const TriangleMesh& mesh,
                                  std::vector<BoundaryLoop>& loops,
                                  const std::vector<HalfedgeId>* boundary)
{
  loops.clear();
  if (mesh.halfedges.size() != mesh.triangles.size() || mesh.triangles.size() % 3 != 0)
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "halfedges (" + std::to_string(mesh.halfedges.size()) +
                             ") must have one entry per triangle corner (" +
                             std::to_string(mesh.triangles.size()) + ")");
  std::vector<bool> visited; // sized at the first boundary halfedge
  // The boundary halfedges in increasing order: from the list, else by a scan.
  const std::size_t starts =
      boundary != nullptr ? boundary->size() : mesh.halfedges.size();
  for (std::size_t k = 0; k < starts; ++k) {
    const HalfedgeId start =
        boundary != nullptr ? (*boundary)[k] : static_cast<HalfedgeId>(k);
    if (mesh.halfedges[start] != INVALID_ID)
      continue;
    if (visited.empty())
      visited.assign(mesh.halfedges.size(), false);
    if (visited[start])
      continue;
    BoundaryLoop loop;
    HalfedgeId e = start;
    do {
      if (e == INVALID_ID || visited[e])
        return Status::error(StatusCode::INVALID_PARAMETER,
                             "boundary walk from halfedge " + std::to_string(start) +
                                 " does not close: inconsistent twins");
      visited[e] = true;
      loop.halfedges.push_back(e);
      loop.vertices.push_back(mesh.triangles[e]);
      e = nextBoundaryHalfedge(mesh, e);
    } while (e != start);
    startAtSmallestVertex(mesh, loop);
    loop.twice_area = twiceSignedArea(mesh, loop.vertices);
    std::vector<VertexId> sorted = loop.vertices;
    std::sort(sorted.begin(), sorted.end());
    loop.has_repeated_vertex =
        std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
    loops.push_back(std::move(loop));
  }
  return Status::success();
}

Status findBoundaryLoops(const TriangleMesh& mesh, BoundaryLoops& loops)
{
  loops = BoundaryLoops{};
  if (Status s = traceBoundaryLoops(mesh, loops.loops); !s.ok())
    return s;
  labelComponents(mesh, loops);
  for (BoundaryLoop& loop : loops.loops)
    loop.component = loops.triangle_component[triangleOf(loop.halfedges.front())];

  // The outer loop of a piece encloses all its other loops, so it has the largest
  // signed area (the only positive one in exact arithmetic).
  std::vector<std::size_t> best(loops.componentCount(), INVALID_ID);
  for (std::size_t i = 0; i < loops.loops.size(); ++i) {
    std::size_t& b = best[loops.loops[i].component];
    if (b == INVALID_ID || loops.loops[i].twice_area > loops.loops[b].twice_area)
      b = i;
  }
  for (const std::size_t b : best)
    if (b != INVALID_ID)
      loops.loops[b].is_outer = true;
  return Status::success();
}

} // namespace pcl_vts
