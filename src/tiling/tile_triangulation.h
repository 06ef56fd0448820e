// One tile of the tiled path: triangulate the points of the tile's blocks and of a
// halo, keep what is proven final, grow the halo where something is not.
//
// Proof: let R be the tile's rectangle. For every vertex v in R, every triangle
// around v must have a circumdisk that meets no occupied, unloaded block, and every
// hull edge at v must have an empty open half-plane beyond it. Then v's star in the
// loaded triangulation is its star in the triangulation of all points (a Delaunay
// triangle whose circumdisk holds no unknown point is Delaunay among all points, and
// a complete star cannot gain a triangle), so the tile emits exactly the triangles
// of the global triangulation whose smallest vertex (canonical order) lies in R.
#pragma once
#include "block_store.h"
#include "known_space.h"

#include <pcl_vts/core/vts_pipeline.h>

#include <cstdint>
#include <vector>

namespace pcl_vts {

struct TileContext {
  const TileFrame* frame = nullptr;
  const BlockStore* store = nullptr;
  const KnownSpace* space = nullptr;
  /// Per block: global id of its first vertex (canonical order, prefix sums).
  const std::vector<std::uint64_t>* block_first_vertex = nullptr;
  VtsOptions options; ///< triangulation only (reconstruction off)
};

struct TileResult {
  std::vector<double> xyz;              ///< the tile's vertices, canonical order
  std::vector<std::uint32_t> triangles; ///< owned, global ids, smallest first, sorted
  std::uint64_t points_loaded = 0;      ///< the most in one round
  unsigned rounds = 0; ///< triangulations run (1 = the first halo sufficed)
};

/// Triangulates tile `tile` (a node of the store's tile level). `flags` is the
/// worker's scratch: all zero on entry and on return, one byte per block.
Status triangulateTile(const TileContext& context, std::uint32_t tile,
                       LoadedBlocks& flags, TileResult& result);

} // namespace pcl_vts
