// The canonical order of the tiled path, applied to an in-memory mesh (tiled_mesh.h).
#include <pcl_vts/tiling/tiled_mesh.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace pcl_vts {

TileFrame frameOfMesh(const TriangleMesh& mesh,
                      const std::vector<std::uint8_t>* inserted)
{
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    if (inserted != nullptr && (*inserted)[v] != 0)
      continue;
    x0 = std::min(x0, mesh.xy[v].x);
    y0 = std::min(y0, mesh.xy[v].y);
    x1 = std::max(x1, mesh.xy[v].x);
    y1 = std::max(y1, mesh.xy[v].y);
  }
  return TileFrame::fromBounds(x0, y0, x1, y1);
}

namespace {

/// True when the mesh has twins for all its halfedges, mutual and joining the same two
/// vertices the other way, and no triangle repeats a vertex: then they can be carried
/// along instead of rebuilt.
bool twinsToCarry(const TriangleMesh& mesh)
{
  const std::vector<VertexId>& tri = mesh.triangles;
  const std::vector<HalfedgeId>& twin = mesh.halfedges;
  if (twin.size() != tri.size() || tri.size() % 3 != 0)
    return false;
  for (std::size_t e = 0; e < tri.size(); e += 3)
    if (tri[e] == tri[e + 1] || tri[e + 1] == tri[e + 2] || tri[e] == tri[e + 2])
      return false;
  for (std::size_t i = 0; i < tri.size(); ++i) {
    const auto e = static_cast<HalfedgeId>(i);
    const HalfedgeId t = twin[e];
    if (t != INVALID_ID &&
        (t >= tri.size() || t == e || twin[t] != e || tri[t] != tri[nextHalfedge(e)] ||
         tri[nextHalfedge(t)] != tri[e]))
      return false;
  }
  return true;
}

} // namespace

