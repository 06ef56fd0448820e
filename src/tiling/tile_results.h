// Tile results on the shared temporary folder: each tile's owned triangles in one
// file, its vertices rebuilt from its points (tile_vertices.h) when read back; read
// in tile order as the whole mesh (a MeshSource for the writer), or one tile at a
// time for the post-passes and the tile meshes (tile_output).
#pragma once
#include "block_store.h"
#include "tile_triangulation.h"

#include <pcl_vts/core/merge_duplicates.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/io/mesh_writer.h>
#include <pcl_vts/tiling/tile_frame.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {

/// "<folder>/result_<tile>.bin".
std::string resultPath(const std::string& folder, std::uint32_t tile);

/// A tile's result read whole.
struct TileMeshData {
  std::vector<double> xyz;              ///< the tile's vertices (when asked for)
  std::vector<std::uint32_t> triangles; ///< the triangles it owns, global ids
};

/// Writes one tile's result: a header (vertex count, triangle count, all float-exact,
/// the vertices' checksum), then the owned triangles (3 uint32), canonical order. The
/// vertices stay in the tile's point file, where the readers rebuild them.
Status writeTileResult(const std::string& path, const TileResult& tile);

/// Where the tile results are read back: the result files (triangles) and the
/// point files (vertices), with the job's frame and duplicate rule.
struct TileResultFiles {
  std::string folder;
  BlockStore* store = nullptr; ///< not const: the writer releases its files
  const TileFrame* frame = nullptr;
  DuplicateRule rule = DuplicateRule::LOWEST_Z;

  /// Tile's triangles, and its vertices when `vertices` (rebuilt and checked against
  /// the count and checksum its triangulation wrote).
  Status read(std::uint32_t tile, TileMeshData& data, bool vertices) const;
  /// Tile's vertices alone, given its header's count and checksum.
  Status readVertices(std::uint32_t tile, std::uint64_t count, std::uint64_t checksum,
                      std::vector<double>& xyz) const;
};

/// The whole mesh, read back tile by tile from the result files (rank 0).
class TileResultsMesh : public MeshSource {
 public:
  TileResultsMesh(const TileResultFiles& files, std::vector<std::uint32_t> tiles);
  /// Reads every header once: counts, float-exactness and the vertices' checksums
  /// (kept for forEachVertex, which then opens no result file).
  Status scan();
  /// The last reader: each tile's points go back to the file system once its
  /// vertices have been read (the point file removed), its result file once its
  /// triangles have, so the output grows as the temporary files shrink. A section
  /// read again after that is INTERNAL_ERROR, never zeros: only for a writer that
  /// reads each section once (PLY), with the store's descriptors closed on every
  /// rank (BlockStore::closeTileFiles).
  void releaseAsRead() { release_ = true; }
  std::uint64_t vertexCount() const override { return nv_; }
  std::uint64_t triangleCount() const override { return nt_; }
  bool exactInFloat() const override { return exact_; }
  bool hasInsertedFlags() const override { return false; }
  Status forEachVertex(const VertexVisit& visit) const override;
  Status forEachTriangle(const TriangleVisit& visit) const override;

 private:
  /// The state bit of a section (1 vertices, 2 triangles): an error once released.
  Status checkNotReleased(std::size_t k, std::uint8_t bit) const;

  const TileResultFiles& files_;
  std::vector<std::uint32_t> tiles_;
  std::uint64_t nv_ = 0, nt_ = 0;
  bool exact_ = true;
  bool release_ = false;
  std::vector<std::array<std::uint64_t, 2>> vertices_; ///< per tile: count, checksum
  mutable std::vector<std::uint8_t>
      released_; ///< per tile: bit 0 vertices, 1 triangles
};

/// Where every vertex id lives: the tiles with points, their first ids.
struct VertexOwners {
  std::vector<std::uint32_t> tiles;
  std::vector<std::uint64_t>
      first; ///< first id of each tile, plus the total at the end
  std::size_t tileOf(std::uint64_t id) const;
};

/// A triangle as the tile results store it: global ids, smallest first.
using TriangleKey = std::array<std::uint32_t, 3>;

/// What the post-passes changed (tiled_trim.h, tiled_fill.h), as the tile meshes need
/// it; null members: nothing of that kind. With inserted points the ids are final ids
/// (the inserted points placed in the canonical order), and tile k owns the final ids
/// from its first input vertex's to the next tile's: the points inserted between two
/// tiles' inputs go to the first.
struct TileMeshEdits {
  const std::vector<TriangleKey>* removed = nullptr;         ///< input ids, sorted
  const std::vector<std::uint64_t>* inputs_before = nullptr; ///< per inserted point
  const std::vector<std::array<double, 3>>* inserted = nullptr;
  const std::vector<TriangleKey>* added = nullptr; ///< final ids, sorted
};

/// Writes tile k's mesh (its owned triangles, every vertex they use and its own
/// vertices, ids renumbered in global order) into out_folder and returns its line of
/// index.csv. edits: the post-passes' changes, or nullptr.
Status writeTileMesh(const TileResultFiles& files, const std::string& out_folder,
                     const TileFrame& frame, int tile_level, const VertexOwners& owners,
                     const TileMeshEdits* edits, std::size_t k,
                     std::string& index_line);

/// index.csv's header line.
constexpr const char* TILE_INDEX_HEADER =
    "tile,column,row,x0,y0,x1,y1,vertices,triangles,file\n";

} // namespace pcl_vts
