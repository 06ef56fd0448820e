// Checkers over mesh arrays. Each one is linear (or sorts once), never trusts the
// data it checks (ids are range-checked before use) and, on failure, names the first
// offending triangle, halfedge or vertex. Geometry goes through the exact predicates.
#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/predicates.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <tuple>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pcl_vts {
namespace {

/// Whether ok(k) holds for every k in [0, n), on `threads` threads (0 = all cores);
/// a range stops once any thread has found a failure. The verdict does not depend
/// on the split; callers find the first failure for their message sequentially.
template <typename Ok>
bool everyIndex(unsigned threads, std::size_t n, const Ok& ok)
{
  std::atomic<bool> failed{false};
  parallelRanges(threads > 0 ? threads : allCores(), n,
                 [&](std::size_t begin, std::size_t end) {
                   constexpr std::size_t STEP = 4096; // indices between flag reads
                   for (std::size_t k = begin; k < end;) {
                     if (failed.load(std::memory_order_relaxed))
                       return;
                     const std::size_t stop = std::min(end, k + STEP);
                     bool good = true;
                     for (; k < stop; ++k)
                       good &= ok(k);
                     if (!good) {
                       failed.store(true, std::memory_order_relaxed);
                       return;
                     }
                   }
                 });
  return !failed.load();
}

void setWhy(std::string* why, const std::string& text)
{
  if (why)
    *why = text;
}

std::string triangleText(const TriangleMesh& mesh, TriangleId t)
{
  std::ostringstream out;
  out << "triangle " << t << " (vertices " << mesh.triangles[3 * t] << ", "
      << mesh.triangles[3 * t + 1] << ", " << mesh.triangles[3 * t + 2] << ")";
  return out.str();
}

std::string halfedgeText(const TriangleMesh& mesh, HalfedgeId e)
{
  std::ostringstream out;
  out << "halfedge " << e << " (" << mesh.triangles[e] << " -> "
      << mesh.triangles[nextHalfedge(e)] << ", triangle " << triangleOf(e) << ")";
  return out.str();
}

/// Triangle t's corners name vertices; each of its halfedges is a boundary one or has
/// a twin in range, not itself, whose twin it is and that starts where it ends. Over
/// every triangle that is halfedgesConsistent's verdict: the twin's own test gives
/// the other end (it starts where this one ends, and this one where it ends), so the
/// pair runs both ways. The three corners at once, without a branch per halfedge (a
/// twin out of range reads the halfedge itself); corners are range-checked before
/// any use as an index.
bool triangleTwinsGood(const TriangleMesh& mesh, std::size_t t)
{
  const std::size_t n = mesh.xy.size(), count = mesh.triangles.size();
  const VertexId* corner = mesh.triangles.data() + 3 * t;
  const HalfedgeId* twins = mesh.halfedges.data();
  const VertexId a = corner[0], b = corner[1], c = corner[2];
  if (!(a < n && b < n && c < n))
    return false;
  auto good = [&](std::size_t e, VertexId to) {
    const HalfedgeId twin = twins[e];
    const std::size_t at = twin < count ? twin : e;
    return twin == INVALID_ID ||
           (twin < count && twin != e && twins[at] == e && mesh.triangles[at] == to);
  };
  // All three evaluated (no branch per edge): the bools summed.
  return int{good(3 * t, b)} + int{good(3 * t + 1, c)} + int{good(3 * t + 2, a)} == 3;
}

/// Triangles come in threes and every id names an existing vertex.
bool trianglesWellFormed(const TriangleMesh& mesh, std::string* why,
                         unsigned threads = 1)
{
  if (mesh.xy.size() != mesh.z.size()) {
    std::ostringstream out;
    out << "xy has " << mesh.xy.size() << " vertices but z has " << mesh.z.size();
    setWhy(why, out.str());
    return false;
  }
  if (mesh.triangles.size() % 3 != 0) {
    std::ostringstream out;
    out << "triangles has " << mesh.triangles.size() << " ids, not a multiple of 3";
    setWhy(why, out.str());
    return false;
  }
  if (everyIndex(threads, mesh.triangles.size(),
                 [&](std::size_t i) { return mesh.triangles[i] < mesh.xy.size(); }))
    return true;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (mesh.triangles[i] >= mesh.xy.size()) {
      std::ostringstream out;
      out << triangleText(mesh, static_cast<TriangleId>(i / 3)) << " uses vertex "
          << mesh.triangles[i] << " but the mesh has " << mesh.xy.size() << " vertices";
      setWhy(why, out.str());
      return false;
    }
  }
  return true;
}

