// Meshing inputs larger than memory: points are bucketed by tile into temporary
// files, each tile is triangulated with a halo that grows until every triangle it
// owns is proven final (its circumdisk holds no point the tile has not loaded), and
// the mesh streams to the output file. The triangle set equals the in-memory run's,
// and the file is byte-identical to the in-memory run written in canonical order
// (canonicalMesh), for every tiling (docs/scaling.md).
#pragma once
#include <pcl_vts/core/status.h>
#include <pcl_vts/core/vts_pipeline.h>
#include <pcl_vts/io/mesh_writer.h>
#include <pcl_vts/tiling/export.h>
#include <pcl_vts/tiling/job_comm.h>
#include <pcl_vts/tiling/tile_frame.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pcl_vts {

/// The frame of a mesh's (non-inserted) vertices: the frame of the exact bounding
/// box of the distinct input points, as the tiled path computes it.
PCL_VTS_TILING_EXPORT TileFrame frameOfMesh(const TriangleMesh& mesh,
                                            const std::vector<std::uint8_t>* inserted);

/// Reorders a mesh into the canonical order of the tiled path: vertices by Morton
/// code of the frame, then x, then y; each triangle rotated to start at its smallest
/// vertex id, triangles sorted. inserted (optional, one per vertex) is permuted along.
/// INTERNAL_ERROR, the mesh left as it was, when it is not an oriented 2-manifold
/// (the pipeline's meshes always are); INVALID_PARAMETER, the same, when a corner is
/// not a vertex id. Twins already given for every halfedge (mutual,
/// joining the same vertices the other way, as the pipeline's meshes have them) are
/// carried along, not rebuilt: the check of the edges' use counts is then the
/// producer's (reconstructSurface's isValidSurfaceMesh). threads (0 counts as 1):
/// the passes' threads; the result is the same for every count.
[[nodiscard]] PCL_VTS_TILING_EXPORT Status canonicalMesh(
    TriangleMesh& mesh, std::vector<std::uint8_t>* inserted, unsigned threads = 1);

/// Calls sink with every input point (xyz triples, input order, chunk by chunk).
/// The tiled path calls it twice (bounds, then bucketing): it must give the same
/// points both times.
using PointSink = std::function<Status(const double* xyz, std::size_t n)>;
using PointFeed = std::function<Status(const PointSink& sink)>;

/// The inputs of a job as `count` sources (files) read one at a time, in order. With
/// several ranks, rank r reads a contiguous range after rank r-1's, so the ranks in
/// order see the points in input order (the duplicate rules depend on it).
struct PointInputs {
  std::size_t count = 0;
  std::function<Status(std::size_t source, const PointSink& sink)> read;
};

struct TiledProgress {
  /// "scanning", "bucketing", "ordering", "meshing", "writing" (and the pre-pass's
  /// "ground scan", "ground bucket", "ground filter")
  const char* phase = "";
  std::uint64_t done = 0;
  std::uint64_t total = 0;
};

struct TiledMeshOptions {
  /// Triangulation options; the post-passes (reconstruction) run across the tiles
  /// with the in-memory result (docs/scaling.md §5).
  VtsOptions vts;
  /// Parent of the job's temporary folder (created and removed by the job).
  std::string temp_parent = ".";
  /// Memory the job may use; sets the tile size (about 1/400 of it in points per
  /// thread, at most 5e5 points).
  std::uint64_t memory_limit = std::uint64_t{1} << 30;
  /// Tiles meshed at once on this rank (0 = all hardware threads); the memory limit
  /// is shared between them. The output is the same for every value.
  unsigned threads = 1;
  /// Also write one mesh per tile into this folder (must exist): tile_<c>_<r>.ply
  /// with the triangles the tile owns and every vertex they use (so neighbouring
  /// tiles share their seam vertices exactly), and index.csv (tile bounds, counts,
  /// file names). Empty = no tile meshes.
  std::string tile_output;
  /// Called by rank 0 once the mesh is written, while the temporary folder still holds
  /// the tile results: what else is made from the final mesh (the DEM). Its failure
  /// fails the run.
  std::function<Status(const MeshSource& mesh, const std::string& temp_folder)>
      after_write;
  /// An optional pre-pass (the tiled crop and PMF ground filter, ground_tiles.h): run
  /// by every rank once the temporary folder exists, before the scan, with the job's
  /// inputs (all of them: rank 0 reads them, the ranks share the filtering); it writes
  /// the points to mesh into files in the folder and names them (rank 0's list is
  /// the job's). The job then meshes those files, read by every rank with
  /// read_prepared, instead of the inputs, and removes them once it has bucketed
  /// their points. Its failure fails the run.
  std::function<Status(const PointInputs& inputs, const std::string& temp_folder,
                       JobComm& comm, std::vector<std::string>& files)>
      prepare;
  std::function<Status(const std::string& file, const PointSink& sink)> read_prepared;
  /// Testing knobs: quadtree levels of tiles and blocks (-1 = from memory_limit).
  int tile_level = -1;
  int block_level = -1;
  std::function<void(const TiledProgress&)> progress;
};