Status canonicalMesh(TriangleMesh& mesh, std::vector<std::uint8_t>* inserted)
{
  const TileFrame frame = frameOfMesh(mesh, inserted);
  const std::size_t nv = mesh.vertexCount();
  // Keys (code << 32 | vertex) by code in three counting passes of 11 bits (linear;
  // every pass reads its keys in sequence and writes 2048 streams, which the caches
  // hold), then each run of equal codes (a few points) by x, then y.
  std::vector<std::uint64_t> keys(nv);
  for (std::size_t v = 0; v < nv; ++v)
    keys[v] = std::uint64_t{frame.code(mesh.xy[v])} << 32 | v;
  {
    std::vector<std::uint64_t> scratch(nv);
    for (const int shift : {32, 43, 54}) {
      std::vector<std::size_t> start((1u << 11) + 1, 0);
      for (const std::uint64_t k : keys)
        ++start[((k >> shift) & 0x7ff) + 1];
      for (std::size_t d = 1; d < start.size(); ++d)
        start[d] += start[d - 1];
      for (const std::uint64_t k : keys)
        scratch[start[(k >> shift) & 0x7ff]++] = k;
      keys.swap(scratch);
    }
  }
  const auto vertexOf = [](std::uint64_t k) { return static_cast<VertexId>(k); };
  for (std::size_t i = 0; i < nv;) {
    std::size_t j = i + 1;
    while (j < nv && (keys[j] >> 32) == (keys[i] >> 32))
      ++j;
    if (j - i > 1)
      std::sort(keys.begin() + static_cast<std::ptrdiff_t>(i),
                keys.begin() + static_cast<std::ptrdiff_t>(j),
                [&](std::uint64_t a, std::uint64_t b) {
                  return lexLess(mesh.xy[vertexOf(a)], mesh.xy[vertexOf(b)]);
                });
    i = j;
  }
  std::vector<VertexId> rank(nv);
  TriangleMesh out;
  out.xy.resize(nv);
  out.z.resize(nv);
  std::vector<std::uint8_t> flags(inserted != nullptr ? nv : 0);
  for (std::size_t k = 0; k < nv; ++k) {
    const VertexId v = vertexOf(keys[k]);
    rank[v] = static_cast<VertexId>(k);
    out.xy[k] = mesh.xy[v];
    out.z[k] = mesh.z[v];
    if (inserted != nullptr)
      flags[k] = (*inserted)[v];
  }
  keys = {};
  // Each triangle renamed and rotated (by `turn`) to start at its smallest vertex, in
  // place; then the triangles by first vertex in one counting pass (`order`: new
  // position -> old triangle), then each vertex's few triangles by the other two.
  // With twins to carry, nothing can fail and the triangles are renamed in place;
  // without, in a copy, so that the mesh is left as it was if the rebuild fails.
  const bool carry = twinsToCarry(mesh);
  std::vector<VertexId> copy;
  if (!carry)
    copy = mesh.triangles;
  std::vector<VertexId>& tri = carry ? mesh.triangles : copy;
  const std::size_t nt = mesh.triangleCount();
  std::vector<std::uint8_t> turn(nt);
  std::vector<std::uint32_t> start(nv + 1, 0); // < 2^32: halfedge ids are 32-bit
  for (std::size_t t = 0; t < nt; ++t) {
    VertexId* g = tri.data() + 3 * t;
    const VertexId a = rank[g[0]], b = rank[g[1]], c = rank[g[2]];
    const int k = a < b ? (a < c ? 0 : 2) : (b < c ? 1 : 2);
    const VertexId r[5] = {a, b, c, a, b};
    g[0] = r[k];
    g[1] = r[k + 1];
    g[2] = r[k + 2];
    turn[t] = static_cast<std::uint8_t>(k);
    ++start[g[0] + std::size_t{1}];
  }
  rank = {};
  for (std::size_t v = 1; v <= nv; ++v)
    start[v] += start[v - 1];
  std::vector<std::uint32_t> order(nt);
  for (std::size_t t = 0; t < nt; ++t)
    order[start[tri[3 * t]]++] = static_cast<std::uint32_t>(t);
  // start[v] is now where row v + 1 begins; rows hold a few triangles: insertion sort.
  const auto less = [&](std::uint32_t p, std::uint32_t q) {
    const VertexId* a = tri.data() + 3 * std::size_t{p};
    const VertexId* b = tri.data() + 3 * std::size_t{q};
    return a[1] < b[1] || (a[1] == b[1] && a[2] < b[2]);
  };
  for (std::size_t v = 0, first = 0; v < nv; first = start[v++])
    for (std::size_t i = first + 1; i < start[v]; ++i) {
      const std::uint32_t p = order[i];
      std::size_t j = i;
      for (; j > first && less(p, order[j - 1]); --j)
        order[j] = order[j - 1];
      order[j] = p;
    }
  start = {};
  out.triangles.resize(3 * nt);
  for (std::size_t i = 0; i < nt; ++i)
    std::copy_n(tri.data() + 3 * std::size_t{order[i]}, 3,
                out.triangles.data() + 3 * i);
  tri = {};
  if (carry) {
    // The twins carried along (for an oriented 2-manifold, what a rebuild from the new
    // triangles finds, without its sort): old halfedge 3t + i is new
    // 3 where[t] + (i - turn[t]) mod 3.
    std::vector<std::uint32_t> where(nt);
    for (std::size_t i = 0; i < nt; ++i)
      where[order[i]] = static_cast<std::uint32_t>(i);
    const auto renamed = [&](HalfedgeId e) {
      const std::size_t t = e / 3;
      return static_cast<HalfedgeId>(3 * std::size_t{where[t]} +
                                     (e % 3 + 3 - turn[t]) % 3);
    };
    out.halfedges.resize(3 * nt);
    for (std::size_t i = 0; i < nt; ++i) {
      const std::size_t t = order[i];
      for (std::size_t j = 0; j < 3; ++j) {
        const HalfedgeId twin = mesh.halfedges[3 * t + (j + turn[t]) % 3];
        out.halfedges[3 * i + j] = twin == INVALID_ID ? INVALID_ID : renamed(twin);
      }
    }
  } else if (!out.rebuildHalfedges()) {
    // The vertices are renumbered one to one, so this fails only when the input is
    // not an oriented 2-manifold.
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "canonical order: the mesh is not an oriented 2-manifold (an "
                         "edge in more than two triangles or twice in one direction)");
  }
  mesh = std::move(out);
  if (inserted != nullptr)
    inserted->swap(flags);
  return Status::success();
}

} // namespace pcl_vts
