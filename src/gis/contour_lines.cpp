// Contour tracing: per level, each crossed triangle has one entry halfedge (from a
// vertex above the level to one below) and one exit (below to above); the exit's
// twin is the entry of the next triangle, so a line is walked, never matched. Out of
// core, the crossings are kept as segments and the twin is found by the crossed edge.
#include "mapped_vertices.h"

#include <pcl_vts/gis/contour_lines.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pcl_vts {

namespace {

/// Level k: base + k * interval, computed here only, so that every test against it
/// (which triangles it crosses, which of their corners lie above it) sees one value.
double levelAt(std::int64_t k, double interval, double base)
{
  return base + static_cast<double>(k) * interval;
}

/// Calls visit(k, level) for every level base + k*interval that crosses a triangle
/// with heights z0, z1, z2 (zmin < level <= zmax), k ascending.
template <typename Visit>
Status forEachCrossingLevel(double z0, double z1, double z2, double interval,
                            double base, const Visit& visit)
{
  const double zmin = std::min({z0, z1, z2}), zmax = std::max({z0, z1, z2});
  const double kmax = std::floor((zmax - base) / interval);
  const double kmin = std::floor((zmin - base) / interval);
  if (std::abs(kmax) > 9e15 || std::abs(kmin) > 9e15)
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "contour interval " + formatValue(interval) +
                             " is too small for elevations up to " + formatValue(zmax));
  // Rounding in the division is settled by the exact comparisons with L_k.
  for (std::int64_t k = static_cast<std::int64_t>(kmin) - 1;
       k <= static_cast<std::int64_t>(kmax) + 1; ++k) {
    const double level = levelAt(k, interval, base);
    if (zmin < level && level <= zmax)
      visit(k, level);
  }
  return Status::success();
}

/// Where the level crosses the edge from lo (below it) to hi (at or above it): the
/// same bits from both triangles sharing the edge.
Point2 crossingPoint(const Point2& a, double zl, const Point2& b, double zh,
                     double level)
{
  if (zh == level)
    return b;
  const double t = (level - zl) / (zh - zl);
  return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
}

Status checkParameters(double interval, double base)
{
  if (!(interval > 0.0) || !std::isfinite(interval) || !std::isfinite(base))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "contour interval must be a positive number, not " +
                             formatValue(interval));
  return Status::success();
}

Status notManifold(double level)
{
  return Status::error(StatusCode::INTERNAL_ERROR,
                       "contour line at " + formatValue(level) +
                           " runs into itself: the mesh is not a manifold");
}

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
    return crossingPoint(mesh_.xy[lo], mesh_.z[lo], mesh_.xy[hi], mesh_.z[hi], level_);
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

/// Hands a traced line to the sink, counted: a closed line gets its first point
/// repeated at its end; a line that shrank to a point (a summit exactly at the level)
/// is not emitted.
Status emitLine(ContourLine& line, ContourStats& stats, const ContourSink& sink)
{
  if (line.closed && line.points.size() > 1 &&
      (line.points.front().x != line.points.back().x ||
       line.points.front().y != line.points.back().y))
    line.points.push_back(line.points.front());
  if (line.points.size() < (line.closed ? 4u : 2u))
    return Status::success();
  ++stats.lines;
  stats.closed += line.closed;
  return sink(line);
}

} // namespace

Status traceContours(const TriangleMesh& mesh, double interval, double base,
                     const ContourSink& sink, ContourStats* stats)
{
  if (Status s = checkParameters(interval, base); !s.ok())
    return s;
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
  for (TriangleId t = 0; t < n_tri; ++t)
    if (Status s = forEachCrossingLevel(
            mesh.z[mesh.triangles[3 * t]], mesh.z[mesh.triangles[3 * t + 1]],
            mesh.z[mesh.triangles[3 * t + 2]], interval, base,
            [&](std::int64_t k, double) {
              crossings.push_back({k, t});
            });
        !s.ok())
      return s;
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
    const double level = levelAt(crossings[begin].level, interval, base);
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
          return notManifold(level);
      }
      return emitLine(line, local, sink);
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

