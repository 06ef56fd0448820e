// Halo growth until the tile's stars are proven (tile_triangulation.h).
#include "tile_triangulation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace pcl_vts {
namespace {

/// Blocks one triangle's disk or one hull edge may add in one round before only the
/// first reached are kept: as many as the tile owns, and at least this many.
constexpr std::size_t MIN_BLOCKS_PER_ROUND = 64;

/// Unloaded occupied blocks in the block rectangle around `blocks`, widened by
/// `margin` blocks.
void ringAround(const std::vector<std::uint32_t>& blocks, int level,
                const KnownSpace& space, const LoadedBlocks& flags,
                std::vector<std::uint32_t>& out, std::uint32_t margin = 1)
{
  std::uint32_t x0 = ~0u, y0 = ~0u, x1 = 0, y1 = 0;
  for (std::uint32_t b : blocks) {
    const std::uint32_t x = gatherBits(b), y = gatherBits(b >> 1);
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
  }
  const std::uint32_t last = (1u << level) - 1;
  x0 = x0 > margin ? x0 - margin : 0;
  y0 = y0 > margin ? y0 - margin : 0;
  x1 = std::min(x1 + std::min(margin, last), last);
  y1 = std::min(y1 + std::min(margin, last), last);
  for (std::uint32_t y = y0; y <= y1; ++y)
    for (std::uint32_t x = x0; x <= x1; ++x) {
      const std::uint32_t b = spreadBits(x) | (spreadBits(y) << 1);
      if (space.occupied(b) && !flags[b])
        out.push_back(b);
    }
}

/// Adds `more` (any order, repeats allowed) to the sorted list `loaded`.
void load(std::vector<std::uint32_t>& more, std::vector<std::uint32_t>& loaded,
          LoadedBlocks& flags)
{
  std::sort(more.begin(), more.end());
  more.erase(std::unique(more.begin(), more.end()), more.end());
  for (std::uint32_t b : more)
    flags[b] = 1;
  std::vector<std::uint32_t> merged;
  merged.reserve(loaded.size() + more.size());
  std::merge(loaded.begin(), loaded.end(), more.begin(), more.end(),
             std::back_inserter(merged));
  loaded.swap(merged);
  more.clear();
}

/// Keeps, of hits[first..], the `keep` blocks that a circle grown from the edge pq
/// to its right (away from the triangle or the hull it bounds) reaches first:
/// the mediatrix search of the triangulation itself, on block centres. Those hold the
/// points that replace the triangle (across a void, the partner edge), where the
/// blocks nearest to it would only extend a straight data edge. Blocks behind pq come
/// after, by distance. A ranking only: the next round checks the disk again.
void keepFirstReached(const KnownSpace& space, const Point2& p, const Point2& q,
                      std::size_t keep, std::size_t first,
                      std::vector<std::uint32_t>& hits)
{
  if (hits.size() - first <= keep)
    return;
  const double longest = (q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y);
  const Point2 mid{0.5 * (p.x + q.x), 0.5 * (p.y + q.y)};
  const double length = std::sqrt(longest);
  const Point2 normal{(q.y - p.y) / length, (p.x - q.x) / length}; // right of p -> q
  const auto score = [&](std::uint32_t block) {
    const Rect& box = space.bounds(block);
    const double cx = 0.5 * (box.x0 + box.x1) - mid.x,
                 cy = 0.5 * (box.y0 + box.y1) - mid.y;
    const double ahead = cx * normal.x + cy * normal.y;
    const double reach = cx * cx + cy * cy - 0.25 * longest;
    return ahead > 0 ? reach / (2 * ahead) : 1e300 * 0.5 + std::sqrt(cx * cx + cy * cy);
  };
  std::vector<std::pair<double, std::uint32_t>> ranked;
  ranked.reserve(hits.size() - first);
  for (std::size_t h = first; h < hits.size(); ++h)
    ranked.emplace_back(score(hits[h]), hits[h]);
  std::partial_sort(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(keep),
                    ranked.end());
  hits.resize(first);
  for (std::size_t h = 0; h < keep; ++h)
    hits.push_back(ranked[h].second);
}

/// Distance from a box to the segment a-b, from below (centre distance less the
/// half diagonal): a ranking, not a test.
double roughDistance(const Rect& box, const Point2& a, const Point2& b)
{
  const Point2 c{0.5 * (box.x0 + box.x1), 0.5 * (box.y0 + box.y1)};
  const double ex = b.x - a.x, ey = b.y - a.y, length2 = ex * ex + ey * ey;
  const double t =
      length2 > 0
          ? std::clamp(((c.x - a.x) * ex + (c.y - a.y) * ey) / length2, 0.0, 1.0)
          : 0.0;
  const double dx = a.x + t * ex - c.x, dy = a.y + t * ey - c.y;
  return std::sqrt(dx * dx + dy * dy) -
         0.5 * std::hypot(box.x1 - box.x0, box.y1 - box.y0);
}

/// Unknown blocks with points beyond the hull edge a -> b, but only those near it
/// (within four edge lengths or blocks): along a nearly straight data boundary the
/// line reaches points kilometres away, while the triangles that replace the edge are
/// decided by the nearest. When none is near, or too many are (across a void, the
/// other side), those a circle grown from the edge reaches first. Progress is kept
/// (some block always comes); the next round checks again.
void nearestRightOf(const KnownSpace& space, const Point2& a, const Point2& b,
                    const LoadedBlocks& flags, double block_side, std::size_t cap,
                    std::vector<std::uint32_t>& hits)
{
  const std::size_t first = hits.size();
  space.unknownRightOf(a, b, flags, hits);
  if (hits.size() == first)
    return;
  const double reach = 4.0 * std::max(std::hypot(b.x - a.x, b.y - a.y), block_side);
  const auto near_end =
      std::stable_partition(hits.begin() + static_cast<std::ptrdiff_t>(first),
                            hits.end(), [&](std::uint32_t block) {
                              return roughDistance(space.bounds(block), a, b) <= reach;
                            });
  if (near_end != hits.begin() + static_cast<std::ptrdiff_t>(first)) {
    hits.erase(near_end, hits.end());
    keepFirstReached(space, a, b, cap, first, hits);
  } else {
    keepFirstReached(space, a, b, 1, first, hits);
  }
}

/// The corner k whose edge k -> k+1 is the longest of the triangle (the first of
/// equals); out: its squared length.
int longestEdge(const Point2* corners, double& squared)
{
  int k = 0;
  squared = -1;
  for (int e = 0; e < 3; ++e) {
    const Point2& a = corners[e];
    const Point2& b = corners[(e + 1) % 3];
    const double l2 = (b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y);
    if (l2 > squared) {
      squared = l2;
      k = e;
    }
  }
  return k;
}

/// A triangle too flat for floating point to bound its circumdisk (three nearly
/// collinear points along a straight data edge, common where coordinates are
/// quantised). When its angle opposite the longest edge p -> q (CCW order) is surely
/// obtuse, the disk lies in the open half-plane right of p -> q (away from the third
/// vertex) and in the disk on diameter pq (the arc on the vertex's side sees pq under
/// an obtuse angle). Both are asked for, the half-plane nearest first as for a hull
/// edge, instead of every unknown block. False when the angle is not surely obtuse.
bool flatTriangleUnknowns(const Point2* v, const KnownSpace& space,
                          const LoadedBlocks& flags, double block_side, std::size_t cap,
                          std::vector<std::uint32_t>& hits)
{
  double longest = 0;
  const int k = longestEdge(v, longest);
  const Point2& p = v[k];
  const Point2& q = v[(k + 1) % 3];
  const Point2& m = v[(k + 2) % 3];
  const double ax = p.x - m.x, ay = p.y - m.y, bx = q.x - m.x, by = q.y - m.y;
  const double la = std::hypot(ax, ay), lb = std::hypot(bx, by);
  // Rounding of the differences (an ulp of the coordinates) and of the products.
  const double magnitude = std::fabs(p.x) + std::fabs(p.y) + std::fabs(q.x) +
                           std::fabs(q.y) + std::fabs(m.x) + std::fabs(m.y);
  const double tolerance = 1e-6 * la * lb + 1e-15 * magnitude * (la + lb);
  if (!(ax * bx + ay * by < -tolerance))
    return false;
  CircumdiskBound thales;
  thales.center = {0.5 * (p.x + q.x), 0.5 * (p.y + q.y)};
  thales.radius = 0.5 * std::sqrt(longest) * (1 + 1e-9) + 1e-15 * magnitude;
  space.unknownInDisk(thales, flags, hits);
  nearestRightOf(space, p, q, flags, block_side, cap, hits);
  return true;
}

/// Disks up to this radius (in blocks) are loaded three blocks wider than they are.
constexpr double ENLARGED_RADIUS_BLOCKS = 16.0;

/// keepFirstReached from the triangle's longest edge (CCW order).
void keepFirstReachedFrom(const KnownSpace& space, const Point2* corners,
                          std::size_t cap, std::size_t first,
                          std::vector<std::uint32_t>& hits)
{
  double longest = 0;
  const int k = longestEdge(corners, longest);
  keepFirstReached(space, corners[k], corners[(k + 1) % 3], cap, first, hits);
}

/// Unknown blocks that the stars of the vertices to check (and their hull edges)
/// meet. A vertex to check whose star meets one is marked in `failed`.
void unprovenStars(const TriangleMesh& mesh, const std::vector<std::uint8_t>& check,
                   const KnownSpace& space, const LoadedBlocks& flags,
                   double block_side, std::size_t cap, std::vector<std::uint32_t>& hits,
                   std::vector<std::uint8_t>& failed)
{
  const std::size_t nt = mesh.triangleCount();
  for (std::size_t t = 0; t < nt; ++t) {
    const VertexId* v = &mesh.triangles[3 * t];
    if (!check[v[0]] && !check[v[1]] && !check[v[2]])
      continue;
    CircumdiskBound disk = boundCircumdisk(mesh.xy[v[0]], mesh.xy[v[1]], mesh.xy[v[2]]);
    const std::size_t before = hits.size();
    const Point2 corners[3] = {mesh.xy[v[0]], mesh.xy[v[1]], mesh.xy[v[2]]};
    if (!disk.unbounded ||
        !flatTriangleUnknowns(corners, space, flags, block_side, cap, hits))
      space.unknownInDisk(disk, flags, hits);
    if (hits.size() - before > cap) {
      // A disk over many unknown blocks belongs to a triangle that the nearest of them
      // will replace (a flat triangle along a straight data edge, a sliver across a
      // void): load those first, and let the next round ask again.
      keepFirstReachedFrom(space, corners, cap, before, hits);
    } else if (hits.size() != before && !disk.unbounded &&
               disk.radius <= ENLARGED_RADIUS_BLOCKS * block_side) {
      // Not proven: the points that will settle it lie around this disk, so load a
      // wider disk now (by up to three blocks) rather than one ring per round. Not for
      // a large disk: three blocks more along its rim would sweep a band the length of
      // a data edge (a flat triangle along a straight edge has a disk of kilometres).
      hits.resize(before);
      disk.radius += std::min(disk.radius, 3 * block_side);
      space.unknownInDisk(disk, flags, hits);
    }
    if (hits.size() != before)
      for (int k = 0; k < 3; ++k)
        failed[v[k]] = 1;
    for (int k = 0; k < 3; ++k) {
      const std::size_t e = 3 * t + static_cast<std::size_t>(k);
      const VertexId a = mesh.triangles[e],
                     b = mesh.triangles[nextHalfedge(static_cast<HalfedgeId>(e))];
      if (mesh.halfedges[e] == INVALID_ID && (check[a] || check[b])) {
        const std::size_t at = hits.size();
        nearestRightOf(space, mesh.xy[a], mesh.xy[b], flags, block_side, cap, hits);
        if (hits.size() != at)
          failed[a] = failed[b] = 1;
      }
    }
  }
}

/// Occupied blocks whose code cells may meet the rectangle [x0, x1] x [y0, y1]
/// widened by `margin` blocks, appended to `out` (column() is monotone, so every
/// point inside the rectangle lies in one of them).
void blocksInRect(const TileFrame& frame, const KnownSpace& space, double x0, double y0,
                  double x1, double y1, std::uint32_t margin,
                  std::vector<std::uint32_t>& out)
{
  const int shift = TileFrame::CODE_LEVEL - space.level();
  const std::uint32_t last = (1u << space.level()) - 1;
  const std::uint32_t bx0 = frame.column(x0) >> shift, bx1 = frame.column(x1) >> shift;
  const std::uint32_t by0 = frame.row(y0) >> shift, by1 = frame.row(y1) >> shift;
  const std::uint32_t cx0 = bx0 > margin ? bx0 - margin : 0,
                      cy0 = by0 > margin ? by0 - margin : 0;
  const std::uint32_t cx1 = std::min(bx1 + margin, last),
                      cy1 = std::min(by1 + margin, last);
  for (std::uint32_t y = cy0; y <= cy1; ++y)
    for (std::uint32_t x = cx0; x <= cx1; ++x) {
      const std::uint32_t b = spreadBits(x) | (spreadBits(y) << 1);
      if (space.occupied(b))
        out.push_back(b);
    }
}

/// The blocks the next round triangulates around the vertices still unproven: those
/// under the circumdisks of their triangles (or the triangles themselves, for a disk
/// too large or unbounded; their hull edges are edges of those), one block wider.
/// Where the points that will settle them are beyond, the unknown blocks that the
/// checks met bring them.
void windowsAround(const TriangleMesh& mesh, const std::vector<std::uint8_t>& unproven,
                   const TileFrame& frame, const KnownSpace& space, double block_side,
                   std::vector<std::uint32_t>& out)
{
  const std::size_t nt = mesh.triangleCount();
  for (std::size_t t = 0; t < nt; ++t) {
    const VertexId* v = &mesh.triangles[3 * t];
    if (!unproven[v[0]] && !unproven[v[1]] && !unproven[v[2]])
      continue;
    const Point2 &a = mesh.xy[v[0]], &b = mesh.xy[v[1]], &c = mesh.xy[v[2]];
    const CircumdiskBound disk = boundCircumdisk(a, b, c);
    if (!disk.unbounded && disk.radius <= ENLARGED_RADIUS_BLOCKS * block_side)
      blocksInRect(frame, space, disk.center.x - disk.radius,
                   disk.center.y - disk.radius, disk.center.x + disk.radius,
                   disk.center.y + disk.radius, 1, out);
    else
      blocksInRect(frame, space, std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}),
                   std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), 1, out);
  }
}

} // namespace