/// What a failed run could not do, beyond its status: for a caller that names the
/// setting involved in its own words (a tool puts its flag in front of the message).
enum class TiledFailure {
  NONE,         ///< the run succeeded
  OTHER,        ///< the arguments, the inputs or their points (see the status code)
  TEMP_FOLDER,  ///< creating the temporary folder in temp_parent, or writing or
                ///< reading its files (a full disk, a quota, permissions)
  MEMORY_LIMIT, ///< memory_limit is below what the job needs at least
  TILE_OUTPUT,  ///< writing the tile meshes into tile_output
  OUTPUT,       ///< writing the output, or after_write
};

struct TiledMeshReport {
  std::uint64_t points = 0; ///< points fed (each pass)
  std::uint64_t non_finite_dropped = 0;
  std::uint64_t vertices = 0; ///< distinct XY positions
  std::uint64_t triangles = 0;
  std::uint64_t tiles = 0;           ///< tiles with points
  std::uint64_t points_loaded = 0;   ///< sum over tiles of the points of the last round
  std::uint64_t max_tile_points = 0; ///< the largest last round (memory driver)
  unsigned max_rounds = 0;           ///< most triangulations one tile needed
  std::uint64_t rounds = 0;          ///< triangulations run, all tiles together
  std::uint64_t temp_bytes = 0;      ///< the bucketed points (24 B a point)
  std::uint64_t temp_peak_bytes = 0; ///< most disk the temporary folder took (rank 0)
  /// What the folder still held once the mesh was written (rank 0): the tile results
  /// go back as a PLY writer reads them, so little is left unless a product (the DEM,
  /// the contours) or another format reads them again.
  std::uint64_t temp_bytes_after_write = 0;
  int tile_level = 0, block_level = 0;
  TrimResult trim; ///< when trimming (its spacing is left 0)
  FillResult fill; ///< when filling (without per-vertex flags)
  double seconds_scan = 0, seconds_bucket = 0, seconds_mesh = 0, seconds_trim = 0,
         seconds_fill = 0, seconds_write = 0;
  MeshWriteInfo written;
  TiledFailure failure = TiledFailure::NONE; ///< set when the run fails (every rank)
};

/// Meshes every point of `inputs` and writes the mesh to `output` (atomically, by
/// rank 0). Every rank of `comm` calls it with the same arguments; the temporary
/// folder must then be shared by all ranks (a cluster file system). The report holds
/// totals over all ranks; every rank returns the same status (a failing rank's error
/// names it).
PCL_VTS_TILING_EXPORT Status runTiledMesh(const PointInputs& inputs,
                                          const TiledMeshOptions& options,
                                          const std::string& output,
                                          const MeshWriteOptions& write_options,
                                          TiledMeshReport& report, JobComm& comm);

/// One process, one input stream.
PCL_VTS_TILING_EXPORT Status runTiledMesh(const PointFeed& feed,
                                          const TiledMeshOptions& options,
                                          const std::string& output,
                                          const MeshWriteOptions& write_options,
                                          TiledMeshReport& report);

} // namespace pcl_vts