namespace {

/// One triangle crossed by one level, as the out-of-core tracer keeps it (32 B): an
/// edge is named by its end below the level and its end above, so the exit of one
/// segment and the entry of the next name their shared edge alike. The crossing
/// points are computed again from the vertices when the lines are walked.
struct Segment {
  std::int64_t level; ///< k
  TriangleId triangle;
  VertexId in_lo, in_hi;   ///< entry edge
  VertexId out_lo, out_hi; ///< exit edge

  std::uint64_t entry() const { return (std::uint64_t{in_lo} << 32) | in_hi; }
  std::uint64_t exit() const { return (std::uint64_t{out_lo} << 32) | out_hi; }
};

/// Segments are numbered in 32 bits (4e9 crossings would be 128 GB of segments).
using SegmentId = std::uint32_t;
constexpr SegmentId NO_SEGMENT = INVALID_ID;

/// Where the level crosses the edge from vertex lo (below) to hi (above).
Point2 crossingOf(const MappedVertices& vertices, VertexId lo, VertexId hi,
                  double level)
{
  const double *a = vertices.xyz(lo), *b = vertices.xyz(hi);
  return crossingPoint({a[0], a[1]}, a[2], {b[0], b[1]}, b[2], level);
}

/// Every (level, triangle) crossing of the streamed mesh as a segment, sorted by
/// level, then triangle: the triangles are read twice, counted first so that the
/// segments take no more memory than they need.
Status collectSegments(const MeshStream& mesh, const MappedVertices& vertices,
                       double interval, double base, std::vector<Segment>& segments)
{
  const std::uint64_t n = vertices.count();
  std::uint64_t crossings = 0;
  for (const bool count : {true, false}) {
    Status failed = Status::success();
    bool bad_id = false;
    std::uint64_t id = 0;
    Status s = mesh.triangles([&](VertexId a, VertexId b, VertexId c) {
      const std::uint64_t t = id++;
      if (!failed.ok() || bad_id)
        return;
      if (a >= n || b >= n || c >= n || t >= INVALID_ID) {
        bad_id = true;
        return;
      }
      const VertexId v[3] = {a, b, c};
      const double z[3] = {vertices.xyz(a)[2], vertices.xyz(b)[2], vertices.xyz(c)[2]};
      // The entry (above to below) and exit (below to above) edges at level k.
      const auto cut = [&](std::int64_t k, double level) {
        if (count) {
          ++crossings;
          return;
        }
        Segment g{};
        g.level = k;
        g.triangle = static_cast<TriangleId>(t);
        for (int i = 0; i < 3; ++i) {
          const int j = (i + 1) % 3;
          const bool above_i = z[i] >= level, above_j = z[j] >= level;
          if (above_i == above_j)
            continue;
          (above_i ? g.in_lo : g.out_lo) = v[above_i ? j : i];
          (above_i ? g.in_hi : g.out_hi) = v[above_i ? i : j];
        }
        segments.push_back(g);
      };
      failed = forEachCrossingLevel(z[0], z[1], z[2], interval, base, cut);
      if ((t & 0x3FFFF) == 0x3FFFF) // pages of corners already used: out of memory
        vertices.dropPages();
    });
    if (!s.ok())
      return s;
    if (bad_id)
      return Status::error(StatusCode::INVALID_PARAMETER,
                           "triangle vertex out of range");
    if (!failed.ok())
      return failed;
    if (crossings >= NO_SEGMENT)
      return Status::error(StatusCode::INVALID_PARAMETER,
                           "more than 4e9 contour crossings: the interval " +
                               formatValue(interval) + " is too small");
    if (count)
      segments.reserve(static_cast<std::size_t>(crossings));
    else if (segments.size() != crossings)
      // The tiled mesh is read from files twice: a file changed under us.
      return Status::error(StatusCode::IO_ERROR,
                           "contours: the mesh changed between two reads");
  }
  vertices.dropPages();
  std::sort(segments.begin(), segments.end(), [](const Segment& x, const Segment& y) {
    return x.level < y.level || (x.level == y.level && x.triangle < y.triangle);
  });
  return Status::success();
}

/// Each segment's successor at its level (the segment that enters by its exit edge;
/// NO_SEGMENT at the mesh boundary) and whether a segment leads into it. An edge
/// entered twice, or left twice, at a level is not a manifold's: INTERNAL_ERROR.
Status linkSegments(const std::vector<Segment>& segments, double interval, double base,
                    std::vector<SegmentId>& next, std::vector<char>& entered)
{
  std::vector<SegmentId> order(segments.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = static_cast<SegmentId>(i);
  // Sorted by (level, key): an edge used twice at a level lies next to itself.
  const auto sortBy = [&](auto key) {
    std::sort(order.begin(), order.end(), [&](SegmentId x, SegmentId y) {
      const Segment &a = segments[x], &b = segments[y];
      return a.level < b.level || (a.level == b.level && key(a) < key(b));
    });
    for (std::size_t i = 1; i < order.size(); ++i) {
      const Segment &a = segments[order[i - 1]], &b = segments[order[i]];
      if (a.level == b.level && key(a) == key(b))
        return notManifold(levelAt(a.level, interval, base));
    }
    return Status::success();
  };
  if (Status s = sortBy([](const Segment& g) { return g.exit(); }); !s.ok())
    return s;
  if (Status s = sortBy([](const Segment& g) { return g.entry(); }); !s.ok())
    return s; // order stays sorted by entry for the look-ups below
  next.assign(segments.size(), NO_SEGMENT);
  entered.assign(segments.size(), 0);
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const Segment& g = segments[i];
    const auto at = std::partition_point(order.begin(), order.end(), [&](SegmentId x) {
      const Segment& a = segments[x];
      return a.level < g.level || (a.level == g.level && a.entry() < g.exit());
    });
    if (at != order.end() && segments[*at].level == g.level &&
        segments[*at].entry() == g.exit()) {
      next[i] = *at;
      entered[*at] = 1;
    }
  }
  return Status::success();
}

} // namespace

