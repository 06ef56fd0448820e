// Outward-triangle removal: static oversize test, flood over oversized triangles
// from the outline and void seeds, then pinch repair by restoring fan gaps.
// See trim_outward_triangles.h.
#include "cpu_features.h"
#include "post_pass_spacing.h"
#include "trim_compaction.h"

#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/point_spacing.h>
#include <pcl_vts/core/trim_outward_triangles.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__SSE2__) && defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#include <immintrin.h>
// The compaction's AVX2 loop, taken where the CPU has it (compactionHasAvx2).
#define PCL_VTS_COMPACTION_AVX2 1
#endif

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

/// Original fan of v as a sequence of triangles (into fan, replaced), starting at an
/// open end if the fan is open. out: any halfedge leaving v.
void fanOf(const TriangleMesh& mesh, HalfedgeId out, bool& closed,
           std::vector<TriangleId>& fan)
{
  fan.clear();
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
  const detail::TriangleSquares squares = detail::triangleSquares(a, b, c);
  const double ab = std::sqrt(squares.ab), bc = std::sqrt(squares.bc),
               ca = std::sqrt(squares.ca);
  const double longest = std::max({ab, bc, ca});
  const double twice_area = squares.twice_area;
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

/// The set bits of x (__builtin_popcountll is a call into libgcc without -mpopcnt).
inline unsigned bitCount(std::uint64_t x)
{
  x -= (x >> 1) & 0x5555555555555555ull;
  x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
  x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0full;
  return static_cast<unsigned>((x * 0x0101010101010101ull) >> 56);
}

/// The flood's starts: the oversized triangles on the outline and, with open_voids,
/// the void seeds.
std::vector<TriangleId> floodStarts(const TriangleMesh& mesh,
                                    const std::vector<std::uint8_t>& flags,
                                    bool open_voids)
{
  std::vector<TriangleId> starts;
  const std::size_t count = mesh.triangleCount();
  for (TriangleId t = 0; t < count; ++t) {
    if ((flags[t] & OVERSIZED) == 0)
      continue;
    const bool on_boundary = mesh.halfedges[3 * t] == INVALID_ID ||
                             mesh.halfedges[3 * t + 1] == INVALID_ID ||
                             mesh.halfedges[3 * t + 2] == INVALID_ID;
    if (on_boundary || (open_voids && (flags[t] & VOID_SEED) != 0))
      starts.push_back(t);
  }
  return starts;
}

/// Flood over oversized triangles from the starts, each removal exposing its
/// neighbours. Order does not matter for the set removed (the oversized triangles
/// connected to a start), only for speed. Appends the removed ones to `list`.
/// oversized(t): whether triangle t is oversized.
template <typename Oversized>
void floodOversized(const TriangleMesh& mesh, const Oversized& oversized,
                    std::vector<TriangleId> stack, std::vector<bool>& removed,
                    std::vector<TriangleId>& list)
{
  while (!stack.empty()) {
    const TriangleId t = stack.back();
    stack.pop_back();
    if (removed[t])
      continue;
    removed[t] = true;
    list.push_back(t);
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
std::size_t repairPinches(const TriangleMesh& mesh, const std::vector<TriangleId>& list,
                          std::vector<bool>& removed)
{
  // The round's vertices with a halfedge leaving each (a corner of a removed or a
  // restored triangle): a fan does not depend on where its walk starts (fanOf).
  std::vector<std::pair<VertexId, HalfedgeId>> round;
  for (const TriangleId t : list)
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
      round.emplace_back(mesh.triangles[e], e);
  std::size_t restored_count = 0;
  std::vector<TriangleId> restore;
  auto by_vertex = [](const std::pair<VertexId, HalfedgeId>& a,
                      const std::pair<VertexId, HalfedgeId>& b) {
    return a.first < b.first;
  };
  auto same_vertex = [](const std::pair<VertexId, HalfedgeId>& a,
                        const std::pair<VertexId, HalfedgeId>& b) {
    return a.first == b.first;
  };
  while (!round.empty()) {
    std::sort(round.begin(), round.end(), by_vertex);
    round.erase(std::unique(round.begin(), round.end(), same_vertex), round.end());
    restore.clear();
    std::vector<TriangleId> fan;
    for (const auto& [v, out] : round) {
      bool closed = false;
      fanOf(mesh, out, closed, fan);
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
        round.emplace_back(mesh.triangles[e], e);
    }
  }
  return restored_count;
}

/// Whether each triangle is OVERSIZED (a bit per triangle), against the largest
/// local spacing of its corners, and the flood's starts (floodStarts' order, from
/// the OVERSIZED and VOID_SEED flags). A triangle with a cleared
/// corner (below), or no larger than trim_factor times the largest ringLowerBound
/// of its corners (a lower bound of their local spacing), is not oversized, with
/// classifyTriangle's own figures; only the others need the local medians, and
/// those of their corners alone are computed. Each triangle its own slot, on any
/// threads. The pass of the ring bounds also counts the global median's histogram
/// and clears the vertices (ringLowerBounds). scale: each vertex's need
/// (VertexRows::build with edge_limit2 = max_edge^2 * Clearance::MARGIN, +inf
/// without max_edge) on entry.
///
/// Vertex clearance. For triangle t = abc, need(t) (Clearance::need) is the
/// computed max(longest squared edge L2, squared circumradius R2 = P / (4 T^2), P
/// the product of the squared edges, T twice the area), +inf when a figure lies
/// outside [1e-60, 1e60] or is NaN or L2 > edge_limit2; S(v), the largest need of
/// v's triangles, each rounded up to a float (+inf past the float range), so S(v)
/// >= need(t) for every t at v (the scatter of the rows computes it). v is cleared
/// when, B(v) being its ringLowerBound and lim = fl(trim_factor * B(v)) in [1e-60,
/// 1e60], S(v) <= fl(fl(lim * lim) * MARGIN), MARGIN = 1 - 1e-12 (ringLowerBounds).
/// Claim: a triangle t with a cleared corner a is not
/// oversized by classifyTriangle(a, b, c, scale(t)), scale(t) the largest local
/// median of its corners. Let u = 2^-53. need(t) <= S(a) <= lim^2 (1 - 1e-12)
/// (1 + u)^2 < lim^2 (1 - 9e-13). (1) classifyTriangle's lengths are the correctly
/// rounded roots of the same computed squares (triangleSquares, -ffp-contract=off),
/// so its longest edge is fl(sqrt(L2)) <= lim, as sqrt(L2) < lim and lim is a
/// double; and lim = fl(f B(a)) <= fl(f local(a)) <= fl(f scale(t)) (B(a) <=
/// local(a) <= scale(t), rounding is monotone): not over the factor's limit. (2)
/// Its radius, three roots, two products and a quotient of the same figures, is at
/// most sqrt(P) / (2T) (1 + u)^6; when need(t) took L2 (fl(P) <= fl(fl(4 T^2) *
/// L2)), P <= 4 T^2 L2 (1 + u)^5, else need(t) >= P / (4 T^2) (1 + u)^-5; either
/// way sqrt(P) / (2T) <= sqrt(need(t)) (1 + u)^3, and the radius is below lim
/// (1 - 4e-13) < lim. (3) With max_edge, L2 <= fl(fl(max_edge^2) * MARGIN) <
/// max_edge^2, so fl(sqrt(L2)) <= max_edge. The range keeps every product and
/// quotient (at most 1e300, at least 1e-240) normal and finite, so the relative
/// bounds hold. The figures are the per-triangle clearance's below (the same
/// proof with scale(t)'s largest ring bound); triangles with no cleared corner take
/// it, then classifyTriangle. They are found in the fans of the uncleared vertices
/// (hull, voids: few), each from one triangle ringLowerBounds lists, so no pass
/// reads every triangle here; the flags and the hard list are the same as a test of
/// every triangle would give (a cleared triangle is never oversized), in triangle
/// order.
std::vector<bool>
classifyTriangles(const TriangleMesh& mesh, const detail::VertexRows& rows,
                  const std::vector<double>& own, const detail::OwnStats& stats,
                  const TrimOptions& options, unsigned threads,
                  std::vector<TriangleId>& starts, detail::MedianSelection& histogram,
                  std::vector<double>& scale)
{
  const std::size_t count = mesh.triangleCount();
  // scale: the needs, then ringLowerBound, then the local median where needed.
  detail::ClearedVertices cleared;
  cleared.trim_factor = options.trim_factor;
  detail::ringLowerBounds(rows, own, stats, threads, scale, &histogram, &cleared);
  const std::size_t n = scale.size();
  auto corner = [&](TriangleId t, unsigned k) -> const Point2& {
    return mesh.xy[mesh.triangles[3 * std::size_t{t} + k]];
  };
  auto largest = [&](TriangleId t) {
    double s = 0.0;
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
      s = std::max(s, scale[mesh.triangles[e]]);
    return s;
  };
  // The triangles the bound does not clear, per range in triangle order.
  const unsigned parts = usefulThreads(threads, count);
  // A triangle without a cleared corner is cleared without a root or a division
  // when its squared edges and squared circumradius (the product of the squared
  // edges over four squared areas, the same area classifyTriangle computes) are
  // below the squared limits by a relative margin far above their rounding errors (a
  // few units in the last place), all figures in a range where no product overflows
  // or loses precision; any other triangle (near the limits, tiny or huge, NaN)
  // takes classifyTriangle.
  const double max_edge2 = options.max_edge > 0.0
                               ? options.max_edge * options.max_edge
                               : std::numeric_limits<double>::infinity();
  constexpr double LOW = detail::Clearance::LOW, HIGH = detail::Clearance::HIGH,
                   MARGIN = detail::Clearance::MARGIN;
  const VertexId* ids = mesh.triangles.data();
  const std::uint64_t* cleared_bits = cleared.bits.data();
  auto clear = [cleared_bits](VertexId v) {
    return (cleared_bits[v / 64] >> (v % 64)) & 1u;
  };
  const Point2* xy = mesh.xy.data();
  const double* bound = scale.data();
  const double factor = options.trim_factor, edge_limit2 = max_edge2 * MARGIN;
  // Triangle t without a cleared corner: onto `mine` when the bound does not clear
  // it and classifyTriangle finds it oversized against the bound.
  auto examine = [&](std::size_t t, std::vector<TriangleId>& mine) {
    const VertexId ia = ids[3 * t], ib = ids[3 * t + 1], ic = ids[3 * t + 2];
    double corner_scale = 0.0; // largest's order
    corner_scale = std::max(corner_scale, bound[ia]);
    corner_scale = std::max(corner_scale, bound[ib]);
    corner_scale = std::max(corner_scale, bound[ic]);
    const Point2 &a = xy[ia], &b = xy[ib], &c = xy[ic];
    const auto [ab, bc, ca, twice_area] = detail::triangleSquares(a, b, c);
    const double limit = factor * corner_scale;
    const double limit2 = limit * limit * MARGIN;
    const double longest = std::max({ab, bc, ca});
    // Every condition evaluated (no branch per condition; out of range, the
    // others' figures are not used), the range test on the smallest and the
    // largest figure: min and max may pass over a NaN, but a NaN figure makes the
    // last comparison false anyway.
    const double low =
        std::min(std::min(ab, bc), std::min(ca, std::min(twice_area, limit)));
    const double high =
        std::max(std::max(ab, bc), std::max(ca, std::max(twice_area, limit)));
    const bool cleared_here = (low >= LOW) & (high <= HIGH) & (longest <= limit2) &
                              (longest <= edge_limit2) &
                              (ab * bc * ca <= 4.0 * twice_area * twice_area * limit2);
    if (!cleared_here && classifyTriangle(a, b, c, corner_scale, options).oversized)
      mine.push_back(static_cast<TriangleId>(t));
  };
  // The triangles without a cleared corner are in the fans of the uncleared
  // vertices: each from the fan of its smallest corner, when every such fan, walked
  // from the triangle ringLowerBounds kept, holds all the vertex's triangles (its
  // row's count: a triangle per halfedge leaving it, one more for an open fan) and
  // they are few (one per 256 triangles: the walks' accesses are random, and uniform
  // points leave one vertex in 30 uncleared); else a pass over every triangle tests
  // its corners' bits.
  // v's triangles into fan, walked both ways around v from `out` (a halfedge
  // leaving v; any order: fanOf's is not needed); false unless every halfedge
  // reached leaves v and they are all of v's triangles by its row's count.
  const HalfedgeId* twins = mesh.halfedges.data();
  auto fanAround = [&](VertexId v, HalfedgeId out, std::vector<TriangleId>& fan) {
    fan.clear();
    const std::size_t row = rows.end(v) - rows.begin(v);
    bool closed = false;
    HalfedgeId e = out;
    for (std::size_t steps = 0; steps <= row && ids[e] == v; ++steps) {
      fan.push_back(triangleOf(e));
      const HalfedgeId across = twins[prevHalfedge(e)]; // leaves v
      if (across == INVALID_ID)
        break;
      if (across == out) {
        closed = true;
        break;
      }
      e = across;
    }
    if (ids[e] != v)
      return false;
    e = out;
    for (std::size_t steps = 0; !closed && steps <= row; ++steps) {
      const HalfedgeId across = twins[e]; // enters v
      if (across == INVALID_ID)
        break;
      e = nextHalfedge(across);
      if (ids[e] != v)
        return false;
      fan.push_back(triangleOf(e));
    }
    return fan.size() + (closed ? 0 : 1) == row;
  };
  std::vector<std::vector<TriangleId>> unclear(parts);
  bool fans = cleared.uncleared.size() <= count / 256;
  if (fans) {
    std::vector<TriangleId> fan, found;
    for (const auto& [v, t0] : cleared.uncleared) {
      HalfedgeId out = 3 * t0;
      while (out < 3 * t0 + 3 && ids[out] != v)
        ++out;
      if (out == 3 * t0 + 3) {
        fans = false;
        break;
      }
      if (!fanAround(v, out, fan)) {
        fans = false;
        break;
      }
      for (const TriangleId t : fan) {
        const VertexId ia = ids[3 * std::size_t{t}], ib = ids[3 * std::size_t{t} + 1],
                       ic = ids[3 * std::size_t{t} + 2];
        if (std::min(ia, std::min(ib, ic)) == v &&
            (clear(ia) | clear(ib) | clear(ic)) == 0)
          found.push_back(t);
      }
    }
    if (fans) {
      std::sort(found.begin(), found.end());
      found.erase(std::unique(found.begin(), found.end()), found.end());
      for (const TriangleId t : found)
        examine(t, unclear[0]);
    }
  }
  if (!fans)
    parallelChunks(parts, count, [&](std::size_t begin, std::size_t end, unsigned p) {
      std::vector<TriangleId>& mine = unclear[p];
      mine.clear();
      for (std::size_t t = begin; t < end; ++t) {
        const VertexId ia = ids[3 * t], ib = ids[3 * t + 1], ic = ids[3 * t + 2];
        if ((clear(ia) | clear(ib) | clear(ic)) == 0)
          examine(t, mine);
      }
    });
  std::vector<TriangleId> hard;
  for (const std::vector<TriangleId>& part : unclear)
    hard.insert(hard.end(), part.begin(), part.end());
  std::vector<std::vector<TriangleId>>().swap(unclear);
  // Their corners, each once, in increasing order: a bit per vertex, then the set
  // bits word by word (no sort).
  std::vector<std::uint64_t> marked((n + 63) / 64, 0);
  for (const TriangleId t : hard)
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
      marked[mesh.triangles[e] / 64] |= std::uint64_t{1} << (mesh.triangles[e] % 64);
  std::vector<VertexId> corners;
  for (std::size_t w = 0; w < marked.size(); ++w)
    for (std::uint64_t bits = marked[w]; bits != 0; bits &= bits - 1)
      corners.push_back(
          static_cast<VertexId>(64 * w + static_cast<unsigned>(__builtin_ctzll(bits))));
  std::vector<std::uint64_t>().swap(marked);
  parallelRanges(threads, corners.size(), [&](std::size_t begin, std::size_t end) {
    std::vector<double> values;
    for (std::size_t k = begin; k < end; ++k)
      scale[corners[k]] = detail::localMedian(rows, own, corners[k], values);
  });
  // The hard triangles' flags, each its own slot on any threads; then a bit per
  // triangle (a byte per triangle was 2 MB of fresh pages at 1e6 points).
  std::vector<std::uint8_t> flags(hard.size(), 0);
  parallelFor(threads, hard.size(), [&](std::size_t k) {
    const TriangleId t = hard[k];
    const TriangleSize size =
        classifyTriangle(corner(t, 0), corner(t, 1), corner(t, 2), largest(t), options);
    flags[k] = static_cast<std::uint8_t>((size.oversized ? OVERSIZED : 0) |
                                         (size.void_seed ? VOID_SEED : 0));
  });
  std::vector<bool> oversized(count, false);
  for (std::size_t k = 0; k < hard.size(); ++k) {
    if ((flags[k] & OVERSIZED) == 0)
      continue;
    const TriangleId t = hard[k];
    oversized[t] = true;
    const bool on_boundary = mesh.halfedges[3 * t] == INVALID_ID ||
                             mesh.halfedges[3 * t + 1] == INVALID_ID ||
                             mesh.halfedges[3 * t + 2] == INVALID_ID;
    if (on_boundary || (options.open_voids && (flags[k] & VOID_SEED) != 0))
      starts.push_back(t);
  }
  return oversized;
}

#if defined(PCL_VTS_COMPACTION_AVX2)
/// The AVX2 loop of a run's move (compactTriangles): from halfedge h, eight at a
/// time while eight remain before h_end, the corners and the twins move down by delta;
/// a twin in the run [first, first + size) by delta, any other by its block's entry
/// of `shifts` (a gather), and the eight by remap, one by one, when a block's entry
/// is INVALID_ID (a dropped triangle in the block, or an INVALID_ID twin: the clamp
/// to last_block). Both arrays fetched AHEAD halfedges ahead. Returns the first
/// halfedge not moved.
template <typename Remap>
__attribute__((target("avx2"))) std::size_t
moveRunAvx2(VertexId* corners, HalfedgeId* twins, std::size_t h, std::size_t h_end,
            std::size_t delta, std::size_t first, std::size_t size,
            const std::uint32_t* shifts, unsigned shift_bits, std::uint32_t last_block,
            std::size_t halfedge_count, const Remap& remap)
{
  const __m256i bias = _mm256_set1_epi32(std::numeric_limits<std::int32_t>::min());
  const __m256i first8 = _mm256_set1_epi32(static_cast<std::int32_t>(first));
  const __m256i size8 = _mm256_xor_si256(
      bias,
      _mm256_set1_epi32(static_cast<std::int32_t>(static_cast<std::uint32_t>(size))));
  const __m256i delta8 = _mm256_set1_epi32(static_cast<std::int32_t>(delta));
  const __m256i last8 = _mm256_set1_epi32(static_cast<std::int32_t>(last_block));
  const __m256i invalid8 = _mm256_set1_epi32(-1);
  const __m128i bits = _mm_cvtsi32_si128(static_cast<int>(shift_bits));
  constexpr std::size_t AHEAD = 512;
  for (; h + 8 <= h_end; h += 8) {
    const std::size_t ahead = std::min(h + AHEAD, halfedge_count - 1);
    __builtin_prefetch(twins + ahead);
    __builtin_prefetch(corners + ahead);
    _mm256_storeu_si256(
        reinterpret_cast<__m256i*>(corners + h - delta),
        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(corners + h)));
    const __m256i twin8 =
        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(twins + h));
    const __m256i inside = _mm256_cmpgt_epi32(
        size8, _mm256_xor_si256(_mm256_sub_epi32(twin8, first8), bias));
    if (_mm256_movemask_epi8(inside) == -1) {
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(twins + h - delta),
                          _mm256_sub_epi32(twin8, delta8));
      continue;
    }
    const __m256i block8 = _mm256_min_epu32(_mm256_srl_epi32(twin8, bits), last8);
    const __m256i shift8 =
        _mm256_i32gather_epi32(reinterpret_cast<const int*>(shifts), block8, 4);
    if (_mm256_movemask_epi8(_mm256_cmpeq_epi32(shift8, invalid8)) == 0) {
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(twins + h - delta),
                          _mm256_sub_epi32(twin8, shift8));
      continue;
    }
    for (std::size_t k = h; k < h + 8; ++k)
      twins[k - delta] = remap(k);
  }
  return h;
}
#endif

} // namespace

