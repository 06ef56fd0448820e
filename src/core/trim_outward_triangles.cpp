// Outward-triangle removal: static oversize test, flood over oversized triangles
// from the outline and void seeds, then pinch repair by restoring fan gaps.
// See trim_outward_triangles.h.
#include "post_pass_spacing.h"

#include <pcl_vts/core/parallel_for.h>
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
  if (closed) {
    // A closed fan has no open end: start it where the corner after v is smallest
    // in (x, y), so that ties between its gaps do not depend on the ids.
    const VertexId v = mesh.triangles[out];
    auto after = [&](TriangleId t) -> const Point2& {
      HalfedgeId e = 3 * t;
      while (mesh.triangles[e] != v)
        ++e;
      return mesh.xy[mesh.triangles[nextHalfedge(e)]];
    };
    auto first =
        std::min_element(fan.begin(), fan.end(), [&](TriangleId s, TriangleId t) {
          return lexLess(after(s), after(t));
        });
    std::rotate(fan.begin(), first, fan.end());
  }
  return fan;
}

/// The angle of triangle t at its corner v.
double angleAt(const TriangleMesh& mesh, TriangleId t, VertexId v)
{
  HalfedgeId e = 3 * t;
  while (mesh.triangles[e] != v)
    ++e;
  const Point2& o = mesh.xy[v];
  const Point2& p = mesh.xy[mesh.triangles[nextHalfedge(e)]];
  const Point2& q = mesh.xy[mesh.triangles[prevHalfedge(e)]];
  const double ux = p.x - o.x, uy = p.y - o.y, wx = q.x - o.x, wy = q.y - o.y;
  return std::atan2(std::fabs(ux * wy - uy * wx), ux * wx + uy * wy);
}

/// The removed triangles of v's fan that separate two kept runs: all gaps of an open
/// fan, all but the widest (by angle at v) of a closed fan, so that v keeps one fan.
std::vector<TriangleId> fanGapsToRestore(const TriangleMesh& mesh, VertexId v,
                                         const std::vector<TriangleId>& fan,
                                         bool closed, const std::vector<bool>& removed)
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
    double angle; ///< the opening at v, radians
  };
  std::vector<Gap> gaps;
  const std::size_t span = closed ? n : n - first_kept;
  for (std::size_t k = 0; k < span;) {
    const std::size_t i = (first_kept + k) % n;
    if (!removed[fan[i]]) {
      ++k;
      continue;
    }
    Gap gap{k, 0, 0.0};
    while (k < span && removed[fan[(first_kept + k) % n]]) {
      gap.angle += angleAt(mesh, fan[(first_kept + k) % n], v);
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
      if (gaps[g].angle > gaps[keep_open].angle)
        keep_open = g;
  }
  for (std::size_t g = 0; g < gaps.size(); ++g) {
    if (g == keep_open)
      continue;
    for (std::size_t k = 0; k < gaps[g].length; ++k) {
      const TriangleId t = fan[(first_kept + gaps[g].begin + k) % n];
      restored.push_back(t);
    }
  }
  return restored;
}

} // namespace

TriangleSize classifyTriangle(const Point2& a, const Point2& b, const Point2& c,
                              double scale, const TrimOptions& options)
{
  auto length = [](const Point2& p, const Point2& q) {
    const double dx = p.x - q.x, dy = p.y - q.y;
    return std::sqrt(dx * dx + dy * dy);
  };
  const double ab = length(a, b), bc = length(b, c), ca = length(c, a);
  const double longest = std::max({ab, bc, ca});
  const double twice_area =
      std::fabs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
  const double radius = ab * bc * ca / (2.0 * twice_area);
  TriangleSize size;
  size.oversized = longest > options.trim_factor * scale ||
                   radius > options.trim_factor * scale ||
                   (options.max_edge > 0.0 && longest > options.max_edge);
  if (!size.oversized)
    return size;
  // A data void holds a local maximum of the distance to the nearest point: a
  // Voronoi vertex inside its own Delaunay triangle, i.e. a non-obtuse triangle.
  // Only such triangles open a void from inside; the thin obtuse slivers along a
  // straight hull side are left to the peel from the outline.
  auto dot = [](const Point2& o, const Point2& p, const Point2& q) {
    return (p.x - o.x) * (q.x - o.x) + (p.y - o.y) * (q.y - o.y);
  };
  size.void_seed = dot(a, b, c) >= 0.0 && dot(b, c, a) >= 0.0 && dot(c, a, b) >= 0.0;
  return size;
}