Status traceContoursOutOfCore(const MeshStream& mesh, double interval, double base,
                              const std::string& temp_folder, const ContourSink& sink,
                              ContourStats* stats)
{
  if (Status s = checkParameters(interval, base); !s.ok())
    return s;
  MappedVertices vertices;
  if (Status s = vertices.map(mesh, temp_folder + "/contour_vertices.bin", "contours");
      !s.ok())
    return s;

  // 1. Every (level, triangle) crossing as a segment, sorted by level and triangle.
  std::vector<Segment> segments;
  if (Status s = collectSegments(mesh, vertices, interval, base, segments); !s.ok())
    return s;

  // 2. Each segment's successor: the segment of its level entering by its exit edge.
  std::vector<SegmentId> next;
  std::vector<char> entered; // a segment leads into it
  if (Status s = linkSegments(segments, interval, base, next, entered); !s.ok())
    return s;
  const auto levelOf = [&](const Segment& g) {
    return levelAt(g.level, interval, base);
  };

  // 3. The walks of traceContours, in its order: per level, open lines from the
  // segments no other leads into, then closed loops, each by triangle.
  ContourStats local;
  local.segments = segments.size();
  std::vector<char> visited(segments.size(), 0);
  std::size_t walked = 0;
  ContourLine line;
  for (std::size_t begin = 0; begin < segments.size();) {
    std::size_t end = begin;
    while (end < segments.size() && segments[end].level == segments[begin].level)
      ++end;
    const double level = levelOf(segments[begin]);
    ++local.levels;
    auto walk = [&](std::size_t start) -> Status {
      line.level = level;
      line.points.clear();
      line.closed = false;
      append(line.points,
             crossingOf(vertices, segments[start].in_lo, segments[start].in_hi, level));
      for (SegmentId g = static_cast<SegmentId>(start);;) {
        visited[g] = 1;
        append(line.points,
               crossingOf(vertices, segments[g].out_lo, segments[g].out_hi, level));
        if ((++walked & 0xFFFF) == 0) // the corners of lines already traced
          vertices.dropPages();
        g = next[g];
        if (g == NO_SEGMENT)
          break;
        if (g == start) {
          line.closed = true;
          break;
        }
        if (visited[g])
          return notManifold(level);
      }
      return emitLine(line, local, sink);
    };
    for (std::size_t i = begin; i < end; ++i)
      if (!entered[i])
        if (Status w = walk(i); !w.ok())
          return w;
    for (std::size_t i = begin; i < end; ++i)
      if (!visited[i])
        if (Status w = walk(i); !w.ok())
          return w;
    begin = end;
  }
  if (stats)
    *stats = local;
  return Status::success();
}

} // namespace pcl_vts
