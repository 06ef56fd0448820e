// The tiled job (tiled_mesh.h), one function per phase:
//   scan -> levels -> bucket and order -> number -> mesh tiles -> tile meshes -> write.
// Every phase ends with an agreement (job_agreement.h), so all ranks leave together.
#include "block_store.h"
#include "job_agreement.h"
#include "known_space.h"
#include "temp_folder.h"
#include "tile_levels.h"
#include "tile_results.h"
#include "tile_triangulation.h"
#include "tiled_fill.h"
#include "tiled_trim.h"

#include <pcl_vts/core/atomic_file.h>
#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/stopwatch.h>
#include <pcl_vts/tiling/tiled_mesh.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <numeric>
#include <thread>

namespace pcl_vts {
namespace {

bool finitePoint(const double* p)
{
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

/// What every phase of one rank's job shares.
struct Job {
  Job(const PointInputs& inputs_, const TiledMeshOptions& options_, JobComm& comm_,
      TiledMeshReport& report_)
      : inputs(inputs_)
      , options(options_)
      , comm(comm_)
      , report(report_)
  {}

  const PointInputs& inputs;
  const TiledMeshOptions& options;
  JobComm& comm;
  TiledMeshReport& report;
  int rank = 0, ranks = 1;
  unsigned workers = 1;
  std::uint64_t my_points = 0; ///< read by this rank in the scan
  std::uint64_t finite = 0;    ///< all ranks
  TileFrame frame;
  Rect box;
  TileLevels levels;
  /// The tile results in the temporary folder every rank writes into (its `folder`),
  /// vertices from the points.
  TileResultFiles results;
  std::vector<std::uint64_t> first_vertex;
  std::vector<std::uint32_t> occupied_tiles;
  std::vector<std::uint32_t> meshed_here; ///< indices into occupied_tiles
  TiledTrim trim;                         ///< rank 0's, when trimming
  TiledFill fill;                         ///< rank 0's, when filling

  /// Where every vertex id lives.
  VertexOwners owners() const
  {
    VertexOwners owners;
    owners.tiles = occupied_tiles;
    const int shift = 2 * (levels.block - levels.tile);
    for (std::uint32_t t : occupied_tiles)
      owners.first.push_back(first_vertex[std::size_t{t} << shift]);
    owners.first.push_back(first_vertex.back());
    return owners;
  }

  void progress(const char* phase, std::uint64_t done, std::uint64_t total) const
  {
    if (options.progress && rank == 0)
      options.progress(TiledProgress{phase, done, total});
  }

  /// This rank's sources, a contiguous range after the lower ranks', to sink.
  Status readMine(const PointSink& sink) const
  {
    const auto share = [&](int r) {
      return inputs.count * static_cast<std::size_t>(r) /
             static_cast<std::size_t>(ranks);
    };
    for (std::size_t k = share(rank); k < share(rank + 1); ++k)
      if (Status s = inputs.read(k, sink); !s.ok())
        return s;
    return Status::success();
  }
};

/// 1. Count and exact bounds of the finite points, over all ranks; the frame.
Status scan(Job& job)
{
  std::vector<double> low = {HUGE_VAL, HUGE_VAL}, high = {-HUGE_VAL, -HUGE_VAL};
  std::vector<std::uint64_t> counts = {0, 0}; // points, non-finite
  Status status = job.readMine([&](const double* xyz, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      const double* p = xyz + 3 * i;
      ++counts[0];
      if (!finitePoint(p)) {
        ++counts[1];
        continue;
      }
      low[0] = std::min(low[0], p[0]);
      low[1] = std::min(low[1], p[1]);
      high[0] = std::max(high[0], p[0]);
      high[1] = std::max(high[1], p[1]);
    }
    job.progress("scanning", counts[0], 0);
    return Status::success();
  });
  if (!(status = agree(job.comm, status)).ok())
    return status;
  job.my_points = counts[0];
  job.comm.sum(counts);
  job.comm.min(low);
  job.comm.max(high);
  job.report.points = counts[0];
  job.report.non_finite_dropped = counts[1];
  job.finite = counts[0] - counts[1];
  if (job.finite == 0)
    return Status::error(StatusCode::EMPTY_INPUT, "no finite point in the input");
  job.box = Rect{low[0], low[1], high[0], high[1]};
  job.frame = TileFrame::fromBounds(low[0], low[1], high[0], high[1]);
  return Status::success();
}

/// 3. This rank's points into its part files; the tiles ordered by block (shared out
///    over the ranks); the block index and the global hull shared.
Status bucket(Job& job, BlockStore& store)
{
  std::uint64_t fed = 0, bucketed = 0;
  bool store_error = false;
  Status status = job.readMine([&](const double* xyz, std::size_t n) {
    // Runs of finite points straight into the store: no copy of the chunk.
    Status added = Status::success();
    for (std::size_t i = 0; i < n && added.ok();) {
      std::size_t end = i;
      while (end < n && finitePoint(xyz + 3 * end))
        ++end;
      added = store.add(xyz + 3 * i, end - i);
      bucketed += end - i;
      i = end + 1; // past the non-finite point (or the end)
    }
    store_error = !added.ok();
    fed += n;
    job.progress("bucketing", fed * static_cast<std::uint64_t>(job.ranks),
                 job.report.points);
    return added;
  });
  // The store's failures are the temporary folder's, the others the inputs'.
  bool store_failed = !status.ok() && store_error;
  if (status.ok() && fed != job.my_points)
    status = Status::error(
        StatusCode::IO_ERROR,
        "the input changed while it was read: " + std::to_string(job.my_points) +
            " points the first time, " + std::to_string(fed) + " the second");
  if (status.ok()) {
    status = store.flush();
    store_failed = !status.ok();
  }
  if (!(status = agree(job.comm, status)).ok()) {
    std::vector<std::uint64_t> failed = {store_failed ? 1u : 0u};
    job.comm.sum(failed); // some rank's store failed (its error, or another rank's)
    job.report.failure = failed[0] != 0 && status.code == StatusCode::IO_ERROR
                             ? TiledFailure::TEMP_FOLDER
                             : TiledFailure::OTHER;
    return status;
  }
  std::vector<std::uint64_t> bucketed_all = {bucketed};
  job.comm.sum(bucketed_all);
  if (bucketed_all[0] != job.finite) {
    job.report.failure = TiledFailure::OTHER;
    return Status::error(StatusCode::IO_ERROR, "the input changed while it was read");
  }
  // This rank's tiles (rank, rank + ranks, ...), one per worker at a time: the tile
  // size leaves each worker memory for one tile, twice.
  const auto ranks = static_cast<std::size_t>(job.ranks);
  const std::size_t mine =
      (store.tileCount() + ranks - 1 - static_cast<std::size_t>(job.rank)) / ranks;
  job.progress("ordering", 0, mine);
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  std::size_t ordered = 0;
  runTeam(static_cast<unsigned>(
              std::max<std::size_t>(1, std::min<std::size_t>(job.workers, mine))),
          [&](unsigned) {
            for (std::size_t k = next++; k < mine; k = next++) {
              const auto t = static_cast<std::uint32_t>(
                  static_cast<std::size_t>(job.rank) + k * ranks);
              Status s = store.orderTile(t);
              const std::lock_guard<std::mutex> lock(mutex);
              if (!s.ok()) {
                if (status.ok())
                  status = s;
                next = mine; // the others stop after their current tile
                return;
              }
              job.progress("ordering", ++ordered, mine);
            }
          });
  if (!(status = agree(job.comm, status)).ok()) {
    job.report.failure = status.code == StatusCode::IO_ERROR ? TiledFailure::TEMP_FOLDER
                                                             : TiledFailure::OTHER;
    return status;
  }
  store.shareIndex(job.comm);
  job.report.temp_bytes = store.bytesOnDisk(); // every rank's points, after shareIndex
  return Status::success();
}

/// 4. Global vertex ids: prefix sums of the distinct points per block.
Status number(Job& job, const BlockStore& store)
{
  const std::vector<std::uint64_t>& distinct = store.blockDistinct();
  job.first_vertex.assign(distinct.size() + 1, 0);
  std::partial_sum(distinct.begin(), distinct.end(), job.first_vertex.begin() + 1);
  job.report.vertices = job.first_vertex.back();
  if (job.report.vertices >
      static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
    return Status::error(StatusCode::CAPACITY_EXCEEDED,
                         std::to_string(job.report.vertices) +
                             " distinct points do not fit the 32-bit vertex indices of "
                             "one mesh: mesh the area in parts of fewer points");
  if (job.report.vertices < 3)
    return Status::error(StatusCode::TOO_FEW_POINTS,
                         "fewer than 3 distinct XY positions (" +
                             std::to_string(job.report.vertices) + ")");
  for (std::uint32_t t = 0; t < store.tileCount(); ++t)
    if (store.tilePoints(t) != 0)
      job.occupied_tiles.push_back(t);
  job.report.tiles = job.occupied_tiles.size();
  return Status::success();
}

/// 5. Each worker of each rank takes the next tile of the shared counter (a rank that
///    finishes early takes more: tiles are unequal on real data) and writes its result
///    file; nothing depends on who meshed what.
Status meshTiles(Job& job, const BlockStore& store)
{
  job.comm.startTasks();
  const KnownSpace space(job.frame, job.levels.block, store.blockPoints(),
                         store.blockBounds(), store.globalHull());
  TileContext context;
  context.frame = &job.frame;
  context.store = &store;
  context.space = &space;
  context.block_first_vertex = &job.first_vertex;
  context.options = job.options.vts;
  context.options.reconstruction = noPostPasses(); // they run on the whole mesh, later
  context.options.input_map = true; // a tile's vertex order comes from it
  const unsigned all_threads = job.workers;
  const unsigned workers =
      std::max(1u, std::min<unsigned>(
                       all_threads, static_cast<unsigned>(job.occupied_tiles.size())));
  context.options.threads = std::max(1u, all_threads / workers);
  std::mutex mutex;
  Status failure;
  std::vector<std::uint64_t> sums = {0, 0}; // points loaded, rounds
  std::vector<double> maxima = {0, 0};      // largest tile, most rounds
  std::uint64_t furthest = 0;               // tasks taken up to here, for progress
  const auto work = [&]() {
    LoadedBlocks flags(space.blockCount(), 0);
    TileResult tile;
    for (;;) {
      {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!failure.ok())
          return;
      }
      const std::uint64_t k = job.comm.nextTask();
      if (k >= job.occupied_tiles.size())
        return;
      const std::uint32_t t = job.occupied_tiles[static_cast<std::size_t>(k)];
      Status s = triangulateTile(context, t, flags, tile);
      if (s.ok())
        s = writeTileResult(resultPath(job.results.folder, t), tile);
      const std::lock_guard<std::mutex> lock(mutex);
      if (!s.ok()) {
        if (failure.ok())
          failure =
              Status::error(s.code, "tile " + std::to_string(t) + ": " + s.message);
        return;
      }
      job.meshed_here.push_back(static_cast<std::uint32_t>(k));
      sums[0] += tile.points_loaded;
      sums[1] += tile.rounds;
      maxima[0] = std::max(maxima[0], static_cast<double>(tile.points_loaded));
      maxima[1] = std::max(maxima[1], static_cast<double>(tile.rounds));
      // Tasks finish out of order: the furthest one taken, so the count never drops.
      furthest = std::max(furthest, k + 1);
      job.progress("meshing", furthest, job.occupied_tiles.size());
    }
  };
  runTeam(workers, [&](unsigned) { work(); });
  if (Status s = agree(job.comm, failure); !s.ok())
    return s;
  job.comm.sum(sums);
  job.comm.max(maxima);
  job.report.points_loaded = sums[0];
  job.report.rounds = sums[1];
  job.report.max_tile_points = static_cast<std::uint64_t>(maxima[0]);
  job.report.max_rounds = static_cast<unsigned>(maxima[1]);
  return Status::success();
}

/// 6. The tile meshes (tile_output): each rank writes the meshes of the tiles it
///    meshed; their index lines ("k line") go to every rank; rank 0 writes index.csv.
Status writeTileOutputs(Job& job)
{
  job.progress("writing tiles", 0, 0);
  const VertexOwners owners = job.owners();
  // After the post-passes, rank 0 holds what they changed and writes every tile.
  const ReconstructionOptions& post = job.options.vts.reconstruction;
  TileMeshEdits edits;
  edits.removed = &job.trim.removed;
  if (post.fill) {
    edits.inputs_before = &job.fill.inputs_before;
    edits.inserted = &job.fill.inserted;
    edits.added = &job.fill.added;
  }
  const bool edited = post.trim || post.fill;
  std::vector<std::uint32_t> mine = job.meshed_here;
  if (edited) {
    mine.clear();
    for (std::uint32_t k = 0; job.rank == 0 && k < job.occupied_tiles.size(); ++k)
      mine.push_back(k);
  }
  Status status;
  std::string my_lines;
  for (std::size_t i = 0; i < mine.size() && status.ok(); ++i) {
    std::string line;
    status =
        writeTileMesh(job.results, job.options.tile_output, job.frame, job.levels.tile,
                      owners, edited ? &edits : nullptr, mine[i], line);
    my_lines += std::to_string(mine[i]) + " " + line;
  }
  if (!(status = agree(job.comm, status)).ok())
    return status;
  std::vector<std::string> lines(job.occupied_tiles.size());
  for (int root = 0; root < job.ranks; ++root) {
    std::string bytes = my_lines;
    job.comm.broadcast(bytes, root);
    for (std::size_t at = 0; at < bytes.size();) {
      const std::size_t gap = bytes.find(' ', at), end = bytes.find('\n', at);
      lines[std::stoul(bytes.substr(at, gap - at))] = bytes.substr(gap + 1, end - gap);
      at = end + 1;
    }
  }
  if (job.rank == 0) {
    AtomicFile index(job.options.tile_output + "/index.csv");
    status = index.open();
    if (status.ok()) {
      index.write(TILE_INDEX_HEADER);
      for (const std::string& line : lines)
        index.write(line);
      status = index.commit();
    }
  }
  return agree(job.comm, status);
}

/// 6'. The ranks trim the mesh (tiled_trim.h): the sweeps shared, rank 0 peels.
Status trim(Job& job)
{
  job.progress("trimming", 0, 0);
  const Status status = trimTiledMesh(
      job.results, job.owners(), job.options.vts.reconstruction.trim_options, job.comm,
      job.workers,
      [&](std::uint64_t done, std::uint64_t total) {
        job.progress("trimming", done, total);
      },
      job.trim);
  job.report.trim = job.trim.result;
  return agree(job.comm, status);
}

/// 6''. The ranks fill the holes of the trimmed mesh (tiled_fill.h): the sweeps
/// shared, rank 0 fills.
Status fill(Job& job)
{
  job.progress("filling", 0, 0);
  const Status status = fillTiledMesh(
      job.results, job.owners(), job.frame, job.options.vts.reconstruction.fill_options,
      job.trim, job.comm, job.workers,
      [&](std::uint64_t done, std::uint64_t total) {
        job.progress("filling", done, total);
      },
      job.fill);
  job.report.fill = job.fill.result;
  return agree(job.comm, status);
}

/// 7. Rank 0 writes the mesh, atomically, from the result files in tile order.
Status writeOutput(Job& job, const std::string& output, MeshFileFormat format,
                   const MeshWriteOptions& write_options)
{
  job.progress("writing", 0, 0);
  Status status;
  if (job.rank == 0) {
    TileResultsMesh mesh(job.results, job.occupied_tiles);
    // The writer is the last reader of the results and the points unless a product
    // reads them after it; PLY reads each section once (OBJ and VTK read the vertices
    // twice when points were inserted).
    if (!job.options.after_write && format == MeshFileFormat::PLY)
      mesh.releaseAsRead();
    status = mesh.scan();
    if (status.ok() && mesh.vertexCount() != job.report.vertices)
      status = Status::error(StatusCode::INTERNAL_ERROR,
                             "tiles wrote " + std::to_string(mesh.vertexCount()) +
                                 " vertices, the block index counts " +
                                 std::to_string(job.report.vertices));
    const TrimmedMesh trimmed(mesh, job.trim.removed);
    const FilledMesh filled(trimmed, job.fill);
    const MeshSource& final_mesh = job.options.vts.reconstruction.fill
                                       ? static_cast<const MeshSource&>(filled)
                                       : trimmed;
    job.report.triangles = final_mesh.triangleCount();
    if (status.ok())
      status = writeMesh(output, final_mesh, write_options, &job.report.written);
    if (status.ok() && job.options.after_write) {
      job.progress("writing products", 0, 0);
      status = job.options.after_write(final_mesh, job.results.folder);
    }
  }
  status = agree(job.comm, status);
  std::vector<std::uint64_t> triangles = {job.report.triangles};
  job.comm.sum(triangles);
  job.report.triangles = triangles[0];
  return status;
}

} // namespace

Status runTiledMesh(const PointFeed& feed, const TiledMeshOptions& options,
                    const std::string& output, const MeshWriteOptions& write_options,
                    TiledMeshReport& report)
{
  PointInputs inputs;
  inputs.count = 1;
  inputs.read = [&feed](std::size_t, const PointSink& sink) { return feed(sink); };
  LocalComm local;
  return runTiledMesh(inputs, options, output, write_options, report, local);
}

Status runTiledMesh(const PointInputs& inputs, const TiledMeshOptions& options,
                    const std::string& output, const MeshWriteOptions& write_options,
                    TiledMeshReport& report, JobComm& comm)
{
  report = TiledMeshReport{};
  // A failure's kind (TiledFailure): by the step, an I/O error told from the others.
  const auto failed = [&report](Status s, TiledFailure io_kind = TiledFailure::OTHER) {
    if (report.failure == TiledFailure::NONE)
      report.failure = s.code == StatusCode::IO_ERROR ? io_kind : TiledFailure::OTHER;
    return s;
  };
  // Argument checks: the same answer on every rank, no agreement needed.
  const ReconstructionOptions& post = options.vts.reconstruction;
  if (Status s = validateOptions(options.vts); !s.ok())
    return failed(s);
  MeshFileFormat format;
  if (Status s = meshFileFormatFromPath(output, format); !s.ok())
    return failed(s);
  TempFolder temp; // rank 0 makes it (and removes it, last), every rank writes into it
  std::string folder;
  Status status;
  if (comm.rank() == 0) {
    status = temp.create(options.temp_parent);
    folder = temp.path();
  }
  if (!(status = agree(comm, status)).ok())
    return failed(status, TiledFailure::TEMP_FOLDER);
  comm.broadcast(folder, 0);
  if (comm.rank() != 0) // any rank that mpirun stops removes the folder too
    temp.adopt(folder);
  // The pre-pass (every rank) replaces the inputs by the files it wrote.
  PointInputs prepared;
  std::vector<std::string> files;
  if (options.prepare) {
    status = options.prepare(inputs, folder, comm, files);
    if (!(status = agree(comm, status)).ok())
      return failed(status);
    std::string list;
    for (const std::string& file : files)
      list += file + '\n';
    comm.broadcast(list, 0);
    files.clear();
    for (std::size_t at = 0, end; (end = list.find('\n', at)) != std::string::npos;
         at = end + 1)
      files.push_back(list.substr(at, end - at));
    prepared.count = files.size();
    prepared.read = [files, &options](std::size_t k, const PointSink& sink) {
      return options.read_prepared(files[k], sink);
    };
  }

  Job job(options.prepare ? prepared : inputs, options, comm, report);
  job.rank = comm.rank();
  job.ranks = comm.size();
  job.workers = options.threads != 0 ? options.threads : allCores();
  job.results.folder = folder;

  Stopwatch watch;
  if (Status s = scan(job); !s.ok())
    return failed(s);
  report.seconds_scan = watch.seconds();
  if (Status s = chooseTileLevels(job.finite, job.frame, job.box, options, job.workers,
                                  job.ranks, job.levels);
      !s.ok()) {
    report.failure = TiledFailure::MEMORY_LIMIT;
    return s;
  }
  report.tile_level = job.levels.tile;
  report.block_level = job.levels.block;

  watch.restart();
  const std::size_t tiles = std::size_t{1} << (2 * job.levels.tile);
  const std::size_t buffer_points = std::clamp<std::size_t>(
      static_cast<std::size_t>(options.memory_limit / 8 / (tiles * 24)), 64, 16384);
  BlockStore store(job.results.folder, job.frame, job.levels.tile, job.levels.block,
                   buffer_points, job.rank, job.ranks);
  if (!(status = bucket(job, store)).ok())
    return failed(status); // bucket() tells the store's failures from the inputs'
  if (job.rank == 0)       // every rank is past its reading (bucket's agreement)
    for (const std::string& file : files) // the pre-pass's: read no more
      std::remove(file.c_str());
  report.seconds_bucket = watch.seconds();
  if (!(status = number(job, store)).ok())
    return failed(status);
  job.results.store = &store;
  job.results.frame = &job.frame;
  job.results.rule = options.vts.duplicate_rule;

  watch.restart();
  if (!(status = meshTiles(job, store)).ok())
    return failed(status, TiledFailure::TEMP_FOLDER);
  const auto measureTemp = [&]() {
    if (job.rank == 0)
      report.temp_peak_bytes = std::max(report.temp_peak_bytes, temp.bytesUsed());
  };
  measureTemp(); // points and tile results
  const bool edited = post.trim || post.fill;
  if (!options.tile_output.empty() && !edited && !(status = writeTileOutputs(job)).ok())
    return failed(status, TiledFailure::TILE_OUTPUT);
  report.seconds_mesh = watch.seconds();

  if (post.trim) {
    watch.restart();
    if (!(status = trim(job)).ok())
      return failed(status, TiledFailure::TEMP_FOLDER);
    report.seconds_trim = watch.seconds();
    measureTemp();
  }
  if (post.fill) {
    watch.restart();
    if (!(status = fill(job)).ok())
      return failed(status, TiledFailure::TEMP_FOLDER);
    report.seconds_fill = watch.seconds();
    measureTemp();
  }
  if (edited && job.rank == 0) // every rank is past the last sweep (its agreement)
    temp.removeFilesExcept({"result_", "tile_"}); // the post-passes' files: the
                                                  // writer reads results and points
  if (!options.tile_output.empty() && edited && !(status = writeTileOutputs(job)).ok())
    return failed(status, TiledFailure::TILE_OUTPUT);

  // The writer, rank 0 alone, is the points' last reader: every rank's descriptors
  // closed first, so the files it releases give their disk back at once.
  store.closeTileFiles();
  comm.barrier();
  watch.restart();
  status = writeOutput(job, output, format, write_options);
  report.seconds_write = watch.seconds();
  if (job.rank == 0) { // the tile results unless released, what the products left
    report.temp_bytes_after_write = temp.bytesUsed();
    report.temp_peak_bytes =
        std::max(report.temp_peak_bytes, report.temp_bytes_after_write);
  }
  comm.barrier(); // every rank is done with the points and the folder
  store.removeTileFiles();
  return status.ok() ? status : failed(status, TiledFailure::OUTPUT);
}

} // namespace pcl_vts
