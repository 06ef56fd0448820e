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

/// Unknown blocks that the stars of the tile's vertices (and their hull edges) meet.
void unprovenStars(const TriangleMesh& mesh, const std::vector<std::uint8_t>& in_tile,
                   const KnownSpace& space, const LoadedBlocks& flags,
                   double block_side, std::size_t cap, std::vector<std::uint32_t>& hits)
{
  const std::size_t nt = mesh.triangleCount();
  for (std::size_t t = 0; t < nt; ++t) {
    const VertexId* v = &mesh.triangles[3 * t];
    if (!in_tile[v[0]] && !in_tile[v[1]] && !in_tile[v[2]])
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
    for (int k = 0; k < 3; ++k) {
      const std::size_t e = 3 * t + static_cast<std::size_t>(k);
      const VertexId a = mesh.triangles[e],
                     b = mesh.triangles[nextHalfedge(static_cast<HalfedgeId>(e))];
      if (mesh.halfedges[e] == INVALID_ID && (in_tile[a] || in_tile[b]))
        nearestRightOf(space, mesh.xy[a], mesh.xy[b], flags, block_side, cap, hits);
    }
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
  result = TileResult{};

  std::vector<std::uint32_t> loaded, more;
  for (std::uint32_t b = tile << shift; b < ((tile + 1) << shift); ++b)
    if (space.occupied(b))
      more.push_back(b);
  const std::vector<std::uint32_t> own = more;
  ringAround(own, block_level, space, flags, more);
  load(more, loaded, flags);

  std::vector<double> xyz;
  VtsResult mesh;
  std::vector<std::uint32_t> code;
  std::vector<std::uint8_t> in_tile;
  Status status;
  for (;;) {
    ++result.rounds;
    xyz.clear();
    for (std::uint32_t b : loaded)
      if (!(status = store.readBlock(b, xyz)).ok())
        break;
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
    const TriangleMesh& m = mesh.mesh;
    const std::size_t nv = m.vertexCount();
    code.resize(nv);
    in_tile.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) {
      code[v] = frame.code(m.xy[v]);
      in_tile[v] = TileFrame::nodeOf(code[v], tile_level) == tile;
    }
    unprovenStars(m, in_tile, space, flags, frame.side / (1u << block_level),
                  std::max(MIN_BLOCKS_PER_ROUND, own.size()), more);
    if (more.empty())
      break;
    load(more, loaded, flags);
  }
  result.points_loaded = xyz.size() / 3;
  for (std::uint32_t b : loaded)
    flags[b] = 0;
  if (!status.ok())
    return status;

  // Global ids: canonical rank inside each loaded (hence complete) block.
  const TriangleMesh& m = mesh.mesh;
  const std::size_t nv = m.vertexCount();
  std::vector<VertexId> order(nv);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](VertexId a, VertexId b) {
    return canonicalLess(code[a], m.xy[a], code[b], m.xy[b]);
  });
  std::vector<std::uint32_t> global(nv);
  const std::vector<std::uint64_t>& first = *context.block_first_vertex;
  for (std::size_t k = 0; k < nv;) {
    const std::uint32_t block = TileFrame::nodeOf(code[order[k]], block_level);
    std::size_t end = k;
    while (end < nv && TileFrame::nodeOf(code[order[end]], block_level) == block) {
      global[order[end]] = static_cast<std::uint32_t>(first[block] + (end - k));
      ++end;
    }
    if (end - k != store.blockDistinct()[block])
      return Status::error(StatusCode::INTERNAL_ERROR,
                           "tile " + std::to_string(tile) + ": block " +
                               std::to_string(block) + " has " +
                               std::to_string(end - k) + " vertices, its index says " +
                               std::to_string(store.blockDistinct()[block]));
    k = end;
  }
  for (VertexId v : order)
    if (in_tile[v])
      result.xyz.insert(result.xyz.end(), {m.xy[v].x, m.xy[v].y, m.z[v]});
  std::vector<std::array<std::uint32_t, 3>> owned;
  for (std::size_t t = 0; t < m.triangleCount(); ++t) {
    std::array<std::uint32_t, 3> g = {global[m.triangles[3 * t]],
                                      global[m.triangles[3 * t + 1]],
                                      global[m.triangles[3 * t + 2]]};
    const int k = g[0] < g[1] ? (g[0] < g[2] ? 0 : 2) : (g[1] < g[2] ? 1 : 2);
    if (!in_tile[m.triangles[3 * t + static_cast<std::size_t>(k)]])
      continue;
    std::rotate(g.begin(), g.begin() + k, g.end());
    owned.push_back(g);
  }
  std::sort(owned.begin(), owned.end());
  result.triangles.reserve(3 * owned.size());
  for (const auto& g : owned)
    result.triangles.insert(result.triangles.end(), g.begin(), g.end());
  return Status::success();
}

} // namespace pcl_vts