/// One entry per halfedge: unordered vertex pair first, then the direction.
struct EdgeUse {
  std::uint64_t key;
  VertexId from;
  HalfedgeId e;
};

EdgeUse edgeUseOf(const TriangleMesh& mesh, HalfedgeId e)
{
  const VertexId from = mesh.triangles[e];
  const VertexId to = mesh.triangles[nextHalfedge(e)];
  const std::uint64_t lo = std::min(from, to);
  const std::uint64_t hi = std::max(from, to);
  return {(lo << 32) | hi, from, e};
}

void sortEdgeUses(std::vector<EdgeUse>& uses)
{
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& a, const EdgeUse& b) {
    return std::tie(a.key, a.from, a.e) < std::tie(b.key, b.from, b.e);
  });
}

std::vector<EdgeUse> sortedEdgeUses(const TriangleMesh& mesh)
{
  std::vector<EdgeUse> uses;
  uses.reserve(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    uses.push_back(edgeUseOf(mesh, static_cast<HalfedgeId>(i)));
  sortEdgeUses(uses);
  return uses;
}

/// Checks a key-sorted run of edge uses: at most two per edge, in opposite directions.
bool edgeUsesManifold(const std::vector<EdgeUse>& uses, std::string* why)
{
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].key == uses[i].key)
      ++j;
    const auto lo = static_cast<VertexId>(uses[i].key >> 32);
    const auto hi = static_cast<VertexId>(uses[i].key & 0xffffffffu);
    if (j - i > 2) {
      std::ostringstream out;
      out << "edge " << lo << "-" << hi << " is used by " << (j - i) << " triangles ("
          << triangleOf(uses[i].e) << ", " << triangleOf(uses[i + 1].e) << ", "
          << triangleOf(uses[i + 2].e) << ")";
      setWhy(why, out.str());
      return false;
    }
    if (j - i == 2 && uses[i].from == uses[i + 1].from) {
      std::ostringstream out;
      out << "edge " << uses[i].from << " -> " << (uses[i].from == lo ? hi : lo)
          << " is used in the same direction by "
          << "triangles " << triangleOf(uses[i].e) << " and "
          << triangleOf(uses[i + 1].e);
      setWhy(why, out.str());
      return false;
    }
    i = j;
  }
  return true;
}

} // namespace

bool allTrianglesCcw(const TriangleMesh& mesh, std::string* why, unsigned threads)
{
  if (!trianglesWellFormed(mesh, why, threads))
    return false;
  if (everyIndex(threads, mesh.triangleCount(), [&](std::size_t t) {
        return orient2d(mesh.xy[mesh.triangles[3 * t]],
                        mesh.xy[mesh.triangles[3 * t + 1]],
                        mesh.xy[mesh.triangles[3 * t + 2]]) == Sign::POSITIVE;
      }))
    return true;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Point2& a = mesh.xy[mesh.triangles[3 * t]];
    const Point2& b = mesh.xy[mesh.triangles[3 * t + 1]];
    const Point2& c = mesh.xy[mesh.triangles[3 * t + 2]];
    const Sign s = orient2d(a, b, c);
    if (s != Sign::POSITIVE) {
      setWhy(why,
             triangleText(mesh, static_cast<TriangleId>(t)) +
                 (s == Sign::ZERO ? " is degenerate (collinear)" : " is clockwise"));
      return false;
    }
  }
  return true;
}

