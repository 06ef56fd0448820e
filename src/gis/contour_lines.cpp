// Contour tracing: per level, each crossed triangle has one entry halfedge (from a
// vertex above the level to one below) and one exit (below to above); the exit's
// twin is the entry of the next triangle, so a line is walked, never matched.
#include <pcl_vts/gis/contour_lines.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pcl_vts {

namespace {

struct Crossing {
  std::int64_t level;
  TriangleId triangle;
};

class Tracer {
 public:
  Tracer(const TriangleMesh& mesh, double level)
      : mesh_(mesh)
      , level_(level)
  {}

  bool above(VertexId v) const { return mesh_.z[v] >= level_; }

  /// The entry and exit halfedges of triangle t (INVALID_ID when not crossed).
  void halfedges(TriangleId t, HalfedgeId& in, HalfedgeId& out) const
  {
    in = out = INVALID_ID;
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e) {
      const bool a = above(mesh_.triangles[e]);
      const bool b = above(mesh_.triangles[nextHalfedge(e)]);
      if (a && !b)
        in = e;
      else if (!a && b)
        out = e;
    }
  }

  /// Where the level crosses halfedge e: from the lower end to the upper one.
  Point2 crossing(HalfedgeId e) const
  {
    VertexId lo = mesh_.triangles[e], hi = mesh_.triangles[nextHalfedge(e)];
    if (above(lo))
      std::swap(lo, hi);
    const double zl = mesh_.z[lo], zh = mesh_.z[hi];
    if (zh == level_)
      return mesh_.xy[hi];
    const double t = (level_ - zl) / (zh - zl);
    const Point2& a = mesh_.xy[lo];
    const Point2& b = mesh_.xy[hi];
    return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
  }

 private:
  const TriangleMesh& mesh_;
  double level_;
};

void append(std::vector<Point2>& line, const Point2& p)
{
  if (line.empty() || line.back().x != p.x || line.back().y != p.y)
    line.push_back(p);
}

} // namespace

Status traceContours(const TriangleMesh& mesh, double interval, double base,
                     const ContourSink& sink, ContourStats* stats)
{
  if (!(interval > 0.0) || !std::isfinite(interval) || !std::isfinite(base))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "contour interval must be a positive number, not " +
                             formatValue(interval));
  const std::size_t n_tri = mesh.triangleCount();
  if (mesh.halfedges.size() != mesh.triangles.size() || mesh.xy.size() != mesh.z.size())
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "contours need the mesh's halfedges");
  for (VertexId v : mesh.triangles)
    if (v >= mesh.vertexCount())
      return Status::error(StatusCode::INVALID_PARAMETER,
                           "triangle vertex out of range");
  // Every (level, triangle) crossing: level k crosses t when zmin < L_k <= zmax.
  std::vector<Crossing> crossings;
  for (TriangleId t = 0; t < n_tri; ++t) {
    const double z0 = mesh.z[mesh.triangles[3 * t]],
                 z1 = mesh.z[mesh.triangles[3 * t + 1]],
                 z2 = mesh.z[mesh.triangles[3 * t + 2]];
    const double zmin = std::min({z0, z1, z2}), zmax = std::max({z0, z1, z2});
    const double kmax = std::floor((zmax - base) / interval);
    const double kmin = std::floor((zmin - base) / interval);
    if (std::abs(kmax) > 9e15 || std::abs(kmin) > 9e15)
      return Status::error(StatusCode::INVALID_PARAMETER,
                           "contour interval " + formatValue(interval) +
                               " is too small for elevations up to " +
                               formatValue(zmax));
    // Rounding in the division is settled by the exact comparisons with L_k.
    for (std::int64_t k = static_cast<std::int64_t>(kmin) - 1;
         k <= static_cast<std::int64_t>(kmax) + 1; ++k) {
      const double level = base + static_cast<double>(k) * interval;
      if (zmin < level && level <= zmax)
        crossings.push_back({k, t});
    }
  }
  std::sort(
      crossings.begin(), crossings.end(), [](const Crossing& a, const Crossing& b) {
        return a.level < b.level || (a.level == b.level && a.triangle < b.triangle);
      });

  ContourStats local;
  local.segments = crossings.size();
  // visited[t] = the stamp (1, 2, ...) of the level that last walked through t.
  std::vector<std::size_t> visited(n_tri, 0);
  ContourLine line;
  for (std::size_t begin = 0; begin < crossings.size();) {
    std::size_t end = begin;
    while (end < crossings.size() && crossings[end].level == crossings[begin].level)
      ++end;
    const std::int64_t k = crossings[begin].level;
    const double level = base + static_cast<double>(k) * interval;
    const Tracer tracer(mesh, level);
    const std::size_t stamp = ++local.levels;
    // Walks from triangle t until the boundary or back to the start.
    auto walk = [&](TriangleId start) -> Status {
      line.level = level;
      line.points.clear();
      line.closed = false;
      HalfedgeId in = INVALID_ID, out = INVALID_ID;
      tracer.halfedges(start, in, out);
      append(line.points, tracer.crossing(in));
      TriangleId t = start;
      for (;;) {
        visited[t] = stamp;
        tracer.halfedges(t, in, out);
        append(line.points, tracer.crossing(out));
        const HalfedgeId twin = mesh.halfedges[out];
        if (twin == INVALID_ID)
          break;
        t = triangleOf(twin);
        if (t == start) {
          line.closed = true;
          break;
        }
        if (visited[t] == stamp)
          return Status::error(StatusCode::INTERNAL_ERROR,
                               "contour line at " + formatValue(level) +
                                   " runs into itself: the mesh is not a manifold");
      }
      if (line.closed && line.points.size() > 1 &&
          (line.points.front().x != line.points.back().x ||
           line.points.front().y != line.points.back().y))
        line.points.push_back(line.points.front());
      if (line.points.size() < (line.closed ? 4u : 2u))
        return Status::success(); // shrank to a point: a summit exactly at the level
      ++local.lines;
      local.closed += line.closed;
      return sink(line);
    };
    // Open lines first, from the triangle whose entry lies on the boundary...
    for (std::size_t i = begin; i < end; ++i) {
      HalfedgeId in = INVALID_ID, out = INVALID_ID;
      tracer.halfedges(crossings[i].triangle, in, out);
      if (mesh.halfedges[in] == INVALID_ID)
        if (Status s = walk(crossings[i].triangle); !s.ok())
          return s;
    }
    // ...then what is left is closed loops.
    for (std::size_t i = begin; i < end; ++i)
      if (visited[crossings[i].triangle] != stamp)
        if (Status s = walk(crossings[i].triangle); !s.ok())
          return s;
    begin = end;
  }
  if (stats)
    *stats = local;
  return Status::success();
}

} // namespace pcl_vts