bool detail::compactionHasAvx2()
{
#if defined(PCL_VTS_COMPACTION_AVX2)
  return cpuHasAvx2();
#else
  return false;
#endif
}

/// Drops the removed triangles: the survivors keep their order, twins are remapped.
/// A survivor's new id is its id less the removed triangles before it: the same for
/// a run of survivors between two removed triangles, and for a twin into the run
/// (one unsigned comparison, four twins at a time); a twin elsewhere counts them from a
/// bit per triangle and a prefix count per 64 of them (cache-resident, unlike an id per
/// triangle). In place, on contiguous ranges of triangles (one per thread): a survivor
/// only moves down, over triangles already moved or dropped. The first survivors of a
/// range whose new place lies in an earlier range are set aside while every range moves
/// its others within itself, then written: no range writes where another reads.
/// With AVX2 (moveRunAvx2), eight halfedges at a time, and a twin elsewhere takes
/// three times the removed triangles before its block of 64 halfedges from a table
/// (a gather; jittered 1e6: about a tenth of the twins leave their run), unless a
/// removed triangle lies in that block.
void detail::compactTriangles(TriangleMesh& mesh,
                              const std::vector<TriangleId>& dropped, unsigned threads,
                              std::vector<HalfedgeId>* boundary, CompactionLoop loop)
{
  const std::size_t count = mesh.triangleCount();
  std::vector<std::uint64_t> bits((count + 63) / 64, 0);
  for (const TriangleId t : dropped)
    bits[t / 64] |= std::uint64_t{1} << (t % 64);
  std::vector<std::uint32_t> before(bits.size() + 1, 0); // removed in earlier words
  for (std::size_t w = 0; w < bits.size(); ++w)
    before[w + 1] = before[w] + static_cast<std::uint32_t>(bitCount(bits[w]));
  // Raw pointers: the writes into the mesh's arrays would otherwise make the
  // compiler reload every vector's data pointer after each store.
  const std::uint64_t* removed_bits = bits.data();
  const std::uint32_t* removed_before = before.data();
  VertexId* corners = mesh.triangles.data();
  HalfedgeId* twins = mesh.halfedges.data();
  // The new id of triangle t, or INVALID_ID when it is removed. Most words hold no
  // removed triangle: their count is skipped.
  auto new_id = [removed_bits, removed_before](std::size_t t) {
    const std::uint64_t word = removed_bits[t / 64];
    if (((word >> (t % 64)) & 1u) != 0)
      return INVALID_ID;
    std::size_t id = t - removed_before[t / 64];
    if (word != 0)
      id -= bitCount(word & ((std::uint64_t{1} << (t % 64)) - 1));
    return static_cast<TriangleId>(id);
  };
  const std::size_t kept = count - before.back();
  const unsigned parts = usefulThreads(threads, count);
  struct Moved {
    TriangleId to;
    VertexId corners[3];
    HalfedgeId twins[3];
  };
  std::vector<std::vector<Moved>> aside(parts);
  std::vector<std::vector<HalfedgeId>> open_edges(parts); // new ids, increasing
  // The removed triangles in increasing order: between two of them (a run) the
  // survivors move down by the same count, and so do the twins into the run, which
  // are most twins (a twin outside it takes new_id).
  std::vector<TriangleId> removed_in_order;
  removed_in_order.reserve(before.back());
  for (std::size_t w = 0; w < bits.size(); ++w)
    for (std::uint64_t word = bits[w]; word != 0; word &= word - 1)
      removed_in_order.push_back(static_cast<TriangleId>(
          64 * w + static_cast<unsigned>(__builtin_ctzll(word))));
  const TriangleId* removed_at = removed_in_order.data();
  const std::size_t removed_count = removed_in_order.size();
#if defined(PCL_VTS_COMPACTION_AVX2)
  // Per block of 2^SHIFT_BITS halfedges: three times the removed triangles before
  // it, or INVALID_ID when a removed triangle has a halfedge in it; one more entry,
  // INVALID_ID, where INVALID_ID twins are clamped.
  constexpr unsigned SHIFT_BITS = 6;
  const bool avx2 = loop == CompactionLoop::BEST && compactionHasAvx2();
  const std::size_t blocks = avx2 ? ((3 * count) >> SHIFT_BITS) + 1 : 0;
  std::vector<std::uint32_t> shift_table(avx2 ? blocks + 1 : 0, INVALID_ID);
  for (std::size_t block = 0, r = 0; block < blocks; ++block) {
    const std::size_t low = block << SHIFT_BITS;
    while (r < removed_count && 3 * std::size_t{removed_at[r]} + 3 <= low)
      ++r;
    if (r == removed_count ||
        3 * std::size_t{removed_at[r]} >= low + (1u << SHIFT_BITS))
      shift_table[block] = static_cast<std::uint32_t>(3 * r);
  }
  const std::uint32_t* const shifts = shift_table.data();
#else
  (void)loop;
#endif
  parallelChunks(parts, count, [&](std::size_t begin, std::size_t end, unsigned p) {
    // The arrays' starts and new_id as locals of the range: the SSE2 stores below
    // may alias anything, so the captured ones were loaded again after each store.
    VertexId* const corners_at = corners;
    HalfedgeId* const twins_at = twins;
    const auto new_id_of = new_id;
    std::vector<HalfedgeId>* open = boundary != nullptr ? &open_edges[p] : nullptr;
    // j: the removed triangles before t.
    std::size_t j = static_cast<std::size_t>(
        std::lower_bound(removed_at, removed_at + removed_count, begin) - removed_at);
    for (std::size_t t = begin; t < end;) {
      if (j < removed_count && removed_at[j] == t) {
        ++j;
        ++t;
        continue;
      }
      const std::size_t stop =
          std::min<std::size_t>(end, j < removed_count ? removed_at[j] : count);
      const std::size_t shift = j;
      // The run's halfedges [first, first + size): a twin among them moves by shift.
      const std::size_t first = j > 0 ? 3 * std::size_t{removed_at[j - 1]} + 3 : 0;
      const std::size_t size =
          (j < removed_count ? 3 * std::size_t{removed_at[j]} : 3 * count) - first;
      // The new twin of halfedge h's, h - 3 * shift: a twin outside the run takes
      // new_id, and lists h - 3 * shift among the open edges when it has none.
      auto remap = [&](std::size_t h) {
        const HalfedgeId twin = twins_at[h];
        if (std::size_t{twin} - first < size)
          return static_cast<HalfedgeId>(twin - 3 * shift);
        const TriangleId across = twin == INVALID_ID ? INVALID_ID : new_id_of(twin / 3);
        if (across == INVALID_ID && open != nullptr)
          open->push_back(static_cast<HalfedgeId>(h - 3 * shift));
        return across == INVALID_ID ? INVALID_ID : 3 * across + twin % 3;
      };
      // The survivors whose new place lies before the range: set aside.
      for (; t < stop && t - shift < begin; ++t) {
        Moved moved{static_cast<TriangleId>(t - shift), {}, {}};
        for (std::size_t k = 0; k < 3; ++k) {
          moved.corners[k] = corners_at[3 * t + k];
          moved.twins[k] = remap(3 * t + k);
        }
        aside[p].push_back(moved);
      }
      if (t == stop)
        continue;
      // The rest of the run moves down by shift as a block, its halfedges in order
      // (each read before its new place, at or before it, is written).
      const std::size_t h_begin = 3 * t, h_end = 3 * stop, delta = 3 * shift;
      std::size_t h = h_begin;
#if defined(PCL_VTS_COMPACTION_AVX2)
      if (avx2)
        h = moveRunAvx2(corners_at, twins_at, h, h_end, delta, first, size, shifts,
                        SHIFT_BITS, static_cast<std::uint32_t>(blocks), 3 * count,
                        remap);
#endif
#if defined(__SSE2__)
      // Four halfedges at a time: their corners, and their twins when all four lie
      // in the run (unsigned comparison of twin - first with size, through the
      // sign bit). Both arrays are fetched AHEAD entries ahead (jittered 1e6:
      // 7.3-8.0 ms against 9.2 without).
      const __m128i bias = _mm_set1_epi32(std::numeric_limits<std::int32_t>::min());
      const __m128i first4 = _mm_set1_epi32(static_cast<std::int32_t>(first));
      const __m128i size4 = _mm_xor_si128(
          bias,
          _mm_set1_epi32(static_cast<std::int32_t>(static_cast<std::uint32_t>(size))));
      const __m128i delta4 = _mm_set1_epi32(static_cast<std::int32_t>(delta));
      constexpr std::size_t AHEAD = 512;
      const std::size_t halfedge_count = 3 * count;
      for (; h + 4 <= h_end; h += 4) {
        const std::size_t ahead = std::min(h + AHEAD, halfedge_count - 1);
        __builtin_prefetch(twins_at + ahead);
        __builtin_prefetch(corners_at + ahead);
        _mm_storeu_si128(
            reinterpret_cast<__m128i*>(corners_at + h - delta),
            _mm_loadu_si128(reinterpret_cast<const __m128i*>(corners_at + h)));
        const __m128i twin4 =
            _mm_loadu_si128(reinterpret_cast<const __m128i*>(twins_at + h));
        const __m128i inside =
            _mm_cmplt_epi32(_mm_xor_si128(_mm_sub_epi32(twin4, first4), bias), size4);
        if (_mm_movemask_epi8(inside) == 0xffff) {
          _mm_storeu_si128(reinterpret_cast<__m128i*>(twins_at + h - delta),
                           _mm_sub_epi32(twin4, delta4));
          continue;
        }
        for (std::size_t k = h; k < h + 4; ++k)
          twins_at[k - delta] = remap(k);
      }
#endif
      for (; h < h_end; ++h) {
        corners_at[h - delta] = corners_at[h];
        twins_at[h - delta] = remap(h);
      }
      t = stop;
    }
  });
  for (const std::vector<Moved>& part : aside)
    for (const Moved& moved : part)
      for (std::size_t k = 0; k < 3; ++k) {
        mesh.triangles[3 * std::size_t{moved.to} + k] = moved.corners[k];
        mesh.halfedges[3 * std::size_t{moved.to} + k] = moved.twins[k];
      }
  mesh.triangles.resize(3 * kept);
  mesh.halfedges.resize(3 * kept);
  if (boundary != nullptr) {
    boundary->clear();
    for (const std::vector<HalfedgeId>& part : open_edges)
      boundary->insert(boundary->end(), part.begin(), part.end());
  }
}