bool halfedgesConsistent(const TriangleMesh& mesh, std::string* why, unsigned threads)
{
  // One pass over the triangles for the verdict (ids and twins together); the checks
  // run again in their order for the message of a failure.
  if (mesh.xy.size() == mesh.z.size() && mesh.triangles.size() % 3 == 0 &&
      mesh.halfedges.size() == mesh.triangles.size() &&
      everyIndex(threads, mesh.triangleCount(),
                 [&](std::size_t t) { return triangleTwinsGood(mesh, t); }))
    return true;
  if (!trianglesWellFormed(mesh, why, threads))
    return false;
  const std::size_t count = mesh.triangles.size();
  if (mesh.halfedges.size() != count) {
    std::ostringstream out;
    out << "halfedges has " << mesh.halfedges.size() << " entries, triangles has "
        << count;
    setWhy(why, out.str());
    return false;
  }
  auto good = [&](std::size_t i) {
    const auto e = static_cast<HalfedgeId>(i);
    const HalfedgeId twin = mesh.halfedges[e];
    return twin == INVALID_ID ||
           (twin < count && twin != e && mesh.halfedges[twin] == e &&
            mesh.triangles[twin] == mesh.triangles[nextHalfedge(e)] &&
            mesh.triangles[nextHalfedge(twin)] == mesh.triangles[e]);
  };
  if (everyIndex(threads, count, good))
    return true;
  for (std::size_t i = 0; i < count; ++i) {
    const auto e = static_cast<HalfedgeId>(i);
    const HalfedgeId twin = mesh.halfedges[e];
    if (twin == INVALID_ID)
      continue;
    if (twin < count && twin != e && mesh.halfedges[twin] == e &&
        mesh.triangles[twin] == mesh.triangles[nextHalfedge(e)] &&
        mesh.triangles[nextHalfedge(twin)] == mesh.triangles[e])
      continue; // the common case, without building a message
    std::ostringstream out;
    if (twin >= count)
      out << halfedgeText(mesh, e) << " has twin " << twin << ", out of range";
    else if (twin == e)
      out << halfedgeText(mesh, e) << " is its own twin";
    else if (mesh.halfedges[twin] != e)
      out << halfedgeText(mesh, e) << " has twin " << twin << " whose twin is "
          << mesh.halfedges[twin];
    else if (mesh.triangles[twin] != mesh.triangles[nextHalfedge(e)] ||
             mesh.triangles[nextHalfedge(twin)] != mesh.triangles[e])
      out << halfedgeText(mesh, e) << " has twin " << halfedgeText(mesh, twin)
          << " that does not run the other way";
    else
      continue;
    setWhy(why, out.str());
    return false;
  }
  return true;
}

