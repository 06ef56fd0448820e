// Twin matching for TriangleMesh: each halfedge is keyed by its unordered vertex
// pair, keys are sorted, and each run of equal keys must be one halfedge (boundary)
// or two running in opposite directions (interior). O(E log E), no hash map.
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
  // (unordered vertex pair, halfedge): sorting groups every use of an edge.
  std::vector<std::pair<std::uint64_t, HalfedgeId>> keys;
  keys.reserve(count);
  bool manifold = true;
  for (std::size_t i = 0; i < count; ++i) {
    const auto e = static_cast<HalfedgeId>(i);
    const VertexId from = triangles[e];
    const VertexId to = triangles[nextHalfedge(e)];
    if (from == to)
      manifold = false;
    const std::uint64_t lo = std::min(from, to);
    const std::uint64_t hi = std::max(from, to);
    keys.emplace_back((lo << 32) | hi, e);
  }
  std::sort(keys.begin(), keys.end());
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j].first == keys[i].first)
      ++j;
    if (j - i == 2) {
      const HalfedgeId a = keys[i].second;
      const HalfedgeId b = keys[i + 1].second;
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
  return manifold;
}

} // namespace pcl_vts
