// Outward-triangle removal: static oversize test, then passes over the oversized
// triangles until a pass removes nothing. See trim_outward_triangles.h.
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
  if (!std::isfinite(options.max_edge) || options.max_edge < 0.0)
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "max_edge = " + formatValue(options.max_edge) +
                             " must be finite and >= 0 (0 = no limit)");
  return Status::success();
}

namespace {

/// Removing t leaves vertex v (corner c of t) with one fan: true when t is at an
/// end of v's fan (one of its edges at v is a boundary) or v's fan is closed.
/// A t with both edges at v shared, in an open fan, would split the fan (a pinch).
bool keepsFanAtCorner(const TriangleMesh& mesh, HalfedgeId out)
{
  const HalfedgeId in = prevHalfedge(out); // ends at v
  if (mesh.halfedges[out] == INVALID_ID || mesh.halfedges[in] == INVALID_ID)
    return true;
  // Rotate around v through twin(out): next(twin(out)) leaves v again.
  HalfedgeId f = out;
  for (std::size_t steps = 0; steps <= mesh.halfedges.size(); ++steps) {
    const HalfedgeId twin = mesh.halfedges[f];
    if (twin == INVALID_ID)
      return false; // reached the fan's end: the fan is open
    f = nextHalfedge(twin);
    if (f == out)
      return true; // back to t: closed fan
  }
  return false;
}

void detachTriangle(TriangleMesh& mesh, TriangleId t)
{
  for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e) {
    const HalfedgeId twin = mesh.halfedges[e];
    if (twin != INVALID_ID)
      mesh.halfedges[twin] = INVALID_ID;
    mesh.halfedges[e] = INVALID_ID;
  }
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

  std::vector<TriangleId> oversized;
  for (TriangleId t = 0; t < count; ++t) {
    double longest = 0.0;
    double scale = 0.0;
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e) {
      const Point2& a = mesh.xy[mesh.triangles[e]];
      const Point2& b = mesh.xy[mesh.triangles[nextHalfedge(e)]];
      longest = std::max(longest, std::hypot(a.x - b.x, a.y - b.y));
      scale = std::max(scale, spacing.local[mesh.triangles[e]]);
    }
    const bool too_long = longest > options.trim_factor * scale ||
                          (options.max_edge > 0.0 && longest > options.max_edge);
    if (too_long)
      oversized.push_back(t);
  }

  std::vector<bool> removed(count, false);
  std::vector<bool> had_triangle(mesh.vertexCount(), false);
  for (const VertexId v : mesh.triangles)
    had_triangle[v] = true;

  // Each pass peels one layer; a pass in increasing triangle order makes the result
  // independent of anything but the arrays.
  bool changed = true;
  while (changed) {
    changed = false;
    for (const TriangleId t : oversized) {
      if (removed[t])
        continue;
      const bool on_boundary = mesh.halfedges[3 * t] == INVALID_ID ||
                               mesh.halfedges[3 * t + 1] == INVALID_ID ||
                               mesh.halfedges[3 * t + 2] == INVALID_ID;
      if (!on_boundary && !options.open_voids)
        continue;
      if (!keepsFanAtCorner(mesh, 3 * t) || !keepsFanAtCorner(mesh, 3 * t + 1) ||
          !keepsFanAtCorner(mesh, 3 * t + 2))
        continue;
      detachTriangle(mesh, t);
      removed[t] = true;
      ++result.triangles_removed;
      changed = true;
    }
  }
  for (const TriangleId t : oversized)
    if (!removed[t]) {
      const bool on_boundary = mesh.halfedges[3 * t] == INVALID_ID ||
                               mesh.halfedges[3 * t + 1] == INVALID_ID ||
                               mesh.halfedges[3 * t + 2] == INVALID_ID;
      if (on_boundary || options.open_voids)
        ++result.kept_to_stay_manifold;
    }

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
      halfedges.push_back(twin == INVALID_ID
                              ? INVALID_ID
                              : 3 * new_id[triangleOf(twin)] + twin % 3);
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
