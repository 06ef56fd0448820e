// Outward-triangle removal: static oversize test, flood over oversized triangles
// from the outline and void seeds, then pinch repair by restoring fan gaps.
// See trim_outward_triangles.h.
#include <pcl_vts/core/point_spacing.h>
#include <pcl_vts/core/trim_outward_triangles.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pcl_vts {

Status validateTrimOptions(const TrimOptions& options)
{
  if (!std::isfinite(options.trim_factor) || !(options.trim_factor > 1.0))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "trim_factor = " + formatValue(options.trim_factor) +
                             " must be finite and > 1");
  return checkFiniteNonNegative("max_edge", options.max_edge, " (0 = no limit)");
}

namespace {

/// Original fan of v as a sequence of triangles, starting at an open end if the fan
/// is open. out: any halfedge leaving v.
std::vector<TriangleId> fanOf(const TriangleMesh& mesh, HalfedgeId out, bool& closed)
{
  std::vector<TriangleId> fan;
  // Back to the open end: across the edge entering v.
  HalfedgeId f = out;
  closed = false;
  for (std::size_t steps = 0; steps <= mesh.halfedges.size(); ++steps) {
    const HalfedgeId twin = mesh.halfedges[prevHalfedge(f)];
    if (twin == INVALID_ID)
      break;
    f = twin;
    if (f == out) {
      closed = true;
      break;
    }
  }
  const HalfedgeId start = f;
  for (std::size_t steps = 0; steps <= mesh.halfedges.size(); ++steps) {
    fan.push_back(triangleOf(f));
    const HalfedgeId twin = mesh.halfedges[f];
    if (twin == INVALID_ID)
      break;
    f = nextHalfedge(twin);
    if (f == start)
      break;
  }
  return fan;
}

/// Restores the removed triangles of v's fan that separate two kept runs, all but
/// the largest gap of a closed fan, so that v keeps one fan. Returns the triangles
/// restored.
std::vector<TriangleId> restoreFanGaps(const std::vector<TriangleId>& fan, bool closed,
                                       std::vector<bool>& removed)
{
  std::vector<TriangleId> restored;
  const std::size_t n = fan.size();
  std::size_t first_kept = n;
  for (std::size_t i = 0; i < n && first_kept == n; ++i)
    if (!removed[fan[i]])
      first_kept = i;
  if (first_kept == n)
    return restored; // v lost all its triangles: no pinch
  // Gaps (runs of removed triangles) in order from the first kept triangle.
  struct Gap {
    std::size_t begin, length;
  };
  std::vector<Gap> gaps;
  const std::size_t span = closed ? n : n - first_kept;
  for (std::size_t k = 0; k < span;) {
    const std::size_t i = (first_kept + k) % n;
    if (!removed[fan[i]]) {
      ++k;
      continue;
    }
    Gap gap{k, 0};
    while (k < span && removed[fan[(first_kept + k) % n]]) {
      ++gap.length;
      ++k;
    }
    // In an open fan a gap reaching the end is not between two runs.
    if (closed || k < span)
      gaps.push_back(gap);
  }
  if (closed && gaps.size() <= 1)
    return restored;
  if (!closed && gaps.empty())
    return restored;
  std::size_t keep_open = gaps.size(); // none, for an open fan
  if (closed) {
    keep_open = 0;
    for (std::size_t g = 1; g < gaps.size(); ++g)
      if (gaps[g].length > gaps[keep_open].length)
        keep_open = g;
  }
  for (std::size_t g = 0; g < gaps.size(); ++g) {
    if (g == keep_open)
      continue;
    for (std::size_t k = 0; k < gaps[g].length; ++k) {
      const TriangleId t = fan[(first_kept + gaps[g].begin + k) % n];
      removed[t] = false;
      restored.push_back(t);
    }
  }
  return restored;
}

} // namespace

