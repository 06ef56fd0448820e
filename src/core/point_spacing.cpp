// Point spacing: median incident edge per vertex, then a one-ring median.
#include <pcl_vts/core/point_spacing.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl_vts {

namespace {

/// Upper median of values, reordering them (0 when empty).
double medianInPlace(std::vector<double>& values)
{
  if (values.empty())
    return 0.0;
  if (values.size() <= 16) { // a vertex ring: insertion sort beats selection
    for (std::size_t k = 1; k < values.size(); ++k) {
      const double v = values[k];
      std::size_t m = k;
      for (; m > 0 && values[m - 1] > v; --m)
        values[m] = values[m - 1];
      values[m] = v;
    }
    return values[values.size() / 2];
  }
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

} // namespace

double medianOf(std::vector<double> values)
{
  return medianInPlace(values);
}

PointSpacing measurePointSpacing(const TriangleMesh& mesh,
                                 const std::vector<bool>* local_for)
{
  const std::size_t n = mesh.vertexCount();
  PointSpacing spacing;

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
  // Per vertex: median incident edge length. Robust to a few long edges into a
  // void (a rim vertex keeps most of its short ones) and to anisotropic sampling
  // (scan lines: the shortest edge would only see the along-line spacing).
  std::vector<double> own(n, 0.0);
  std::vector<double> values;
  std::vector<double> used;
  for (VertexId v = 0; v < n; ++v) {
    if (start[v] == start[v + 1])
      continue;
    values.clear();
    for (std::size_t k = start[v]; k < start[v + 1]; ++k) {
      const Point2& p = mesh.xy[v];
      const Point2& q = mesh.xy[ring[k]];
      const double dx = p.x - q.x, dy = p.y - q.y;
      values.push_back(std::sqrt(dx * dx + dy * dy)); // hypot is 5x slower
    }
    own[v] = medianInPlace(values); // reused buffer: no copy per vertex
    used.push_back(own[v]);
  }
  spacing.global_median = medianInPlace(used);
  spacing.local.assign(n, 0.0);
  for (VertexId v = 0; v < n; ++v) {
    if (start[v] == start[v + 1] || (local_for != nullptr && !(*local_for)[v]))
      continue;
    values.assign(1, own[v]);
    for (std::size_t k = start[v]; k < start[v + 1]; ++k)
      values.push_back(own[ring[k]]);
    spacing.local[v] = medianInPlace(values);
  }
  return spacing;
}

} // namespace pcl_vts