bool isEdgeManifold(const TriangleMesh& mesh, std::string* why)
{
  // One pass counts the halfedges by the lower vertex of their edge and looks for
  // bad ids and self-loops at once; when it finds one, the checks run again in their
  // order for the message.
  const std::size_t corners = mesh.triangles.size();
  const std::size_t n = mesh.xy.size();
  bool suspect = mesh.xy.size() != mesh.z.size() || corners % 3 != 0;
  std::vector<std::uint32_t> start;
  if (!suspect) {
    start.assign(n + 1, 0);
    for (std::size_t i = 0; i < corners && !suspect; ++i) {
      const auto e = static_cast<HalfedgeId>(i);
      const VertexId from = mesh.triangles[e], to = mesh.triangles[nextHalfedge(e)];
      suspect = from >= n || from == to;
      if (!suspect) // to < n: it is the origin of another halfedge, checked there
        ++start[std::min(from, to) + std::size_t{1}];
    }
  }
  if (suspect) {
    if (!trianglesWellFormed(mesh, why))
      return false;
    for (std::size_t i = 0; i < corners; ++i) {
      const auto e = static_cast<HalfedgeId>(i);
      if (mesh.triangles[e] == mesh.triangles[nextHalfedge(e)]) {
        setWhy(why, halfedgeText(mesh, e) + " joins a vertex to itself");
        return false;
      }
    }
  }
  // Halfedges bucketed by the lower vertex of their edge (counting sort), each entry
  // the upper vertex and the direction; a bucket is fine when no key repeats (an edge
  // used three times is used twice in one direction): short buckets compare every
  // pair, long ones are sorted. A failing bucket is sorted again
  // by (upper vertex, origin, id), the order of one global sort, so the first failure
  // reported is the same.
  for (std::size_t v = 0; v < n; ++v)
    start[v + 1] += start[v];
  // (upper vertex << 1) | (runs downward).
  std::vector<std::uint64_t> bucket(mesh.triangles.size());
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      const auto e = static_cast<HalfedgeId>(i);
      const VertexId from = mesh.triangles[e], to = mesh.triangles[nextHalfedge(e)];
      const bool down = from > to;
      bucket[fill[down ? to : from]++] =
          (std::uint64_t{down ? from : to} << 1) | std::uint64_t{down};
    }
  }
  std::vector<EdgeUse> uses;
  for (std::size_t v = 0; v < n; ++v) {
    const auto first = bucket.begin() + start[v];
    const auto last = bucket.begin() + start[v + 1];
    bool repeated = false;
    if (last - first <= 16) { // most buckets: every pair compared, without a branch
      for (auto i = first; i != last; ++i)
        for (auto j = i + 1; j != last; ++j)
          repeated |= *i == *j;
    } else {
      std::sort(first, last);
      repeated = std::adjacent_find(first, last) != last;
    }
    if (!repeated)
      continue;
    uses.clear(); // the slow path, for the message
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      const auto e = static_cast<HalfedgeId>(i);
      if (std::min(mesh.triangles[e], mesh.triangles[nextHalfedge(e)]) == v)
        uses.push_back(edgeUseOf(mesh, e));
    }
    sortEdgeUses(uses);
    if (!edgeUsesManifold(uses, why))
      return false;
  }
  return true;
}

