// Tile and block levels (tile_levels.h).
#include "tile_levels.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace pcl_vts {
namespace {

constexpr int MAX_BLOCK_LEVEL = 10; // 4^10 blocks: the index stays ~60 MB
// Blocks of about 512 points: a thinner first halo than 1024 (1.44 points loaded per
// point instead of 1.88 at 1e7, 10% faster), and the index stays small.
constexpr double BLOCK_POINTS = 512.0;
// Tiles of at most half a million points even when memory allows more: a tile and its
// halo then stay near the caches, and 64 such tiles ran as fast as the whole in memory
// (docs/scaling.md §5).
constexpr double TILE_POINTS_MAX = 5e5;
constexpr double TILE_POINTS_MIN = 1e4;
// The pipeline costs ~300 B per loaded point, and a tile loads up to twice its own
// points (its halo, more where the density or the hull makes halos grow).
constexpr double BYTES_PER_TILE_POINT = 800.0;

/// Smallest quadtree level whose nodes hold at most `target` points on average over
/// the part of the frame the box covers (`fill`); never above MAX_BLOCK_LEVEL.
int levelFor(std::uint64_t points, double fill, double target)
{
  int level = 0;
  while (level<MAX_BLOCK_LEVEL&& static_cast<double>(points) /
               (std::ldexp(1.0, 2 * level) * fill)>
             target)
    ++level;
  return level;
}

} // namespace

Status chooseTileLevels(std::uint64_t points, const TileFrame& frame, const Rect& box,
                        const TiledMeshOptions& options, unsigned workers, int ranks,
                        TileLevels& levels)
{
  const double side = frame.side;
  const double fill =
      std::max(1.0 / 1024, std::max(box.x1 - box.x0, side / 1e6) *
                               std::max(box.y1 - box.y0, side / 1e6) / (side * side));
  double tile_target =
      std::max(TILE_POINTS_MIN,
               std::min(TILE_POINTS_MAX, static_cast<double>(options.memory_limit) /
                                             BYTES_PER_TILE_POINT / workers));
  if (ranks > 1) // a few tiles per rank, or the ranks would wait for one another
    tile_target =
        std::min(tile_target, std::max(TILE_POINTS_MIN,
                                       static_cast<double>(points) / (4.0 * ranks)));
  levels.tile = options.tile_level >= 0 ? std::min(options.tile_level, MAX_BLOCK_LEVEL)
                                        : levelFor(points, fill, tile_target);
  levels.block = options.block_level >= 0
                     ? std::min(options.block_level, MAX_BLOCK_LEVEL)
                     : levelFor(points, fill, BLOCK_POINTS);
  // At least 8 x 8 blocks per tile, so that the first halo (one ring) is thin.
  levels.block = std::max(levels.block, std::min(levels.tile + 3, MAX_BLOCK_LEVEL));
  levels.tile = std::min(levels.tile, levels.block);

  // The least this job can run in: the block index (counts, offsets, boxes, the
  // pyramid, each worker's flags), a bucket buffer per tile, and each worker meshing
  // a tile of the smallest size with its halo.
  const double blocks = std::ldexp(1.0, 2 * levels.block);
  const double minimum = blocks * (62.0 + workers) +
                         std::ldexp(1.0, 2 * levels.tile) * 1536.0 +
                         workers * TILE_POINTS_MIN * BYTES_PER_TILE_POINT;
  if (static_cast<double>(options.memory_limit) < minimum)
    return Status::error(
        StatusCode::INVALID_PARAMETER,
        "the memory limit of " + std::to_string(options.memory_limit >> 20) +
            " MiB is below the " +
            std::to_string(static_cast<std::uint64_t>(minimum) >> 20) +
            " MiB this job needs at least (" + std::to_string(workers) +
            " tiles of 10000 points meshed at once, an index of " +
            std::to_string(static_cast<std::uint64_t>(blocks)) +
            " blocks): raise it, or mesh fewer tiles at once (fewer threads)");
  return Status::success();
}

} // namespace pcl_vts
