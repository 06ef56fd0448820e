// Twin matching for TriangleMesh: each halfedge is filed under its smaller vertex
// (a counting sort), each vertex's short row sorted by the other vertex, and each run
// of equal pairs must be one halfedge (boundary) or two running in opposite directions
// (interior). Linear but for the rows' sorts; no hash map.
#include <pcl_vts/core/mesh_arrays.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace pcl_vts {

bool TriangleMesh::rebuildHalfedges()
{
  const std::size_t count = triangles.size();
  halfedges.assign(count, INVALID_ID);
  bool manifold = true;
  VertexId top = 0;
  for (const VertexId v : triangles)
    top = std::max(top, v);
  // Halfedges in rows by their smaller vertex (a counting sort, linear): every use of
  // an edge lands in one short row, sorted there by the other vertex.
  std::vector<std::size_t> start(static_cast<std::size_t>(top) + 2, 0);
  for (std::size_t i = 0; i < count; ++i) {
    const auto e = static_cast<HalfedgeId>(i);
    const VertexId from = triangles[e], to = triangles[nextHalfedge(e)];
    if (from == to)
      manifold = false;
    ++start[std::min(from, to) + std::size_t{1}];
  }
  for (std::size_t v = 1; v < start.size(); ++v)
    start[v] += start[v - 1];
  std::vector<std::pair<VertexId, HalfedgeId>> rows(count); // (larger vertex, halfedge)
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < count; ++i) {
    const auto e = static_cast<HalfedgeId>(i);
    const VertexId from = triangles[e], to = triangles[nextHalfedge(e)];
    rows[next[std::min(from, to)]++] = {std::max(from, to), e};
  }
  for (std::size_t v = 0; v + 1 < start.size(); ++v) {
    const auto first = rows.begin() + static_cast<std::ptrdiff_t>(start[v]);
    const auto last = rows.begin() + static_cast<std::ptrdiff_t>(start[v + 1]);
    std::sort(first, last);
    for (auto i = first; i != last;) {
      auto j = i + 1;
      while (j != last && j->first == i->first)
        ++j;
      if (j - i == 2) {
        const HalfedgeId a = i->second, b = (i + 1)->second;
        if (triangles[a] != triangles[b]) {
          halfedges[a] = b;
          halfedges[b] = a;
        } else {
          manifold = false; // the same directed edge twice: an orientation flip
        }
      } else if (j - i > 2) {
        manifold = false;
      }
      i = j;
    }
  }
  return manifold;
}

} // namespace pcl_vts
