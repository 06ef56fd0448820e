// What a tile knows: every occupied block it has loaded, every empty block (the block
// histogram says so) and everything outside the frame. A triangle of the loaded
// points is final once its circumdisk meets no occupied block that is not loaded;
// a hull edge of the loaded points is final once the open half-plane beyond it meets
// none. This one rule decides halo growth (docs/scaling.md).
#pragma once
#include "global_hull.h"

#include <pcl_vts/core/error_bounds.h>
#include <pcl_vts/core/point2.h>
#include <pcl_vts/tiling/tile_frame.h>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace pcl_vts {

/// Per worker: which blocks the tile being meshed has loaded (1 byte per block).
using LoadedBlocks = std::vector<std::uint8_t>;

/// The occupied blocks and their point boxes, shared read-only by every worker.
class KnownSpace {
 public:
  /// occupied[block] = points in that block (Morton-numbered blocks of `level`);
  /// bounds[block] = the exact bounding box of its points (any value when empty).
  /// hull = the convex hull of all points (nothing lies outside it).
  KnownSpace(const TileFrame& frame, int level,
             const std::vector<std::uint64_t>& occupied,
             const std::vector<Rect>& bounds, const std::vector<Point2>& hull);

  int level() const { return level_; }
  std::size_t blockCount() const { return counts_[levelIndex()].size(); }
  bool occupied(std::uint32_t block) const { return counts_[levelIndex()][block] != 0; }
  /// The exact box of the block's points.
  const Rect& bounds(std::uint32_t block) const { return bounds_[block]; }

  /// Appends to `hits` every occupied, unloaded block the disk may meet
  /// (each at most once per call; duplicates across calls are the caller's).
  void unknownInDisk(const CircumdiskBound& disk, const LoadedBlocks& loaded,
                     std::vector<std::uint32_t>& hits) const;
  /// Appends every occupied, unloaded block that may meet the open half-plane to the
  /// right of the directed line a -> b.
  void unknownRightOf(const Point2& a, const Point2& b, const LoadedBlocks& loaded,
                      std::vector<std::uint32_t>& hits) const;

 private:
  std::size_t levelIndex() const { return static_cast<std::size_t>(level_); }
  /// Descends the pyramid through nodes whose rectangle may meet the region
  /// (meets_node) down to unloaded occupied blocks whose points' box may meet it
  /// (meets_block).
  template <typename MeetsNode, typename MeetsBlock>
  void collect(int level, std::uint32_t node, const MeetsNode& meets_node,
               const MeetsBlock& meets_block, const LoadedBlocks& loaded,
               std::vector<std::uint32_t>& hits) const;

  TileFrame frame_;
  int level_;
  /// counts_[l][node]: occupied blocks under that node of level l.
  std::vector<std::vector<std::uint32_t>> counts_;
  const std::vector<Rect>& bounds_;
  /// Blocks whose point box reaches beyond the hull: the part inside it.
  std::unordered_map<std::uint32_t, ClippedBox> clipped_;
};

} // namespace pcl_vts
