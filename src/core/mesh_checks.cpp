// Checkers over mesh arrays. Each one is linear (or sorts once), never trusts the
// data it checks (ids are range-checked before use) and, on failure, names the first
// offending triangle, halfedge or vertex. Geometry goes through the exact predicates.
#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/predicates.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <tuple>
#include <vector>

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

/// Triangle t's corners name vertices and no edge joins a vertex to itself; each of
/// its halfedges is a boundary one or has a twin in range, not itself, whose twin it
/// is and that runs the other way. The three corners at once: no remainder by 3 per
/// halfedge but for the twins'. Corners are range-checked before any use as an index.
bool triangleTwinsGood(const TriangleMesh& mesh, std::size_t t)
{
  const std::size_t n = mesh.xy.size(), count = mesh.triangles.size();
  const VertexId* corner = mesh.triangles.data() + 3 * t;
  const HalfedgeId* twins = mesh.halfedges.data();
  const VertexId a = corner[0], b = corner[1], c = corner[2];
  if (!(a < n && b < n && c < n))
    return false;
  auto good = [&](std::size_t e, VertexId from, VertexId to) {
    const HalfedgeId twin = twins[e];
    return twin == INVALID_ID ||
           (twin < count && twin != e && twins[twin] == e &&
            mesh.triangles[twin] == to && mesh.triangles[nextHalfedge(twin)] == from);
  };
  // All three evaluated (no branch per edge): the bools summed.
  return int{good(3 * t, a, b)} + int{good(3 * t + 1, b, c)} +
             int{good(3 * t + 2, c, a)} ==
         3;
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

} // namespace

bool isValidSurfaceMesh(const TriangleMesh& mesh, std::string* why, unsigned threads)
{
  auto fast = [&] {
    // One pass over the triangles: ids in range, no self-loop, twins reversed,
    // counter-clockwise (the exact predicate).
    if (mesh.xy.size() != mesh.z.size() || mesh.triangles.size() % 3 != 0 ||
        mesh.halfedges.size() != mesh.triangles.size())
      return false;
    if (!everyIndex(threads, mesh.triangleCount(), [&](std::size_t t) {
          if (!triangleTwinsGood(mesh, t))
            return false;
          const VertexId* corner = mesh.triangles.data() + 3 * t;
          return orient2d(mesh.xy[corner[0]], mesh.xy[corner[1]], mesh.xy[corner[2]]) ==
                 Sign::POSITIVE; // also no self-loop: a degenerate triangle is not
        }))
      return false;
    return edgesUnshared(mesh, threads);
  };
  if (fast())
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