namespace {

/// No directed edge in two triangles, no edge in three (edge-manifold), given
/// consistent twins: an interior pair holds both directions of its edge, a boundary
/// halfedge its own; a directed edge is used twice (also when the edge is used three
/// times) exactly when two entries of one edge share a direction bit. Each edge is
/// listed once at its lower vertex by a counting sort, as its upper vertex less the
/// lower one (Entry: 32 bits while the ids fit 30; half the bytes of whole ids) with
/// two direction bits (1: upward, 2: downward), then each vertex's list is searched
/// for a shared direction. Per triangle, its three halfedges at once.
template <typename Entry>
bool edgesUnsharedIn(const TriangleMesh& mesh, unsigned threads)
{
  const std::size_t corners = mesh.triangles.size();
  const std::size_t n = mesh.xy.size();
  const VertexId* corner = mesh.triangles.data();
  const HalfedgeId* twins = mesh.halfedges.data();
  // start[v]: the end of v's list after the sums; the scatter moves it to its start.
  std::vector<std::uint32_t> start(n + 1, 0);
  for (std::size_t e = 0; e < corners; e += 3) {
    const VertexId v[3] = {corner[e], corner[e + 1], corner[e + 2]};
    for (std::size_t k = 0; k < 3; ++k) {
      const HalfedgeId twin = twins[e + k];
      if (twin == INVALID_ID || e + k < twin)
        ++start[std::min(v[k], v[k == 2 ? 0 : k + 1])];
    }
  }
  for (std::size_t v = 1; v <= n; ++v)
    start[v] += start[v - 1];
  std::vector<Entry> bucket(start[n]);
  for (std::size_t e = 0; e < corners; e += 3) {
    const VertexId v[3] = {corner[e], corner[e + 1], corner[e + 2]};
    for (std::size_t k = 0; k < 3; ++k) {
      const HalfedgeId twin = twins[e + k];
      if (twin != INVALID_ID && twin < e + k)
        continue;
      const VertexId from = v[k], to = v[k == 2 ? 0 : k + 1];
      const Entry directions = twin != INVALID_ID ? 3 : from < to ? 1 : 2;
      const VertexId lower = std::min(from, to);
      bucket[--start[lower]] =
          static_cast<Entry>(Entry{std::max(from, to)} - lower) << 2 | directions;
    }
  }
  return everyIndex(threads, n, [&](std::size_t v) {
    const auto first = bucket.begin() + start[v];
    const auto last = bucket.begin() + start[v + 1];
    if (last - first > 16)
      std::sort(first, last); // each list by one thread
    bool shared = false;
    for (auto i = first; i != last; ++i)
      for (auto j = i + 1; j != last && (last - first <= 16 || (*j >> 2) == (*i >> 2));
           ++j)
        shared |= (*i >> 2) == (*j >> 2) && (*i & *j & 3) != 0;
    return !shared;
  });
}

bool edgesUnshared(const TriangleMesh& mesh, unsigned threads)
{
  return mesh.xy.size() < (std::size_t{1} << 30)
             ? edgesUnsharedIn<std::uint32_t>(mesh, threads)
             : edgesUnsharedIn<std::uint64_t>(mesh, threads);
}

// The fans' proof (isValidSurfaceMesh's edge test without listing the edges).
// Given ids in range, reciprocal reversed twins and every triangle counter-clockwise
// by the exact orient2d, a directed edge a -> b used twice is a vertex a whose
// outgoing halfedges repeat a target. Around a, sigma(e) = twin(prev(e)) takes the
// outgoing halfedge e = a -> b of triangle (a, b, c) to a -> c, the next one
// counter-clockwise: the corner at a turns from b's direction to c's by an angle in
// (0, pi). sigma is one-to-one, so a's outgoing halfedges fall into chains: open
// ones, each starting at a halfedge without twin (B(a) of them), and closed cycles.
// The quadrants [0, pi/2), [pi/2, pi), [pi, 3pi/2), [3pi/2, 2pi) of a direction
// b - a come from comparing b's coordinates with a's (exact); a corner crosses (q(c -
// a) - q(b - a)) mod 4 quadrant starts (0, 1 or 2: it turns less than pi), and Q(a)
// sums them over a's corners. A chain crosses as many quadrant starts as lie in the
// half-open range of angles it sweeps: a closed cycle of w full turns exactly 4w (w >=
// 1), an open chain turning 2 pi or more at least 4. So D(a) = Q(a) + 4 B(a) is 0 (no
// corner), 4 (B = 0: one cycle of one turn; more cycles or turns give 8, 12, ...) or 4
// to 7 (B = 1 and Q <= 3: one open chain turning less than 2 pi and no cycle beside it)
// exactly when D(a) <= 7; B >= 2 gives 8 or more. When D(a) <= 7, a's halfedges point
// in directions that strictly increase within one turn: no two point the same way, so
// no two share a target. Vertices with D(a) > 7 (a pinch, a boundary corner sweeping
// about 3 pi / 2 or more, overlapping triangles) are suspects: their halfedges are
// listed and sorted, the exact test. So the edge test is one pass over the triangles
// (twins, orientation, quadrants: each corner adds its crossings and 4 if its halfedge
// has no twin to its vertex's byte) and a scan of the bytes, instead of a sort of every
// edge.

/// A vertex's fan byte D = Q + 4 B, summed without saturation: the sum of every
/// byte equals the sum of every corner's addend exactly when no byte wrapped.
using FanByte = std::uint8_t;
constexpr unsigned FAN_PROVEN = 7; // D <= 7: no two outgoing halfedges share a target
constexpr FanByte SUSPECT = 0xff;

#if defined(__SSE2__)
/// Quadrants 0-3 ([0, pi/2) ... [3pi/2, 2pi)) of a direction by its sign bits:
/// index bit 0: x > 0, bit 1: y > 0, bit 2: x < 0, bit 3: y < 0 (0 for a zero vector).
constexpr std::array<std::uint8_t, 16> quadrantTable()
{
  std::array<std::uint8_t, 16> table{};
  for (unsigned i = 0; i < 16; ++i) {
    const unsigned gx = i & 1u, gy = i >> 1 & 1u, lx = i >> 2 & 1u, ly = i >> 3 & 1u;
    const unsigned lower = ly | ((gy ^ 1u) & lx); // y < 0, or y = 0 and x < 0
    const unsigned odd = (gy & (gx ^ 1u)) | (ly & (lx ^ 1u)); // quadrant 1 or 3
    table[i] = static_cast<std::uint8_t>(2 * lower + odd);
  }
  return table;
}
constexpr std::array<std::uint8_t, 16> QUADRANT = quadrantTable();

/// The quadrant of to - from by comparing the coordinates (no difference rounded).
inline unsigned quadrant(__m128d from, __m128d to)
{
  return QUADRANT[static_cast<unsigned>(_mm_movemask_pd(_mm_cmpgt_pd(to, from)) |
                                        _mm_movemask_pd(_mm_cmplt_pd(to, from)) << 2)];
}
#else
inline unsigned quadrant(const Point2& from, const Point2& to)
{
  const unsigned gx = to.x > from.x, lx = to.x < from.x;
  const unsigned gy = to.y > from.y, ly = to.y < from.y;
  const unsigned lower = ly | ((gy ^ 1u) & lx);
  const unsigned odd = (gy & (gx ^ 1u)) | (ly & (lx ^ 1u));
  return 2 * lower + odd;
}

inline bool finite(const Point2& p)
{
  return std::abs(p.x) <= std::numeric_limits<double>::max() &&
         std::abs(p.y) <= std::numeric_limits<double>::max();
}
#endif

/// isValidSurfaceMesh's verdict (sizes already checked): one pass over the
/// triangles (twins, orientation, each corner's addend to its vertex's fan byte),
/// then the bytes, then the suspects' halfedges sorted; the counting sort of every
/// edge (edgesUnshared) only where a coordinate is not finite or a byte wrapped.
bool validByFans(const TriangleMesh& mesh, unsigned threads)
{
  const std::size_t n = mesh.xy.size(), count = mesh.triangleCount();
  const unsigned workers = usefulThreads(threads > 0 ? threads : allCores(), count);
  std::vector<FanByte> fans(n, 0);
  std::vector<std::vector<FanByte>> more(workers - 1); // the other workers' bytes
  std::vector<std::uint64_t> added(workers, 0);        // the addends, by worker
  std::atomic<bool> failed{false}, nonfinite{false};
  parallelChunks(workers, count, [&](std::size_t begin, std::size_t end, unsigned w) {
    if (w > 0)
      more[w - 1].assign(n, 0);
    FanByte* const fan = w == 0 ? fans.data() : more[w - 1].data();
    const VertexId* const corners = mesh.triangles.data();
    const HalfedgeId* const twins = mesh.halfedges.data();
    const Point2* const xy = mesh.xy.data();
    std::uint64_t sum = 0;
    bool finite_all = true;
#if defined(__SSE2__)
    __m128d unfinite = _mm_setzero_pd();
#endif
    constexpr std::size_t STEP = 4096; // triangles between flag reads
    for (std::size_t t = begin; t < end;) {
      if (failed.load(std::memory_order_relaxed))
        return;
      const std::size_t stop = std::min(end, t + STEP);
      for (; t < stop; ++t) {
        const std::size_t e = 3 * t;
        const VertexId a = corners[e], b = corners[e + 1], c = corners[e + 2];
        if (!triangleTwinsGood(mesh, t) ||
            orient2d(xy[a], xy[b], xy[c]) != Sign::POSITIVE) {
          failed.store(true, std::memory_order_relaxed);
          return;
        }
#if defined(__SSE2__)
        const __m128d pa = _mm_loadu_pd(&xy[a].x), pb = _mm_loadu_pd(&xy[b].x),
                      pc = _mm_loadu_pd(&xy[c].x);
        // p - p is 0 for a finite coordinate and NaN for an infinite or NaN one; the
        // sum stays 0 while every corner is finite (checked once, after the loop).
        unfinite = _mm_add_pd(
            unfinite, _mm_add_pd(_mm_sub_pd(pa, pa),
                                 _mm_add_pd(_mm_sub_pd(pb, pb), _mm_sub_pd(pc, pc))));
        const unsigned ab = quadrant(pa, pb), bc = quadrant(pb, pc),
                       ca = quadrant(pc, pa);
#else
        finite_all &= finite(xy[a]) && finite(xy[b]) && finite(xy[c]);
        const unsigned ab = quadrant(xy[a], xy[b]), bc = quadrant(xy[b], xy[c]),
                       ca = quadrant(xy[c], xy[a]);
#endif
        // Corner a turns from a -> b (quadrant ab) to a -> c (ca + 2: the reverse).
        const unsigned add_a = ((ca + 2 - ab) & 3u) + 4u * (twins[e] == INVALID_ID);
        const unsigned add_b = ((ab + 2 - bc) & 3u) + 4u * (twins[e + 1] == INVALID_ID);
        const unsigned add_c = ((bc + 2 - ca) & 3u) + 4u * (twins[e + 2] == INVALID_ID);
        fan[a] = static_cast<FanByte>(fan[a] + add_a);
        fan[b] = static_cast<FanByte>(fan[b] + add_b);
        fan[c] = static_cast<FanByte>(fan[c] + add_c);
        sum += add_a + add_b + add_c;
      }
    }
    added[w] = sum;
#if defined(__SSE2__)
    finite_all = _mm_movemask_pd(_mm_cmpunord_pd(unfinite, unfinite)) == 0;
#endif
    if (!finite_all)
      nonfinite.store(true, std::memory_order_relaxed);
  });
  if (failed.load())
    return false;
  if (nonfinite.load()) // no angles to argue with: every edge listed
    return edgesUnshared(mesh, threads);
  // Each vertex's D from the workers' bytes; the bytes' sum against the addends'.
  std::vector<std::uint64_t> stored(workers, 0);
  std::atomic<bool> suspects{false};
  parallelChunks(workers, n, [&](std::size_t begin, std::size_t end, unsigned w) {
    std::uint64_t sum = 0;
    bool any = false;
    for (std::size_t v = begin; v < end; ++v) {
      unsigned d = fans[v];
      for (const std::vector<FanByte>& other : more)
        d += other[v];
      sum += d;
      fans[v] = d <= FAN_PROVEN ? FanByte{0} : SUSPECT;
      any |= d > FAN_PROVEN;
    }
    stored[w] = sum;
    if (any)
      suspects.store(true, std::memory_order_relaxed);
  });
  std::uint64_t added_all = 0, stored_all = 0;
  for (unsigned w = 0; w < workers; ++w) {
    added_all += added[w];
    stored_all += stored[w];
  }
  if (stored_all != added_all) // a byte wrapped (256 or more at one vertex)
    return edgesUnshared(mesh, threads);
  if (!suspects.load())
    return true;
  // The suspects' outgoing halfedges as (origin, target): sorted, none repeated.
  std::vector<std::uint64_t> uses;
  for (std::size_t e = 0; e < 3 * count; ++e) {
    const VertexId from = mesh.triangles[e];
    if (fans[from] == SUSPECT)
      uses.push_back(std::uint64_t{from} << 32 |
                     mesh.triangles[nextHalfedge(static_cast<HalfedgeId>(e))]);
  }
  std::sort(uses.begin(), uses.end());
  return std::adjacent_find(uses.begin(), uses.end()) == uses.end();
}

} // namespace