Status trimOutwardTriangles(TriangleMesh& mesh, const TrimOptions& options,
                            TrimResult& result)
{
  result = TrimResult{};
  Status status = validateTrimOptions(options);
  if (!status.ok())
    return status;
  if (mesh.halfedges.size() != mesh.triangles.size())
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "halfedges must have one entry per triangle corner");
  const std::size_t count = mesh.triangleCount();
  const PointSpacing spacing = measurePointSpacing(mesh);
  result.spacing = spacing.global_median;

  // A data void holds a local maximum of the distance to the nearest point: a
  // Voronoi vertex inside its own Delaunay triangle, i.e. a non-obtuse triangle.
  // Only such triangles open a void from inside; the thin obtuse slivers along a
  // straight hull side are left to the peel from the outline.
  std::vector<TriangleId> oversized;
  std::vector<bool> void_seed(count, false);
  for (TriangleId t = 0; t < count; ++t) {
    double scale = 0.0;
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
      scale = std::max(scale, spacing.local[mesh.triangles[e]]);
    const Point2& a = mesh.xy[mesh.triangles[3 * t]];
    const Point2& b = mesh.xy[mesh.triangles[3 * t + 1]];
    const Point2& c = mesh.xy[mesh.triangles[3 * t + 2]];
    auto length = [](const Point2& p, const Point2& q) {
      const double dx = p.x - q.x, dy = p.y - q.y;
      return std::sqrt(dx * dx + dy * dy);
    };
    const double ab = length(a, b), bc = length(b, c), ca = length(c, a);
    const double longest = std::max({ab, bc, ca});
    const double twice_area =
        std::fabs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
    const double radius = ab * bc * ca / (2.0 * twice_area);
    const bool too_long = longest > options.trim_factor * scale ||
                          radius > options.trim_factor * scale ||
                          (options.max_edge > 0.0 && longest > options.max_edge);
    if (!too_long)
      continue;
    oversized.push_back(t);
    auto dot = [](const Point2& o, const Point2& p, const Point2& q) {
      return (p.x - o.x) * (q.x - o.x) + (p.y - o.y) * (q.y - o.y);
    };
    void_seed[t] = dot(a, b, c) >= 0.0 && dot(b, c, a) >= 0.0 && dot(c, a, b) >= 0.0;
  }

  std::vector<bool> removed(count, false);
  std::vector<bool> had_triangle(mesh.vertexCount(), false);
  std::vector<HalfedgeId> some_out(mesh.vertexCount(), INVALID_ID);
  for (HalfedgeId e = 0; e < mesh.triangles.size(); ++e) {
    had_triangle[mesh.triangles[e]] = true;
    some_out[mesh.triangles[e]] = e;
  }

  // Peel: flood over oversized triangles from those on the outline (and from void
  // seeds), each removal exposing its neighbours. Order does not matter for the set
  // removed (the oversized triangles connected to a start), only for speed.
  std::vector<bool> is_oversized(count, false);
  for (const TriangleId t : oversized)
    is_oversized[t] = true;
  std::vector<TriangleId> stack;
  for (const TriangleId t : oversized) {
    const bool on_boundary = mesh.halfedges[3 * t] == INVALID_ID ||
                             mesh.halfedges[3 * t + 1] == INVALID_ID ||
                             mesh.halfedges[3 * t + 2] == INVALID_ID;
    if (on_boundary || (options.open_voids && void_seed[t]))
      stack.push_back(t);
  }
  while (!stack.empty()) {
    const TriangleId t = stack.back();
    stack.pop_back();
    if (removed[t])
      continue;
    removed[t] = true;
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e) {
      const HalfedgeId twin = mesh.halfedges[e];
      if (twin != INVALID_ID && is_oversized[triangleOf(twin)] &&
          !removed[triangleOf(twin)])
        stack.push_back(triangleOf(twin));
    }
  }

  // A vertex whose remaining triangles form several fans would be a pinch: restore
  // the removed triangles between its fans (a closed fan keeps its largest gap
  // open), and repeat at the vertices of restored triangles until none is left.
  std::vector<VertexId> work;
  for (TriangleId t = 0; t < count; ++t)
    if (removed[t])
      for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
        work.push_back(mesh.triangles[e]);
  std::sort(work.begin(), work.end());
  work.erase(std::unique(work.begin(), work.end()), work.end());
  std::reverse(work.begin(), work.end()); // popped in increasing id order
  while (!work.empty()) {
    const VertexId v = work.back();
    work.pop_back();
    bool closed = false;
    const std::vector<TriangleId> fan = fanOf(mesh, some_out[v], closed);
    for (const TriangleId t : restoreFanGaps(fan, closed, removed)) {
      ++result.kept_to_stay_manifold;
      for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
        if (mesh.triangles[e] != v)
          work.push_back(mesh.triangles[e]);
    }
  }
  for (TriangleId t = 0; t < count; ++t)
    result.triangles_removed += removed[t] ? 1 : 0;

  // Compact: surviving triangles keep their order; twins are remapped.
  std::vector<TriangleId> new_id(count, INVALID_ID);
  TriangleId next = 0;
  for (TriangleId t = 0; t < count; ++t)
    if (!removed[t])
      new_id[t] = next++;
  std::vector<VertexId> triangles;
  std::vector<HalfedgeId> halfedges;
  triangles.reserve(3 * static_cast<std::size_t>(next));
  halfedges.reserve(3 * static_cast<std::size_t>(next));
  for (TriangleId t = 0; t < count; ++t) {
    if (removed[t])
      continue;
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e) {
      triangles.push_back(mesh.triangles[e]);
      const HalfedgeId twin = mesh.halfedges[e];
      const bool open = twin == INVALID_ID || removed[triangleOf(twin)];
      halfedges.push_back(open ? INVALID_ID : 3 * new_id[triangleOf(twin)] + twin % 3);
    }
  }
  mesh.triangles.swap(triangles);
  mesh.halfedges.swap(halfedges);

  std::vector<bool> has_triangle(mesh.vertexCount(), false);
  for (const VertexId v : mesh.triangles)
    has_triangle[v] = true;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
    if (had_triangle[v] && !has_triangle[v])
      ++result.vertices_lost;
  return Status::success();
}

} // namespace pcl_vts
