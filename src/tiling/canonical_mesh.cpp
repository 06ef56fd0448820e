// The canonical order of the tiled path, applied to an in-memory mesh (tiled_mesh.h).
#include "../core/release_memory.h"

#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/tiling/tiled_mesh.h>

#include <algorithm>
#include <array>
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

/// What one pass over the triangles finds: whether every corner names a vertex, and
/// whether the twins can be carried along instead of rebuilt (twins for all the
/// halfedges, mutual and joining the same two vertices the other way, no triangle
/// repeating a vertex). Without a branch per halfedge: each twin in range, not the
/// halfedge itself, naming it back and starting where it ends (the twin's own test
/// gives the other end: the pair runs both ways).
struct TriangleScan {
  bool corners_valid = true;
  bool twins_to_carry = true;
};

TriangleScan scanTriangles(const TriangleMesh& mesh, unsigned threads)
{
  const std::vector<VertexId>& tri = mesh.triangles;
  const std::vector<HalfedgeId>& twin = mesh.halfedges;
  const std::size_t count = tri.size(), nv = mesh.vertexCount();
  const bool twins_given = twin.size() == count;
  const auto good = [&](std::size_t e, VertexId to) {
    const HalfedgeId t = twin[e];
    const std::size_t at = t < count ? t : e; // read in range either way
    return t == INVALID_ID || (t < count && t != e && twin[at] == e && tri[at] == to);
  };
  const unsigned chunks = usefulThreads(threads, count / 3);
  std::vector<TriangleScan> found(chunks);
  parallelChunks(
      chunks, count / 3, [&](std::size_t begin, std::size_t end, unsigned chunk) {
        bool valid = true, carry = twins_given;
        for (std::size_t e = 3 * begin; e < 3 * end; e += 3) {
          const VertexId a = tri[e], b = tri[e + 1], c = tri[e + 2];
          valid &= int{a < nv} + int{b < nv} + int{c < nv} == 3;
          if (twins_given)
            carry &= int{a != b} + int{b != c} + int{a != c} + int{good(e, b)} +
                         int{good(e + 1, c)} + int{good(e + 2, a)} ==
                     6;
        }
        found[chunk] = {valid, carry};
      });
  TriangleScan all;
  for (const TriangleScan& part : found) {
    all.corners_valid &= part.corners_valid;
    all.twins_to_carry &= part.twins_to_carry;
  }
  all.corners_valid &= count % 3 == 0;
  return all;
}

} // namespace