bool isValidSurfaceMesh(const TriangleMesh& mesh, std::string* why, unsigned threads)
{
  // One pass over the triangles: ids in range, no self-loop, twins reversed,
  // counter-clockwise (the exact predicate; a degenerate triangle is not, so no
  // self-loop either), and the fans' proof that no directed edge is used twice.
  if (mesh.xy.size() == mesh.z.size() && mesh.triangles.size() % 3 == 0 &&
      mesh.halfedges.size() == mesh.triangles.size() && validByFans(mesh, threads))
    return true;
  // The checks one by one for the first failure's message (one of them fails).
  return isEdgeManifold(mesh, why) && halfedgesConsistent(mesh, why) &&
         allTrianglesCcw(mesh, why);
}

bool isDelaunay(const TriangleMesh& mesh, std::string* why)
{
  if (!halfedgesConsistent(mesh, why))
    return false;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto e = static_cast<HalfedgeId>(i);
    const HalfedgeId twin = mesh.halfedges[e];
    // Each interior edge once; boundary edges are Delaunay by definition.
    if (twin == INVALID_ID || twin < e)
      continue;
    const VertexId a = mesh.triangles[e];
    const VertexId b = mesh.triangles[nextHalfedge(e)];
    const VertexId c = mesh.triangles[prevHalfedge(e)];
    const VertexId d = mesh.triangles[prevHalfedge(twin)];
    if (incircle(mesh.xy[a], mesh.xy[b], mesh.xy[c], mesh.xy[d]) == Sign::POSITIVE) {
      std::ostringstream out;
      out << "edge " << a << "-" << b << " is not Delaunay: vertex " << d
          << " (across, " << triangleText(mesh, triangleOf(twin))
          << ") lies strictly inside the circumcircle of "
          << triangleText(mesh, triangleOf(e));
      setWhy(why, out.str());
      return false;
    }
  }
  return true;
}

