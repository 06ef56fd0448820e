// Hole filling on a tiled mesh (docs/scaling.md, "Post-passes"): the in-memory fill
// (fill_holes.h) run on the trimmed tile results, with the same answer.
//
// A hole's rim is made of edges of removed triangles, so it lies among the trim's
// corners. The part of the mesh a fill looks at (the rims, the spacing of their
// vertices, rim_rings rings of spline samples) is gathered in sweeps over the tiles
// (rings grown from the removed triangles' corners), and fillHolesOfPart fills it: its
// answer depends on positions only. The one global figure, the median spacing behind
// the automatic largest hole, is selected exactly from the spacing file. The inserted
// points then take their places in the canonical vertex order and every id after them
// shifts: the written mesh is the in-memory one, byte for byte.
#pragma once
#include "tiled_trim.h"

#include <pcl_vts/core/fill_holes.h>
#include <pcl_vts/tiling/tile_frame.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {

struct TiledFill {
  /// The inserted points in canonical order, and for each the number of input
  /// vertices before it (non-decreasing).
  std::vector<std::array<double, 3>> inserted;
  std::vector<std::uint64_t> inputs_before;
  /// The patches' triangles in final ids, smallest first, sorted.
  std::vector<TriangleKey> added;
  FillResult result; ///< without the per-vertex flags
};

/// Fills the holes of the trimmed tile results (after trimTiledMesh, whose scratch
/// files it reads from their folder).
/// Collective over comm (each rank's `workers` share the sweeps); the answer is rank
/// 0's. `report` (may be empty) hears of each tile visited, over all the sweeps.
Status fillTiledMesh(const TileResultFiles& results, const VertexOwners& owners,
                     const TileFrame& frame, const FillOptions& options,
                     const TiledTrim& trim, JobComm& comm, unsigned workers,
                     const std::function<void(std::uint64_t, std::uint64_t)>& report,
                     TiledFill& fill);

/// A streamed mesh with the inserted points and patches of a fill merged in.
class FilledMesh : public MeshSource {
 public:
  FilledMesh(const MeshSource& base, const TiledFill& fill);
  std::uint64_t vertexCount() const override
  {
    return base_.vertexCount() + fill_.inserted.size();
  }
  std::uint64_t triangleCount() const override
  {
    return base_.triangleCount() + fill_.added.size();
  }
  bool exactInFloat() const override { return exact_; }
  bool hasInsertedFlags() const override { return true; }
  Status forEachVertex(const VertexVisit& visit) const override;
  Status forEachTriangle(const TriangleVisit& visit) const override;

 private:
  static constexpr int BLOCK_BITS = 12;
  /// An input vertex's final id: shifted by the points inserted before it.
  VertexId finalId(VertexId input) const;

  const MeshSource& base_;
  const TiledFill& fill_;
  bool exact_;
  /// Per block of 4096 input ids: the first inserted point at or after its start.
  std::vector<std::size_t> block_first_;
};

} // namespace pcl_vts
