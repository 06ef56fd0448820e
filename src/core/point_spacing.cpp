// Point spacing: shortest incident edge per vertex, then a one-ring median.
#include <pcl_vts/core/point_spacing.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl_vts {

double medianOf(std::vector<double> values)
{
  if (values.empty())
    return 0.0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

PointSpacing measurePointSpacing(const TriangleMesh& mesh)
{
  const std::size_t n = mesh.vertexCount();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> shortest(n, inf);
  // Every undirected edge appears as at least one halfedge; each is seen from both
  // ends, so both vertices get it.
  for (HalfedgeId e = 0; e < mesh.triangles.size(); ++e) {
    const VertexId a = mesh.triangles[e];
    const VertexId b = mesh.triangles[nextHalfedge(e)];
    const double len = std::hypot(mesh.xy[a].x - mesh.xy[b].x, mesh.xy[a].y - mesh.xy[b].y);
    shortest[a] = std::min(shortest[a], len);
    shortest[b] = std::min(shortest[b], len);
  }
  PointSpacing spacing;
  std::vector<double> used;
  for (const double s : shortest)
    if (s < inf)
      used.push_back(s);
  spacing.global_median = medianOf(used);

  // One-ring lists by counting sort of directed edges (both directions).
  std::vector<std::size_t> start(n + 1, 0);
  for (HalfedgeId e = 0; e < mesh.triangles.size(); ++e) {
    ++start[mesh.triangles[e] + 1];
    if (mesh.halfedges[e] == INVALID_ID) // boundary edge: seen from one side only
      ++start[mesh.triangles[nextHalfedge(e)] + 1];
  }
  for (std::size_t v = 0; v < n; ++v)
    start[v + 1] += start[v];
  std::vector<VertexId> ring(start[n]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (HalfedgeId e = 0; e < mesh.triangles.size(); ++e) {
    const VertexId a = mesh.triangles[e];
    const VertexId b = mesh.triangles[nextHalfedge(e)];
    ring[fill[a]++] = b;
    if (mesh.halfedges[e] == INVALID_ID)
      ring[fill[b]++] = a;
  }
  spacing.local.assign(n, 0.0);
  std::vector<double> values;
  for (VertexId v = 0; v < n; ++v) {
    if (shortest[v] == inf)
      continue;
    values.assign(1, shortest[v]);
    for (std::size_t k = start[v]; k < start[v + 1]; ++k)
      values.push_back(shortest[ring[k]]);
    spacing.local[v] = medianOf(values);
  }
  return spacing;
}

} // namespace pcl_vts
