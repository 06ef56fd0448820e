// How finely a tiled job is cut: tiles (the unit of work) sized by the memory limit
// shared by the worker threads, blocks (the unit of loading) of a few hundred points,
// and the least memory such a job needs. Every rank computes the same.
#pragma once
#include <pcl_vts/core/status.h>
#include <pcl_vts/tiling/tile_frame.h>
#include <pcl_vts/tiling/tiled_mesh.h>

#include <cstdint>

namespace pcl_vts {

struct TileLevels {
  int tile = 0;  ///< quadtree level of the tiles
  int block = 0; ///< quadtree level of the blocks (>= tile)
};

/// Levels for `points` finite points in the box [x0, x1] x [y0, y1] of `frame`, run by
/// `workers` threads on each of `ranks` ranks. INVALID_PARAMETER naming the minimum
/// when options.memory_limit is below what the job needs at least.
Status chooseTileLevels(std::uint64_t points, const TileFrame& frame, const Rect& box,
                        const TiledMeshOptions& options, unsigned workers, int ranks,
                        TileLevels& levels);

} // namespace pcl_vts
