// Points bucketed by tile into temporary files, then ordered by block inside each
// file: any block reads back with one pread, in input order (duplicates keep their
// relative order, so the duplicate rules give the in-memory run's z). With several
// ranks, each buckets its own inputs into its own part files (rank r reads inputs
// after rank r-1's), and a tile's parts are joined in rank order when it is ordered.
#pragma once
#include <pcl_vts/core/status.h>
#include <pcl_vts/tiling/tile_frame.h>

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace pcl_vts {

class BlockStore {
 public:
  /// Files go to `folder` (which must exist); tiles and blocks are the quadtree
  /// nodes of tile_level <= block_level; each tile buffers `buffer_points` points.
  BlockStore(std::string folder, const TileFrame& frame, int tile_level,
             int block_level, std::size_t buffer_points, int rank = 0, int ranks = 1);
  ~BlockStore();
  BlockStore(const BlockStore&) = delete;
  BlockStore& operator=(const BlockStore&) = delete;

  /// Buckets n finite points (xyz triples) into this rank's part files.
  Status add(const double* xyz, std::size_t n);
  /// Writes what is still buffered. Every rank, before any orders a tile.
  Status flush();
  /// Joins tile's parts into one file ordered by block; fills the index entries
  /// (count, distinct XY positions, bounding box, offset) of its blocks. Needs memory
  /// for one tile, twice. Threads may order different tiles at once.
  Status orderTile(std::uint32_t tile);
  /// After each rank ordered its tiles: the index entries merged over ranks
  /// (a rank's entries are zero, +inf/-inf boxes, for tiles it did not order).
  void shareIndex(class JobComm& comm);
  /// Points per tile over all ranks (after shareIndex).
  std::uint64_t tilePoints(std::uint32_t tile) const;

  /// Appends the points of `block` (xyz triples, input order) to xyz.
  Status readBlock(std::uint32_t block, std::vector<double>& xyz) const;
  /// Closes this rank's descriptors of the tile files (reopened by the next read).
  /// Every rank, before the last reader releases files (releaseTileFile) or once
  /// nothing reads them; then removeTileFiles().
  void closeTileFiles();
  /// Unlinks the tile files this rank ordered, after every rank closed its
  /// descriptors (a barrier between), once the writer has rebuilt every vertex
  /// from them (tile_vertices.h).
  void removeTileFiles();
  /// The last reader of a tile's points (the writer, tile by tile): closes its
  /// descriptor and unlinks the file, so the disk goes back as the output grows. A
  /// later read of the tile is an error (the file is gone), never other points.
  void releaseTileFile(std::uint32_t tile);

  int tileLevel() const { return tile_level_; }
  int blockLevel() const { return block_level_; }
  std::size_t tileCount() const { return buffers_.size(); }
  const std::vector<std::uint64_t>& blockPoints() const { return block_points_; }
  const std::vector<std::uint64_t>& blockDistinct() const { return block_distinct_; }
  const std::vector<Rect>& blockBounds() const { return block_bounds_; }
  std::uint64_t bytesOnDisk() const;
  /// The convex hull of every point (after shareIndex), CCW, no collinear vertices.
  const std::vector<Point2>& globalHull() const { return hull_; }

 private:
  std::string tilePath(std::uint32_t tile) const;
  std::string partPath(std::uint32_t tile, int rank) const;
  Status flush(std::uint32_t tile);
  int openTile(std::uint32_t tile) const;
  Status ioError(const std::string& what, const std::string& path, int err) const;

  std::string folder_;
  TileFrame frame_;
  int tile_level_, block_level_;
  std::size_t buffer_points_;
  int rank_, ranks_;
  std::vector<std::vector<double>> buffers_;
  std::vector<std::uint64_t> part_points_; ///< this rank's points per tile
  std::vector<std::uint64_t> block_points_;
  std::vector<std::uint64_t> block_distinct_;
  std::vector<std::uint64_t>
      block_start_; ///< first point of the block in its tile file
  std::vector<Rect> block_bounds_;
  std::vector<Point2> hull_;     ///< of the tiles this rank ordered, then of all
  std::mutex hull_mutex_;        ///< orderTile's threads extend hull_ under it
  mutable std::vector<int> fds_; ///< opened on first read (under fd_mutex_)
  mutable std::mutex fd_mutex_;
};

} // namespace pcl_vts