bool allVerticesUsed(const TriangleMesh& mesh, std::string* why)
{
  if (!trianglesWellFormed(mesh, why))
    return false;
  std::vector<bool> used(mesh.xy.size(), false);
  for (const VertexId v : mesh.triangles)
    used[v] = true;
  const auto unused = std::find(used.begin(), used.end(), false);
  if (unused != used.end()) {
    std::ostringstream out;
    out << "vertex " << (unused - used.begin()) << " is used by no triangle";
    setWhy(why, out.str());
    return false;
  }
  return true;
}

long long eulerCharacteristic(const TriangleMesh& mesh)
{
  std::vector<VertexId> vertices(mesh.triangles);
  std::sort(vertices.begin(), vertices.end());
  const auto v = std::unique(vertices.begin(), vertices.end()) - vertices.begin();
  const std::vector<EdgeUse> uses = sortedEdgeUses(mesh);
  long long edges = 0;
  for (std::size_t i = 0; i < uses.size(); ++i)
    if (i == 0 || uses[i].key != uses[i - 1].key)
      ++edges;
  return static_cast<long long>(v) - edges +
         static_cast<long long>(mesh.triangleCount());
}

std::size_t boundaryEdgeCount(const TriangleMesh& mesh)
{
  return static_cast<std::size_t>(
      std::count(mesh.halfedges.begin(), mesh.halfedges.end(), INVALID_ID));
}

double twiceArea(const TriangleMesh& mesh)
{
  // Neumaier summation: millions of small positive terms, sum compared at 1e-9.
  double sum = 0.0;
  double compensation = 0.0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Point2& a = mesh.xy[mesh.triangles[3 * t]];
    const Point2& b = mesh.xy[mesh.triangles[3 * t + 1]];
    const Point2& c = mesh.xy[mesh.triangles[3 * t + 2]];
    const double term = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    const double next = sum + term;
    if (std::abs(sum) >= std::abs(term))
      compensation += (sum - next) + term;
    else
      compensation += (term - next) + sum;
    sum = next;
  }
  return sum + compensation;
}

} // namespace pcl_vts
