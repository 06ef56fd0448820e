// Edge and orientation counts (mesh_topology.h): edges as sorted 64-bit keys, so the
// count is a sort and one pass, linear memory.
#include "mesh_topology.h"

#include <algorithm>
#include <numeric>

namespace pcl_vts {
namespace compare {

double signedXyArea(const CompareMesh& mesh, std::size_t t)
{
  const double* a = &mesh.xyz[3 * mesh.triangles[3 * t]];
  const double* b = &mesh.xyz[3 * mesh.triangles[3 * t + 1]];
  const double* c = &mesh.xyz[3 * mesh.triangles[3 * t + 2]];
  return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
}

TopologyCounts countTopology(const CompareMesh& mesh)
{
  TopologyCounts counts;
  const std::size_t nt = mesh.triangleCount();
  counts.triangles = nt;
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * nt);
  std::vector<std::uint8_t> used(mesh.vertexCount(), 0);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = mesh.triangles[3 * t + k];
      const std::uint64_t b = mesh.triangles[3 * t + (k + 1) % 3];
      used[a] = 1;
      if (a != b)
        edges.push_back(std::min(a, b) << 32 | std::max(a, b));
    }
    const double area = signedXyArea(mesh, t);
    if (area < 0.0)
      ++counts.flipped;
    else if (area == 0.0)
      ++counts.vertical;
  }
  counts.vertices_used =
      static_cast<std::size_t>(std::count(used.begin(), used.end(), 1));
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i])
      ++j;
    const auto a = static_cast<std::uint32_t>(edges[i] >> 32);
    const auto b = static_cast<std::uint32_t>(edges[i] & 0xffffffffu);
    if (j - i == 1) {
      ++counts.boundary_edges;
      counts.boundary_edge_list.insert(counts.boundary_edge_list.end(), {a, b});
    } else if (j - i > 2) {
      ++counts.non_manifold_edges;
      counts.non_manifold_edge_list.insert(counts.non_manifold_edge_list.end(), {a, b});
    }
    i = j;
  }
  return counts;
}

long long countUnusedPoints(const CompareMesh& mesh, const PointSet& input)
{
  const std::size_t n = input.size();
  if (mesh.source.empty() || std::none_of(mesh.source.begin(), mesh.source.end(),
                                          [](std::int32_t s) { return s >= 0; }))
    return -1;
  std::vector<std::uint8_t> used(n, 0);
  for (std::uint32_t v : mesh.triangles) {
    const std::int32_t s = mesh.source[v];
    if (s >= 0 && static_cast<std::size_t>(s) < n)
      used[static_cast<std::size_t>(s)] = 1;
  }
  // Groups of exactly equal XY: a group is used when any member is.
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  const double* xyz = input.xyz.data();
  std::sort(order.begin(), order.end(), [xyz](std::uint32_t a, std::uint32_t b) {
    return xyz[3 * a] < xyz[3 * b] ||
           (xyz[3 * a] == xyz[3 * b] && xyz[3 * a + 1] < xyz[3 * b + 1]);
  });
  long long unused = 0;
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    bool any = used[order[i]] != 0;
    while (j < n && xyz[3 * order[j]] == xyz[3 * order[i]] &&
           xyz[3 * order[j] + 1] == xyz[3 * order[i] + 1]) {
      any = any || used[order[j]] != 0;
      ++j;
    }
    if (!any)
      unused += static_cast<long long>(j - i);
    i = j;
  }
  return unused;
}

} // namespace compare
} // namespace pcl_vts
