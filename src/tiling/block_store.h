// Points bucketed by tile into temporary files, then ordered by block inside each
// file: any block reads back with one pread, in input order (duplicates keep their
// relative order, so the duplicate rules give the in-memory run's z).
#pragma once
#include <pcl_vts/core/status.h>
#include <pcl_vts/tiling/tile_frame.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {

class BlockStore {
 public:
  /// Files go to `folder` (which must exist); tiles and blocks are the quadtree
  /// nodes of tile_level <= block_level; each tile buffers `buffer_points` points.
  BlockStore(std::string folder, const TileFrame& frame, int tile_level,
             int block_level, std::size_t buffer_points);
  ~BlockStore();
  BlockStore(const BlockStore&) = delete;
  BlockStore& operator=(const BlockStore&) = delete;

  /// Buckets n finite points (xyz triples).
  Status add(const double* xyz, std::size_t n);
  /// Flushes, orders every tile file by block, counts points, distinct XY positions
  /// and the bounding box of each block. Needs memory for one tile, twice.
  Status finish();

  /// Appends the points of `block` (xyz triples, input order) to xyz.
  Status readBlock(std::uint32_t block, std::vector<double>& xyz) const;

  int tileLevel() const { return tile_level_; }
  int blockLevel() const { return block_level_; }
  const std::vector<std::uint64_t>& tilePoints() const { return tile_points_; }
  const std::vector<std::uint64_t>& blockPoints() const { return block_points_; }
  const std::vector<std::uint64_t>& blockDistinct() const { return block_distinct_; }
  const std::vector<Rect>& blockBounds() const { return block_bounds_; }
  std::uint64_t bytesOnDisk() const;

 private:
  std::string tilePath(std::uint32_t tile) const;
  Status flush(std::uint32_t tile);
  Status orderTile(std::uint32_t tile);
  Status ioError(const std::string& what, const std::string& path, int err) const;

  std::string folder_;
  TileFrame frame_;
  int tile_level_, block_level_;
  std::size_t buffer_points_;
  std::vector<std::vector<double>> buffers_;
  std::vector<std::uint64_t> tile_points_;
  std::vector<std::uint64_t> block_points_;
  std::vector<std::uint64_t> block_distinct_;
  std::vector<std::uint64_t>
      block_start_; ///< first point of the block in its tile file
  std::vector<Rect> block_bounds_;
  std::vector<int> fds_;
};

} // namespace pcl_vts