namespace {

/// Flood over oversized triangles from those on the outline (and from void seeds),
/// each removal exposing its neighbours. Order does not matter for the set removed
/// (the oversized triangles connected to a start), only for speed.
void floodOversized(const TriangleMesh& mesh, const std::vector<std::uint8_t>& flags,
                    bool open_voids, std::vector<bool>& removed)
{
  const std::size_t count = mesh.triangleCount();
  auto oversized = [&](TriangleId t) { return (flags[t] & OVERSIZED) != 0; };
  std::vector<TriangleId> stack;
  for (TriangleId t = 0; t < count; ++t) {
    if (!oversized(t))
      continue;
    const bool on_boundary = mesh.halfedges[3 * t] == INVALID_ID ||
                             mesh.halfedges[3 * t + 1] == INVALID_ID ||
                             mesh.halfedges[3 * t + 2] == INVALID_ID;
    if (on_boundary || (open_voids && (flags[t] & VOID_SEED) != 0))
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
      if (twin != INVALID_ID && oversized(triangleOf(twin)) &&
          !removed[triangleOf(twin)])
        stack.push_back(triangleOf(twin));
    }
  }
}

/// A vertex whose remaining triangles form several fans would be a pinch: restore the
/// removed triangles between its fans (a closed fan keeps its largest gap open).
/// Rounds: every vertex of the round decides on the same state, then all its
/// restorations apply, and the vertices of restored triangles make the next round;
/// so no vertex goes first and the result is the geometry's. Returns the number of
/// triangles restored.
std::size_t repairPinches(const TriangleMesh& mesh, std::vector<bool>& removed)
{
  const std::size_t count = mesh.triangleCount();
  std::vector<HalfedgeId> some_out(mesh.vertexCount(), INVALID_ID);
  for (HalfedgeId e = 0; e < mesh.triangles.size(); ++e)
    some_out[mesh.triangles[e]] = e;
  std::vector<VertexId> round;
  for (TriangleId t = 0; t < count; ++t)
    if (removed[t])
      for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
        round.push_back(mesh.triangles[e]);
  std::size_t restored_count = 0;
  std::vector<TriangleId> restore;
  while (!round.empty()) {
    std::sort(round.begin(), round.end());
    round.erase(std::unique(round.begin(), round.end()), round.end());
    restore.clear();
    for (const VertexId v : round) {
      bool closed = false;
      const std::vector<TriangleId> fan = fanOf(mesh, some_out[v], closed);
      for (const TriangleId t : fanGapsToRestore(mesh, v, fan, closed, removed))
        restore.push_back(t);
    }
    round.clear();
    for (const TriangleId t : restore) {
      if (!removed[t])
        continue; // two vertices of the round restored it
      removed[t] = false;
      ++restored_count;
      for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
        round.push_back(mesh.triangles[e]);
    }
  }
  return restored_count;
}

/// OVERSIZED / VOID_SEED per triangle, against the largest local spacing of its
/// corners; each triangle its own slot, on any threads.
std::vector<std::uint8_t> classifyTriangles(const TriangleMesh& mesh,
                                            const PointSpacing& spacing,
                                            const TrimOptions& options,
                                            unsigned threads)
{
  const std::size_t count = mesh.triangleCount();
  std::vector<std::uint8_t> flags(count, 0);
  parallelFor(threads, count, [&](std::size_t k) {
    const auto t = static_cast<TriangleId>(k);
    double scale = 0.0;
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
      scale = std::max(scale, spacing.local[mesh.triangles[e]]);
    const TriangleSize size = classifyTriangle(
        mesh.xy[mesh.triangles[3 * t]], mesh.xy[mesh.triangles[3 * t + 1]],
        mesh.xy[mesh.triangles[3 * t + 2]], scale, options);
    flags[t] = static_cast<std::uint8_t>((size.oversized ? OVERSIZED : 0) |
                                         (size.void_seed ? VOID_SEED : 0));
  });
  return flags;
}

