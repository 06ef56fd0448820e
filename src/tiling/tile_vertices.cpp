// Rebuilding a tile's vertices from its blocks (tile_vertices.h).
#include "tile_vertices.h"

#include <algorithm>
#include <cstring>

namespace pcl_vts {
namespace {

struct BlockPoint {
  std::uint32_t code;
  std::uint32_t index; ///< in the block, which is input order
  Point2 xy;
  double z;
};

/// The z that a run of equal XY (in input order) gives its vertex.
double foldedHeight(const BlockPoint* run, std::size_t n, DuplicateRule rule)
{
  std::size_t best = 0;
  switch (rule) {
  case DuplicateRule::LOWEST_Z:
    for (std::size_t k = 1; k < n; ++k)
      best = run[k].z < run[best].z ? k : best; // ties: the earliest
    return run[best].z;
  case DuplicateRule::HIGHEST_Z:
    for (std::size_t k = 1; k < n; ++k)
      best = run[k].z > run[best].z ? k : best;
    return run[best].z;
  case DuplicateRule::MEAN_Z: {
    double sum = 0.0; // from +0.0, in input order, as vertexHeights sums
    for (std::size_t k = 0; k < n; ++k)
      sum += run[k].z;
    return sum / static_cast<double>(n);
  }
  case DuplicateRule::FIRST:
    break;
  }
  return run[0].z;
}

} // namespace

Status rebuildTileVertices(const BlockStore& store, const TileFrame& frame,
                           std::uint32_t tile, DuplicateRule rule,
                           std::vector<double>& xyz)
{
  xyz.clear();
  const int shift = 2 * (store.blockLevel() - store.tileLevel());
  const std::vector<std::uint64_t>& counts = store.blockPoints();
  std::vector<double> points;
  std::vector<BlockPoint> sorted;
  for (std::uint32_t b = tile << shift; b < ((tile + 1) << shift); ++b) {
    if (counts[b] == 0)
      continue;
    points.clear();
    if (Status s = store.readBlock(b, points); !s.ok())
      return s;
    const std::size_t n = points.size() / 3;
    sorted.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const Point2 p{points[3 * k], points[3 * k + 1]};
      sorted[k] = {frame.code(p), static_cast<std::uint32_t>(k), p, points[3 * k + 2]};
    }
    // Canonical order; equal XY (so equal codes) stay in input order.
    std::sort(sorted.begin(), sorted.end(),
              [](const BlockPoint& p, const BlockPoint& q) {
                if (canonicalLess(p.code, p.xy, q.code, q.xy))
                  return true;
                return !canonicalLess(q.code, q.xy, p.code, p.xy) && p.index < q.index;
              });
    for (std::size_t k = 0; k < n;) {
      std::size_t end = k + 1;
      while (end < n && sorted[end].xy == sorted[k].xy)
        ++end;
      xyz.insert(xyz.end(), {sorted[k].xy.x, sorted[k].xy.y,
                             foldedHeight(&sorted[k], end - k, rule)});
      k = end;
    }
  }
  return Status::success();
}

std::uint64_t vertexChecksum(const std::vector<double>& xyz)
{
  std::uint64_t h = 0x9E3779B97F4A7C15ull;
  for (double v : xyz) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof(bits));
    h = (h ^ bits) * 0xBF58476D1CE4E5B9ull;
    h ^= h >> 31;
  }
  return h;
}

} // namespace pcl_vts