Status canonicalMesh(TriangleMesh& mesh, std::vector<std::uint8_t>* inserted,
                     unsigned threads)
{
  // Every pass gives the arrays of one thread on any number: each index is written by
  // one thread, and the counting passes are stable (each chunk scatters from offsets
  // past the same digit's keys of the chunks before it).
  threads = std::max(1u, threads);
  const TileFrame frame = frameOfMesh(mesh, inserted);
  const std::size_t nv = mesh.vertexCount();
  // Keys (code << 32 | vertex) by code in three counting passes of 11 bits (linear;
  // every pass reads its keys in sequence and writes 2048 streams, which the caches
  // hold), then each run of equal codes (a few points) by x, then y.
  // The three passes' counts are taken with the keys (TileFrame::code is inline: no
  // call into the library a vertex); on several chunks the later passes count their
  // chunks again.
  constexpr std::size_t DIGITS = (1u << 11) + 1;
  const unsigned chunks = usefulThreads(threads, nv);
  // counts[c]: chunk c's keys by digit, the three passes' after one another (+1: the
  // offsets are summed in place).
  std::vector<std::array<std::size_t, 3 * DIGITS>> counts(chunks);
  std::vector<std::uint64_t> keys;
  detail::fillPopulated(keys, nv);
  parallelChunks(chunks, nv, [&](std::size_t begin, std::size_t end, unsigned c) {
    std::size_t* const count = counts[c].data();
    std::fill(count, count + 3 * DIGITS, std::size_t{0});
    for (std::size_t v = begin; v < end; ++v) {
      const std::uint32_t code = frame.code(mesh.xy[v]);
      keys[v] = std::uint64_t{code} << 32 | v;
      ++count[(code & 0x7ff) + 1];
      ++count[DIGITS + ((code >> 11) & 0x7ff) + 1];
      ++count[2 * DIGITS + (code >> 22) + 1];
    }
  });
  {
    std::vector<std::uint64_t> scratch;
    detail::fillPopulated(scratch, nv);
    for (const int pass : {0, 1, 2}) {
      const int shift = 32 + 11 * pass;
      const auto digit = [shift](std::uint64_t k) { return (k >> shift) & 0x7ff; };
      const std::size_t at = pass * DIGITS;
      // A later pass's chunks hold other keys than the first's: counted again (one
      // chunk: the whole array's counts, the same in any order).
      if (pass > 0 && chunks > 1)
        parallelChunks(chunks, nv, [&](std::size_t begin, std::size_t end, unsigned c) {
          std::size_t* const count = counts[c].data() + at;
          std::fill(count, count + DIGITS, std::size_t{0});
          for (std::size_t i = begin; i < end; ++i)
            ++count[digit(keys[i]) + 1];
        });
      std::size_t sum = 0; // digit d's offset in chunk c: the keys before it
      for (std::size_t d = 1; d < DIGITS; ++d)
        for (unsigned c = 0; c < chunks; ++c) {
          const std::size_t here = counts[c][at + d];
          counts[c][at + d - 1] = sum;
          sum += here;
        }
      const std::uint64_t* const from = keys.data();
      std::uint64_t* const to = scratch.data();
      parallelChunks(chunks, nv, [&](std::size_t begin, std::size_t end, unsigned c) {
        std::size_t* const next = counts[c].data() + at;
        for (std::size_t i = begin; i < end; ++i) {
          const std::uint64_t k = from[i];
          to[next[digit(k)]++] = k;
        }
      });
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
  detail::fillPopulated(out.xy, nv);
  detail::fillPopulated(out.z, nv);
  std::vector<std::uint8_t> flags(inserted != nullptr ? nv : 0);
  { // raw pointers: the flags' byte stores would make every vector's be read again
    const std::uint64_t* const key = keys.data();
    VertexId* const rank_of = rank.data();
    Point2* const xy = out.xy.data();
    double* const z = out.z.data();
    const Point2* const xy_in = mesh.xy.data();
    const double* const z_in = mesh.z.data();
    std::uint8_t* const flag = flags.data();
    const std::uint8_t* const flag_in =
        inserted != nullptr ? inserted->data() : nullptr;
    parallelFor(threads, nv, [=](std::size_t k) {
      const VertexId v = vertexOf(key[k]);
      rank_of[v] = static_cast<VertexId>(k);
      xy[k] = xy_in[v];
      z[k] = z_in[v];
      if (flag_in != nullptr)
        flag[k] = flag_in[v];
    });
  }
  keys = {};
  // Each triangle renamed and rotated (by `turn`) to start at its smallest vertex, in
  // place; then the triangles by first vertex in one counting pass (`order`: new
  // position -> old triangle), then each vertex's few triangles by the other two.
  // With twins to carry, nothing can fail and the triangles are renamed in place;
  // without, in a copy, so that the mesh is left as it was if the rebuild fails.
  const TriangleScan scan = scanTriangles(mesh, threads);
  if (!scan.corners_valid)
    return Status::error(
        StatusCode::INVALID_PARAMETER,
        "canonical order: a triangle corner is not a vertex id (or the "
        "corners are not in threes)");
  const bool carry = scan.twins_to_carry;
  std::vector<VertexId> copy;
  if (!carry)
    copy = mesh.triangles;
  std::vector<VertexId>& tri = carry ? mesh.triangles : copy;
  const std::size_t nt = mesh.triangleCount();
  std::vector<std::uint8_t> turn(nt);
  std::vector<std::uint32_t> start(nv + 1, 0); // < 2^32: halfedge ids are 32-bit
  const auto rename = [&](std::size_t t) {
    VertexId* g = tri.data() + 3 * t;
    const VertexId a = rank[g[0]], b = rank[g[1]], c = rank[g[2]];
    const int k = a < b ? (a < c ? 0 : 2) : (b < c ? 1 : 2);
    const VertexId r[5] = {a, b, c, a, b};
    g[0] = r[k];
    g[1] = r[k + 1];
    g[2] = r[k + 2];
    turn[t] = static_cast<std::uint8_t>(k);
    return g[0];
  };
  if (usefulThreads(threads, nt) == 1) { // the count in the same pass
    for (std::size_t t = 0; t < nt; ++t)
      ++start[rename(t) + std::size_t{1}];
  } else {
    parallelFor(threads, nt, rename);
    for (std::size_t t = 0; t < nt; ++t)
      ++start[tri[3 * t] + std::size_t{1}];
  }
  rank = {};
  for (std::size_t v = 1; v <= nv; ++v)
    start[v] += start[v - 1];
  // Each triangle's other two corners and its old id scattered into its first
  // corner's row, three ids an entry (the rows then sorted without reading the
  // triangles again); then the triangles written out in row order, in sequence, into
  // the renamed triangles' array (no longer read), and the twins into the rows' (of
  // the same size, read by then): no fresh pages for the output.
  std::vector<std::uint32_t> rows;
  detail::fillPopulated(rows, 3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const VertexId* g = tri.data() + 3 * t;
    std::uint32_t* entry = rows.data() + 3 * std::size_t{start[g[0]]++};
    entry[0] = g[1];
    entry[1] = g[2];
    entry[2] = static_cast<std::uint32_t>(t);
  }
  // start[v] is now where row v + 1 begins; rows hold a few triangles: insertion sort.
  const auto less = [](const std::array<std::uint32_t, 3>& p, const std::uint32_t* q) {
    return p[0] < q[0] || (p[0] == q[0] && p[1] < q[1]);
  };
  parallelRanges(threads, nv, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin, first = v == 0 ? 0 : start[v - 1]; v < end;
         first = start[v++])
      for (std::size_t i = first + 1; i < start[v]; ++i) {
        const std::array<std::uint32_t, 3> p = {rows[3 * i], rows[3 * i + 1],
                                                rows[3 * i + 2]};
        std::size_t j = i;
        for (; j > first && less(p, rows.data() + 3 * (j - 1)); --j)
          std::copy_n(rows.data() + 3 * (j - 1), 3, rows.data() + 3 * j);
        std::copy_n(p.data(), 3, rows.data() + 3 * j);
      }
  });
  // Old triangle t is new triangle where[t]; old halfedge 3t + i is new
  // 3 where[t] + (i - turn[t]) mod 3.
  std::vector<std::uint32_t> where;
  detail::fillPopulated(where, nt);
  out.triangles = std::move(tri);
  parallelRanges(threads, nv, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin, i = v == 0 ? 0 : start[v - 1]; v < end; ++v)
      for (; i < start[v]; ++i) {
        out.triangles[3 * i] = static_cast<VertexId>(v);
        out.triangles[3 * i + 1] = rows[3 * i];
        out.triangles[3 * i + 2] = rows[3 * i + 1];
        where[rows[3 * i + 2]] = static_cast<std::uint32_t>(i);
      }
  });
  start = {};
  if (carry) {
    // The twins carried along (for an oriented 2-manifold, what a rebuild from the new
    // triangles finds, without its sort), written at their new places in the old
    // order: the reads are in sequence and a twin's triangle is a neighbour (nearby
    // in the old order), only the writes jump.
    const auto renamed = [&](HalfedgeId e) {
      const std::size_t t = e / 3;
      return static_cast<HalfedgeId>(3 * std::size_t{where[t]} +
                                     (e % 3 + 3 - turn[t]) % 3);
    };
    out.halfedges = std::move(rows);
    parallelFor(threads, nt, [&](std::size_t t) {
      const std::size_t base = 3 * std::size_t{where[t]};
      const unsigned k = turn[t];
      for (unsigned i = 0; i < 3; ++i) {
        const HalfedgeId twin = mesh.halfedges[3 * t + i];
        out.halfedges[base + (i + 3 - k) % 3] =
            twin == INVALID_ID ? INVALID_ID : renamed(twin);
      }
    });
  }
  rows = {};
  where = {};
  turn = {};
  if (!carry && !out.rebuildHalfedges()) {
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
