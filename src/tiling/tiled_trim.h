// Trimming a tiled mesh (docs/scaling.md, "Post-passes"): the in-memory trim
// (trim_outward_triangles.h) run on the tile results, with the same answer.
//
// The static test of a triangle needs the local spacing of its corners, i.e. two
// rings of neighbours: it is computed in sweeps over the tiles, each vertex by the tile
// that holds it, from the triangles around it (its own tile's and those that other
// tiles own and send it), with the neighbours' values read back from files indexed by
// vertex id. The peel and the pinch repair then run in memory on the oversized
// triangles and every triangle around their corners: all they look at, and their
// answer depends on positions only (peelOutwardTriangles). Memory: one tile per
// worker, plus the oversized triangles and their fans.
#pragma once
#include "tile_results.h"

#include <pcl_vts/core/trim_outward_triangles.h>
#include <pcl_vts/io/mesh_writer.h>
#include <pcl_vts/tiling/job_comm.h>

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pcl_vts {

struct TiledTrim {
  std::vector<TriangleKey> removed; ///< sorted
  /// Every corner of an oversized triangle, sorted: the removed triangles' corners
  /// among them (hole rims are made of their edges).
  std::vector<std::uint32_t> corners;
  TrimResult result; ///< spacing is left 0 (a global median)
};

/// The scratch files trimTiledMesh leaves for hole filling: every vertex's x, y, z
/// and its spacing (median edge, before the trim), indexed by id (tile_sweep.h).
std::string positionsPath(const std::string& folder);
std::string ownSpacingPath(const std::string& folder);

/// Trims the mesh of the tile results (scratch files go to their folder too).
/// `workers` tiles are handled at once.
/// `report` (may be empty) hears of each tile visited, over all the sweeps.
/// Collective over comm (each rank's `workers` share the sweeps); the answer is rank
/// 0's.
Status trimTiledMesh(const TileResultFiles& results, const VertexOwners& owners,
                     const TrimOptions& options, JobComm& comm, unsigned workers,
                     const std::function<void(std::uint64_t, std::uint64_t)>& report,
                     TiledTrim& trim);

/// A mesh less some of its triangles, streamed.
class TrimmedMesh : public MeshSource {
 public:
  TrimmedMesh(const MeshSource& base, const std::vector<TriangleKey>& removed)
      : base_(base)
      , removed_(removed)
  {}
  std::uint64_t vertexCount() const override { return base_.vertexCount(); }
  std::uint64_t triangleCount() const override
  {
    return base_.triangleCount() - removed_.size();
  }
  bool exactInFloat() const override { return base_.exactInFloat(); }
  bool hasInsertedFlags() const override { return base_.hasInsertedFlags(); }
  Status forEachVertex(const VertexVisit& visit) const override
  {
    return base_.forEachVertex(visit);
  }
  Status forEachTriangle(const TriangleVisit& visit) const override;

 private:
  const MeshSource& base_;
  const std::vector<TriangleKey>& removed_;
};

} // namespace pcl_vts