std::size_t peelOutwardTriangles(const TriangleMesh& mesh,
                                 const std::vector<std::uint8_t>& flags,
                                 bool open_voids, std::vector<bool>& removed)
{
  removed.assign(mesh.triangleCount(), false);
  std::vector<TriangleId> list;
  floodOversized(
      mesh, [&](TriangleId t) { return (flags[t] & OVERSIZED) != 0; },
      floodStarts(mesh, flags, open_voids), removed, list);
  return repairPinches(mesh, list, removed);
}

Status trimOutwardTriangles(TriangleMesh& mesh, const TrimOptions& options,
                            TrimResult& result)
{
  return detail::trimOutwardTriangles(mesh, options, result, nullptr);
}

Status detail::trimOutwardTriangles(TriangleMesh& mesh, const TrimOptions& options,
                                    TrimResult& result, VertexSpacing* after,
                                    unsigned threads, ScratchBlock scratch)
{
  threads = threads > 0 ? threads : allCores();
  result = TrimResult{};
  Status status = validateTrimOptions(options);
  if (!status.ok())
    return status;
  if (mesh.halfedges.size() != mesh.triangles.size())
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "halfedges must have one entry per triangle corner");
  // With `after`, the boundary halfedges too: the trimmed mesh's when the trim
  // removes nothing, else the compaction lists them.
  std::vector<HalfedgeId> boundary;
  std::vector<double>* own_storage = detail::splitForOwn(scratch, mesh.vertexCount());
  // The own medians' place is free until ownMedians: the rows' build borrows it.
  detail::VertexRows rows(
      scratch, own_storage != nullptr
                   ? detail::ScratchBlock{own_storage->data(),
                                          mesh.vertexCount() * sizeof(double)}
                   : detail::ScratchBlock{});
  std::vector<double> scale; // the vertices' needs (classifyTriangles)
  const double edge_limit2 =
      options.max_edge > 0.0
          ? options.max_edge * options.max_edge * detail::Clearance::MARGIN
          : std::numeric_limits<double>::infinity();
  if (!rows.build(mesh, after != nullptr ? &boundary : nullptr, &scale, edge_limit2))
    return detail::checkCorners(mesh); // a corner is not a vertex id: its error
  detail::OwnStats stats;
  std::vector<double> own =
      detail::ownMedians(mesh, rows, threads, &stats, own_storage);
  // The global median's histogram is counted with the ring bounds (no pass of its
  // own over the medians).
  detail::MedianSelection selection;
  std::vector<TriangleId> starts;
  std::vector<bool> oversized = classifyTriangles(mesh, rows, own, stats, options,
                                                  threads, starts, selection, scale);
  std::vector<double>().swap(scale);
  const double global_median = detail::medianOverRows(own, rows, stats, selection);
  result.spacing = global_median;

  // The peel and the repair (peelOutwardTriangles), from the starts found.
  std::vector<bool> removed(mesh.triangleCount(), false);
  std::vector<TriangleId> list;
  floodOversized(
      mesh, [&](TriangleId t) { return oversized[t]; }, std::move(starts), removed,
      list);
  std::vector<bool>().swap(oversized);
  result.kept_to_stay_manifold = repairPinches(mesh, list, removed);
  // Only a corner of a removed triangle can be left without triangles, and only its
  // row of edges changes: it is lost when no triangle of its fan stays.
  std::vector<bool> changed(mesh.vertexCount(), false);
  std::vector<std::pair<VertexId, HalfedgeId>> corners;
  std::vector<TriangleId> dropped;
  for (const TriangleId t : list) {
    if (!removed[t])
      continue; // restored by the repair
    ++result.triangles_removed;
    dropped.push_back(t);
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
      if (!changed[mesh.triangles[e]]) {
        changed[mesh.triangles[e]] = true;
        corners.emplace_back(mesh.triangles[e], e);
      }
  }
  // The fan from a corner holds all the vertex's triangles when its row (a triangle
  // per halfedge leaving it, and one more entry for an open fan) says so; a vertex
  // with several fans (not from VTS) takes the scan after the compaction.
  // The fill's spacing (post_pass_spacing.h): the rows of the corners on the trimmed
  // mesh are their fans' kept triangles (the halfedge leaving the corner, and the
  // one entering it when the trim leaves it without twin), so their own medians are
  // measured in the same walk, before the compaction (and kept when every fan is
  // whole); and the vertices without triangles after the trim are those without
  // before and the lost ones.
  bool fans_whole = true;
  const bool measure = after != nullptr && result.triangles_removed > 0;
  std::vector<double> trimmed_own(measure ? corners.size() : 0);
  std::vector<char> lost(corners.size(), 0);
  {
    std::vector<TriangleId> fan;
    std::vector<double> lengths;
    auto length = [&](VertexId a, VertexId b) {
      const double dx = mesh.xy[a].x - mesh.xy[b].x, dy = mesh.xy[a].y - mesh.xy[b].y;
      return std::sqrt(dx * dx + dy * dy);
    };
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const auto [v, out] = corners[k];
      bool closed = false;
      fanOf(mesh, out, closed, fan);
      fans_whole =
          fans_whole && fan.size() + (closed ? 0 : 1) == rows.end(v) - rows.begin(v);
      lost[k] = 1;
      lengths.clear();
      for (const TriangleId t : fan) {
        if (removed[t])
          continue;
        lost[k] = 0;
        if (!measure)
          break;
        HalfedgeId e = 3 * t;
        while (mesh.triangles[e] != v)
          ++e;
        lengths.push_back(length(v, mesh.triangles[nextHalfedge(e)]));
        const HalfedgeId in = prevHalfedge(e), twin = mesh.halfedges[in];
        if (twin == INVALID_ID || removed[triangleOf(twin)])
          lengths.push_back(length(v, mesh.triangles[in]));
      }
      result.vertices_lost += lost[k] != 0 ? 1 : 0;
      if (measure && !lengths.empty())
        trimmed_own[k] = medianOf(lengths);
    }
  }
  std::vector<VertexId> without_triangles;
  std::vector<detail::OwnChange> own_changes;
  const bool own_measured = measure && fans_whole;
  if (own_measured)
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const VertexId v = corners[k].first;
      own_changes.push_back({own[v], trimmed_own[k], lost[k] == 0});
      own[v] = trimmed_own[k];
      if (lost[k] != 0)
        without_triangles.push_back(v);
    }
  // Each vertex's triangles in the trimmed mesh, for the fill: its row's entries (a
  // triangle per halfedge leaving it, one more per boundary halfedge entering it),
  // less the latter and its removed triangles; a count that reaches MANY_TRIANGLES
  // stays there (not trusted). The same pass lists the vertices without a row.
  std::vector<std::uint8_t> triangle_count;
  if (after != nullptr) {
    constexpr unsigned MANY = detail::MANY_TRIANGLES;
    const std::size_t n = mesh.vertexCount();
    triangle_count.resize(n);
    std::uint8_t* counts = triangle_count.data();
    rows.visitStarts([&](const auto* start) { // a loop the compiler vectorises
      for (std::size_t v = 0; v < n; ++v) {
        const std::size_t entries = start[v + 1] - start[v];
        counts[v] = static_cast<std::uint8_t>(entries < MANY ? entries : MANY);
      }
    });
    if (own_measured) // the vertices without a row: eight counts at a time
      for (std::size_t v = 0; v < n; v += 8) {
        std::uint64_t word = ~std::uint64_t{0};
        std::memcpy(&word, counts + v, std::min<std::size_t>(8, n - v));
        constexpr std::uint64_t ONES = 0x0101010101010101ull;
        if (((word - ONES) & ~word & (ONES << 7)) == 0)
          continue; // no zero byte
        for (std::size_t u = v; u < std::min(n, v + 8); ++u)
          if (counts[u] == 0)
            without_triangles.push_back(static_cast<VertexId>(u));
      }
    auto lower = [&](VertexId v) {
      if (triangle_count[v] < MANY)
        --triangle_count[v];
    };
    for (const HalfedgeId e : boundary) // the input's, before the compaction
      lower(mesh.triangles[nextHalfedge(e)]);
    for (const TriangleId t : dropped)
      for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
        lower(mesh.triangles[e]);
  }
  rows = detail::VertexRows{};
  if (result.triangles_removed > 0)
    detail::compactTriangles(mesh, dropped, threads,
                             after != nullptr ? &boundary : nullptr);
  std::vector<bool>().swap(removed);
  if (!fans_whole) {
    std::vector<bool> has_triangle(mesh.vertexCount(), false);
    for (const VertexId v : mesh.triangles)
      has_triangle[v] = true;
    result.vertices_lost = 0;
    for (const auto& [v, out] : corners)
      result.vertices_lost += has_triangle[v] ? 0 : 1;
  }

  if (after != nullptr) {
    after->own.swap(own);
    after->global_median = global_median;
    after->settled = result.triangles_removed == 0; // the input's spacing holds
    after->own_settled = fans_whole;
    after->boundary.swap(boundary);
    after->boundary_known = true;
    after->triangle_count.swap(triangle_count);
    if (!after->settled && fans_whole) {
      after->without_triangles.swap(without_triangles);
      after->own_changes.swap(own_changes);
      after->selection = std::move(selection);
    } else if (!after->settled)
      after->changed.swap(changed);
  }
  return Status::success();
}

} // namespace pcl_vts
