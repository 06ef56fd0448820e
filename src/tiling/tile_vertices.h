// A tile's own vertices, rebuilt from its blocks in the point files: the distinct XY
// positions of its points, each with the duplicate rule's z, in canonical order, as
// the tile's triangulation numbered them (tile_triangulation.h). The tile results
// keep only the triangles, so the temporary disk holds the points once, not twice.
#pragma once
#include "block_store.h"

#include <pcl_vts/core/merge_duplicates.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/tiling/tile_frame.h>

#include <cstdint>
#include <vector>

namespace pcl_vts {

/// Replaces xyz by tile's vertices (3 doubles each): per block in block order, its
/// points sorted by (code, x, y), each run of equal XY folded as the core's
/// mergeDuplicates and vertexHeights fold it (the earliest point's XY; its z, or the
/// lowest, highest or mean z summed in input order).
Status rebuildTileVertices(const BlockStore& store, const TileFrame& frame,
                           std::uint32_t tile, DuplicateRule rule,
                           std::vector<double>& xyz);

/// A checksum of vertex coordinates (their bits), stored with a tile's result and
/// compared with the rebuilt vertices': a rebuild that differs from what the tile
/// triangulated is an internal error, never a silently different mesh.
std::uint64_t vertexChecksum(const std::vector<double>& xyz);

} // namespace pcl_vts