/// Drops the removed triangles: the survivors keep their order, twins are remapped.
/// In place, on contiguous ranges of triangles (one per thread): a survivor only
/// moves down, over triangles already moved or dropped. The first survivors of a
/// range whose new place lies in an earlier range are set aside while every range
/// moves its others within itself, then written: no range writes where another reads.
void compactTriangles(TriangleMesh& mesh, const std::vector<bool>& removed,
                      unsigned threads)
{
  const std::size_t count = mesh.triangleCount();
  const auto parts = static_cast<unsigned>(
      std::min<std::size_t>(threads, std::max<std::size_t>(1, count >> 16)));
  std::vector<TriangleId> new_id(count, INVALID_ID);
  std::vector<std::size_t> first_id(parts + 1, 0); // per range: survivors before it
  parallelChunks(parts, count, [&](std::size_t begin, std::size_t end, unsigned p) {
    std::size_t kept = 0;
    for (std::size_t t = begin; t < end; ++t)
      kept += removed[t] ? 0 : 1;
    first_id[p + 1] = kept;
  });
  for (unsigned p = 0; p < parts; ++p)
    first_id[p + 1] += first_id[p];
  struct Moved {
    TriangleId to;
    VertexId corners[3];
    HalfedgeId twins[3];
  };
  std::vector<std::vector<Moved>> aside(parts);
  parallelChunks(parts, count, [&](std::size_t begin, std::size_t end, unsigned p) {
    auto next = static_cast<TriangleId>(first_id[p]);
    for (std::size_t t = begin; t < end; ++t)
      if (!removed[t])
        new_id[t] = next++;
  });
  parallelChunks(parts, count, [&](std::size_t begin, std::size_t end, unsigned p) {
    for (std::size_t t = begin; t < end; ++t) {
      if (removed[t])
        continue;
      Moved moved{new_id[t], {}, {}};
      for (std::size_t k = 0; k < 3; ++k) {
        const HalfedgeId twin = mesh.halfedges[3 * t + k];
        const bool open = twin == INVALID_ID || removed[triangleOf(twin)];
        moved.corners[k] = mesh.triangles[3 * t + k];
        moved.twins[k] = open ? INVALID_ID : 3 * new_id[triangleOf(twin)] + twin % 3;
      }
      if (moved.to < begin) {
        aside[p].push_back(moved);
        continue;
      }
      for (std::size_t k = 0; k < 3; ++k) {
        mesh.triangles[3 * std::size_t{moved.to} + k] = moved.corners[k];
        mesh.halfedges[3 * std::size_t{moved.to} + k] = moved.twins[k];
      }
    }
  });
  for (const std::vector<Moved>& part : aside)
    for (const Moved& moved : part)
      for (std::size_t k = 0; k < 3; ++k) {
        mesh.triangles[3 * std::size_t{moved.to} + k] = moved.corners[k];
        mesh.halfedges[3 * std::size_t{moved.to} + k] = moved.twins[k];
      }
  mesh.triangles.resize(3 * first_id[parts]);
  mesh.halfedges.resize(3 * first_id[parts]);
}

} // namespace

std::size_t peelOutwardTriangles(const TriangleMesh& mesh,
                                 const std::vector<std::uint8_t>& flags,
                                 bool open_voids, std::vector<bool>& removed)
{
  removed.assign(mesh.triangleCount(), false);
  floodOversized(mesh, flags, open_voids, removed);
  return repairPinches(mesh, removed);
}

Status trimOutwardTriangles(TriangleMesh& mesh, const TrimOptions& options,
                            TrimResult& result)
{
  return detail::trimOutwardTriangles(mesh, options, result, nullptr);
}

Status detail::trimOutwardTriangles(TriangleMesh& mesh, const TrimOptions& options,
                                    TrimResult& result, VertexSpacing* after,
                                    unsigned threads)
{
  threads = threads > 0 ? threads : allCores();
  result = TrimResult{};
  Status status = validateTrimOptions(options);
  if (!status.ok())
    return status;
  if (mesh.halfedges.size() != mesh.triangles.size())
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "halfedges must have one entry per triangle corner");
  std::vector<double> own;
  const PointSpacing spacing = detail::measurePointSpacing(
      mesh, nullptr, after != nullptr ? &own : nullptr, threads);
  result.spacing = spacing.global_median;
  const std::vector<std::uint8_t> flags =
      classifyTriangles(mesh, spacing, options, threads);

  std::vector<bool> removed;
  result.kept_to_stay_manifold =
      peelOutwardTriangles(mesh, flags, options.open_voids, removed);
  // Only a corner of a removed triangle can be left without triangles, and only its
  // row of edges changes.
  std::vector<bool> changed(mesh.vertexCount(), false);
  for (TriangleId t = 0; t < removed.size(); ++t) {
    if (!removed[t])
      continue;
    ++result.triangles_removed;
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
      changed[mesh.triangles[e]] = true;
  }
  if (result.triangles_removed > 0)
    compactTriangles(mesh, removed, threads);
  std::vector<bool>().swap(removed);

  std::vector<bool> has_triangle;
  if (result.triangles_removed > 0) {
    has_triangle.assign(mesh.vertexCount(), false);
    for (const VertexId v : mesh.triangles)
      has_triangle[v] = true;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
      if (changed[v] && !has_triangle[v])
        ++result.vertices_lost;
  }
  if (after != nullptr) {
    after->own.swap(own);
    after->global_median = spacing.global_median;
    after->settled = result.triangles_removed == 0; // the input's spacing holds
    if (!after->settled) {
      after->changed.swap(changed);
      after->has_triangle.swap(has_triangle);
    }
  }
  return Status::success();
}

} // namespace pcl_vts