Status triangulateTile(const TileContext& context, std::uint32_t tile,
                       LoadedBlocks& flags, TileResult& result)
{
  const TileFrame& frame = *context.frame;
  const BlockStore& store = *context.store;
  const KnownSpace& space = *context.space;
  const int tile_level = store.tileLevel(), block_level = store.blockLevel();
  const int shift = 2 * (block_level - tile_level);
  const double block_side = frame.side / (1u << block_level);
  result = TileResult{};

  // The tile's vertices have the global ids [tile_first, tile_first + tile_vertices).
  const std::vector<std::uint64_t>& first = *context.block_first_vertex;
  const std::uint32_t first_block = tile << shift, end_block = (tile + 1) << shift;
  const std::uint64_t tile_first = first[first_block];
  std::uint64_t tile_vertices = 0;
  std::vector<std::uint32_t> loaded, more;
  for (std::uint32_t b = first_block; b < end_block; ++b)
    if (space.occupied(b)) {
      more.push_back(b);
      tile_vertices += store.blockDistinct()[b];
    }
  const std::size_t cap = std::max(MIN_BLOCKS_PER_ROUND, more.size());
  const std::vector<std::uint32_t> own = more;
  ringAround(own, block_level, space, flags, more);
  load(more, loaded, flags);

  // Each round triangulates the loaded blocks and proves the stars of the tile's
  // vertices not proven yet; a proven vertex gives its owned triangles (those whose
  // smallest vertex it is) at once. The first round loads the tile and a ring; the
  // next ones only the blocks around the vertices left and the unknown blocks their
  // stars met, so a few triangles across a void do not re-mesh the whole tile.
  std::vector<std::uint8_t> proven(tile_vertices, 0);
  std::uint64_t proven_count = 0;
  std::vector<double> xyz;
  VtsResult mesh;
  std::vector<std::uint32_t> code, global, window;
  std::vector<std::uint8_t> check, failed;
  std::vector<VertexId> order;
  std::vector<std::size_t> block_start;
  std::vector<std::array<std::uint32_t, 3>> owned;
  Status status;
  for (;;) {
    ++result.rounds;
    xyz.clear();
    block_start.clear();
    for (std::uint32_t b : loaded) {
      block_start.push_back(xyz.size() / 3);
      if (!(status = store.readBlock(b, xyz)).ok())
        break;
    }
    block_start.push_back(xyz.size() / 3);
    if (status.ok())
      status = runVtsPipeline(xyz.data(), xyz.size() / 3, context.options, mesh);
    if (!status.ok()) {
      // Too few or collinear points: widen, unless nothing is left to load.
      if (status.code != StatusCode::EMPTY_INPUT &&
          status.code != StatusCode::TOO_FEW_POINTS &&
          status.code != StatusCode::ALL_COLLINEAR)
        break;
      // The nearest other points may be far: widen until some are found.
      for (std::uint32_t margin = 1; more.empty() && margin < (2u << block_level);
           margin *= 2)
        ringAround(loaded, block_level, space, flags, more, margin);
      if (more.empty())
        break;
      load(more, loaded, flags);
      continue;
    }
    result.points_loaded =
        std::max<std::uint64_t>(result.points_loaded, xyz.size() / 3);
    const TriangleMesh& m = mesh.mesh;
    const std::size_t nv = m.vertexCount();

    // Global ids: canonical rank inside each loaded (hence complete) block. The
    // blocks were read in Morton order, so sorting each block's vertices gives the
    // canonical order of all.
    code.resize(nv);
    global.resize(nv);
    order.clear();
    for (std::size_t j = 0; j < loaded.size() && status.ok(); ++j) {
      const std::size_t group = order.size();
      for (std::size_t i = block_start[j]; i < block_start[j + 1]; ++i)
        if (mesh.input_to_vertex[i] != INVALID_ID) // the store holds finite points
          order.push_back(mesh.input_to_vertex[i]);
      const auto begin = order.begin() + static_cast<std::ptrdiff_t>(group);
      std::sort(begin, order.end());
      order.erase(std::unique(begin, order.end()), order.end());
      for (auto v = begin; v != order.end(); ++v)
        code[*v] = frame.code(m.xy[*v]);
      std::sort(begin, order.end(), [&](VertexId a, VertexId b) {
        return canonicalLess(code[a], m.xy[a], code[b], m.xy[b]);
      });
      const std::uint32_t block = loaded[j];
      const std::size_t distinct = order.size() - group;
      if (distinct == 0 || distinct != store.blockDistinct()[block] ||
          TileFrame::nodeOf(code[*begin], block_level) != block ||
          TileFrame::nodeOf(code[order.back()], block_level) != block) {
        status = Status::error(
            StatusCode::INTERNAL_ERROR,
            "tile " + std::to_string(tile) + ": block " + std::to_string(block) +
                " has " + std::to_string(distinct) + " vertices, its index says " +
                std::to_string(store.blockDistinct()[block]));
        break;
      }
      for (std::size_t k = group; k < order.size(); ++k)
        global[order[k]] = static_cast<std::uint32_t>(first[block] + (k - group));
    }
    if (status.ok() && order.size() != nv)
      status = Status::error(StatusCode::INTERNAL_ERROR,
                             "tile " + std::to_string(tile) + ": " +
                                 std::to_string(nv) + " vertices, " +
                                 std::to_string(order.size()) + " in its blocks");
    if (!status.ok())
      break;
    if (result.xyz.empty()) // the first round holds every block of the tile
      for (VertexId v : order)
        if (global[v] - tile_first < tile_vertices)
          result.xyz.insert(result.xyz.end(), {m.xy[v].x, m.xy[v].y, m.z[v]});

    // The tile's vertices not proven yet are checked.
    check.assign(nv, 0);
    failed.assign(nv, 0);
    for (std::size_t v = 0; v < nv; ++v) {
      const std::uint64_t id = global[v] - tile_first;
      check[v] = id < tile_vertices && !proven[id];
    }
    unprovenStars(m, check, space, flags, block_side, cap, more, failed);

    // Proven: a checked vertex whose star met nothing unknown. Its owned triangles
    // are global ones.
    std::uint64_t newly = 0;
    for (std::size_t v = 0; v < nv; ++v)
      if (check[v] && !failed[v]) {
        proven[global[v] - tile_first] = 1;
        ++newly;
      }
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
      const VertexId* tv = &m.triangles[3 * t];
      std::array<std::uint32_t, 3> g = {global[tv[0]], global[tv[1]], global[tv[2]]};
      const int k = g[0] < g[1] ? (g[0] < g[2] ? 0 : 2) : (g[1] < g[2] ? 1 : 2);
      const VertexId smallest = tv[k];
      if (!check[smallest] || failed[smallest])
        continue;
      std::rotate(g.begin(), g.begin() + k, g.end());
      owned.push_back(g);
    }
    proven_count += newly;
    if (proven_count == tile_vertices)
      break;
    if (more.empty()) {
      status = Status::error(StatusCode::INTERNAL_ERROR,
                             "tile " + std::to_string(tile) +
                                 ": a vertex is unproven with nothing to load");
      break;
    }

    // The next round: the blocks around the vertices left, and the unknown blocks
    // their stars met. While a round proves nothing the loaded blocks only grow, so
    // the rounds end (at worst with every block loaded).
    for (std::size_t v = 0; v < nv; ++v)
      failed[v] = check[v] && failed[v];
    window.clear();
    windowsAround(m, failed, frame, space, block_side, window);
    if (newly == 0)
      window.insert(window.end(), loaded.begin(), loaded.end());
    window.insert(window.end(), more.begin(), more.end());
    more.clear();
    for (std::uint32_t b : loaded)
      flags[b] = 0;
    loaded.clear();
    load(window, loaded, flags);
  }
  for (std::uint32_t b : loaded)
    flags[b] = 0;
  if (!status.ok())
    return status;

  // Sorted by smallest vertex (a tile's vertex: counted into rows), then by the
  // second (a directed edge is in one triangle only, so that decides).
  std::vector<std::size_t> row(tile_vertices + 1, 0);
  for (const auto& g : owned)
    ++row[g[0] - tile_first + 1];
  for (std::size_t v = 0; v < tile_vertices; ++v)
    row[v + 1] += row[v];
  std::vector<std::size_t> next(row.begin(), row.end() - 1);
  result.triangles.resize(3 * owned.size());
  for (const auto& g : owned) {
    const std::size_t v = g[0] - tile_first;
    // Insertion by the second vertex among the few triangles of its row so far.
    std::uint32_t* const row_begin = &result.triangles[3 * row[v]];
    std::uint32_t* out = &result.triangles[3 * next[v]++];
    while (out != row_begin && out[-2] > g[1]) {
      std::copy(out - 3, out, out);
      out -= 3;
    }
    std::copy(g.begin(), g.end(), out);
  }
  return Status::success();
}

} // namespace pcl_vts
