// The tiled job (tiled_mesh.h): scan -> bucket -> order -> tiles -> stream out.
#include "block_store.h"
#include "known_space.h"
#include "temp_folder.h"
#include "tile_triangulation.h"

#include <pcl_vts/core/atomic_file.h>
#include <pcl_vts/tiling/tiled_mesh.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>
#include <numeric>
#include <thread>

namespace pcl_vts {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

bool finitePoint(const double* p)
{
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

bool exactInFloat(double v)
{
  return std::fabs(v) <= std::numeric_limits<float>::max() &&
         static_cast<double>(static_cast<float>(v)) == v;
}

/// Smallest quadtree level whose nodes hold at most `target` points on average over
/// the part of the frame the box covers; never above max_level.
int levelFor(std::uint64_t points, double fill, double target, int max_level)
{
  int level = 0;
  while (level<max_level&& static_cast<double>(points) /
               (std::ldexp(1.0, 2 * level) * fill)>
             target)
    ++level;
  return level;
}

std::string resultPath(const std::string& folder, std::uint32_t tile)
{
  return folder + "/result_" + std::to_string(tile) + ".bin";
}

std::string ioFailure(const char* what, const std::string& path, int err)
{
  std::string why = std::strerror(err);
  if (err == ENOSPC || err == EDQUOT || err == EFBIG)
    why += " (the temporary folder is full: choose another with --temp-dir)";
  return std::string("cannot ") + what + " '" + path + "': " + why;
}

/// One tile's output: a header (vertex count, triangle count, all float-exact), the
/// vertices (3 doubles) and the owned triangles (3 uint32), canonical order.
Status writeTileResult(const std::string& path, const TileResult& tile)
{
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr)
    return Status::error(StatusCode::IO_ERROR, ioFailure("create", path, errno));
  bool exact = true;
  for (double v : tile.xyz)
    exact = exact && exactInFloat(v);
  const std::uint64_t header[3] = {tile.xyz.size() / 3, tile.triangles.size() / 3,
                                   exact ? 1u : 0u};
  bool ok = std::fwrite(header, sizeof(header), 1, file) == 1;
  ok =
      ok && (tile.xyz.empty() || std::fwrite(tile.xyz.data(), sizeof(double),
                                             tile.xyz.size(), file) == tile.xyz.size());
  ok = ok && (tile.triangles.empty() ||
              std::fwrite(tile.triangles.data(), sizeof(std::uint32_t),
                          tile.triangles.size(), file) == tile.triangles.size());
  const int err = errno;
  if (std::fclose(file) != 0 || !ok)
    return Status::error(StatusCode::IO_ERROR,
                         ioFailure("write", path, ok ? errno : err));
  return Status::success();
}

/// The whole mesh, read back tile by tile from the result files (rank 0).
class TileResultsMesh : public MeshSource {
 public:
  TileResultsMesh(std::string folder, std::vector<std::uint32_t> tiles)
      : folder_(std::move(folder))
      , tiles_(std::move(tiles))
  {}

  /// Reads every header: counts and float-exactness.
  Status scan()
  {
    nv_ = nt_ = 0;
    exact_ = true;
    for (std::uint32_t t : tiles_) {
      std::uint64_t header[3];
      if (Status s = readAt(t, 0, header, sizeof(header)); !s.ok())
        return s;
      nv_ += header[0];
      nt_ += header[1];
      exact_ = exact_ && header[2] != 0;
    }
    return Status::success();
  }
  std::uint64_t vertexCount() const override { return nv_; }
  std::uint64_t triangleCount() const override { return nt_; }
  bool exactInFloat() const override { return exact_; }
  bool hasInsertedFlags() const override { return false; }
  Status forEachVertex(const VertexVisit& visit) const override
  {
    return forEachSection(true, [&](const char* data, std::size_t count) {
      double xyz[3];
      for (std::size_t k = 0; k < count; ++k) {
        std::memcpy(xyz, data + 24 * k, 24);
        visit(xyz[0], xyz[1], xyz[2], false);
      }
    });
  }
  Status forEachTriangle(const TriangleVisit& visit) const override
  {
    return forEachSection(false, [&](const char* data, std::size_t count) {
      std::uint32_t t[3];
      for (std::size_t k = 0; k < count; ++k) {
        std::memcpy(t, data + 12 * k, 12);
        visit(t[0], t[1], t[2]);
      }
    });
  }

 private:
  Status readAt(std::uint32_t tile, long offset, void* data, std::size_t bytes) const
  {
    const std::string path = resultPath(folder_, tile);
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (file == nullptr)
      return Status::error(StatusCode::IO_ERROR, ioFailure("open", path, errno));
    const bool ok = std::fseek(file, offset, SEEK_SET) == 0 &&
                    std::fread(data, 1, bytes, file) == bytes;
    std::fclose(file);
    if (!ok)
      return Status::error(StatusCode::IO_ERROR, "cannot read back '" + path +
                                                     "': shorter than its header says");
    return Status::success();
  }

  /// Visits the vertex (or triangle) section of every tile, in tile order, in chunks.
  template <typename Visit>
  Status forEachSection(bool vertices, const Visit& visit) const
  {
    const std::size_t item = vertices ? 24 : 12;
    std::vector<char> buffer;
    for (std::uint32_t t : tiles_) {
      std::uint64_t header[3];
      if (Status s = readAt(t, 0, header, sizeof(header)); !s.ok())
        return s;
      const std::uint64_t count = vertices ? header[0] : header[1];
      long offset = static_cast<long>(sizeof(header) + (vertices ? 0 : 24 * header[0]));
      for (std::uint64_t done = 0; done < count;) {
        const std::size_t n =
            static_cast<std::size_t>(std::min<std::uint64_t>(count - done, 1 << 16));
        buffer.resize(n * item);
        if (Status s = readAt(t, offset, buffer.data(), buffer.size()); !s.ok())
          return s;
        visit(buffer.data(), n);
        done += n;
        offset += static_cast<long>(n * item);
      }
    }
    return Status::success();
  }

  std::string folder_;
  std::vector<std::uint32_t> tiles_;
  std::uint64_t nv_ = 0, nt_ = 0;
  bool exact_ = true;
};

/// A tile's result file read whole.
struct TileMeshData {
  std::vector<double> xyz;
  std::vector<std::uint32_t> triangles;
};

Status readTileResult(const std::string& path, TileMeshData& data)
{
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr)
    return Status::error(StatusCode::IO_ERROR, ioFailure("open", path, errno));
  std::uint64_t header[3] = {0, 0, 0};
  bool ok = std::fread(header, sizeof(header), 1, file) == 1;
  if (ok) {
    data.xyz.resize(3 * header[0]);
    data.triangles.resize(3 * header[1]);
    ok = std::fread(data.xyz.data(), sizeof(double), data.xyz.size(), file) ==
             data.xyz.size() &&
         std::fread(data.triangles.data(), sizeof(std::uint32_t), data.triangles.size(),
                    file) == data.triangles.size();
  }
  std::fclose(file);
  if (!ok)
    return Status::error(StatusCode::IO_ERROR, "cannot read back '" + path +
                                                   "': shorter than its header says");
  return Status::success();
}

/// Where every vertex id lives: the tiles with points, their first ids.
struct VertexOwners {
  std::vector<std::uint32_t> tiles;
  std::vector<std::uint64_t>
      first; ///< first id of each tile, plus the total at the end
  std::size_t tileOf(std::uint64_t id) const
  {
    return static_cast<std::size_t>(std::upper_bound(first.begin(), first.end(), id) -
                                    first.begin()) -
           1;
  }
};

/// Writes tile k's mesh (its owned triangles, every vertex they use and its own
/// vertices, ids renumbered in global order) and returns its index line.
Status writeTileMesh(const std::string& folder, const std::string& out_folder,
                     const TileFrame& frame, int tile_level, const VertexOwners& owners,
                     std::size_t k, std::string& index_line)
{
  const std::uint32_t tile = owners.tiles[k];
  TileMeshData own;
  if (Status s = readTileResult(resultPath(folder, tile), own); !s.ok())
    return s;
  std::vector<std::uint64_t> ids;
  for (std::uint64_t v = owners.first[k]; v < owners.first[k + 1]; ++v)
    ids.push_back(v);
  for (std::uint32_t v : own.triangles)
    if (v < owners.first[k] || v >= owners.first[k + 1])
      ids.push_back(v);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  TriangleMesh mesh;
  mesh.xy.resize(ids.size());
  mesh.z.resize(ids.size());
  std::size_t neighbour = SIZE_MAX;
  TileMeshData other;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const std::size_t owner = owners.tileOf(ids[i]);
    const TileMeshData* data = &own;
    if (owner != k) {
      if (owner != neighbour) {
        if (Status s = readTileResult(resultPath(folder, owners.tiles[owner]), other);
            !s.ok())
          return s;
        neighbour = owner;
      }
      data = &other;
    }
    const std::size_t at = 3 * static_cast<std::size_t>(ids[i] - owners.first[owner]);
    mesh.xy[i] = {data->xyz[at], data->xyz[at + 1]};
    mesh.z[i] = data->xyz[at + 2];
  }
  mesh.triangles.reserve(own.triangles.size());
  for (std::uint32_t v : own.triangles)
    mesh.triangles.push_back(static_cast<VertexId>(
        std::lower_bound(ids.begin(), ids.end(), std::uint64_t{v}) - ids.begin()));
  const std::uint32_t column = gatherBits(tile), row = gatherBits(tile >> 1);
  const std::string name =
      "tile_" + std::to_string(column) + "_" + std::to_string(row) + ".ply";
  MeshWriteOptions options;
  options.comment = "pcl_vts tile " + std::to_string(column) + " " +
                    std::to_string(row) + " of level " + std::to_string(tile_level) +
                    ": its triangles of the global Delaunay triangulation";
  if (Status s = writeMesh(out_folder + "/" + name, mesh, options); !s.ok())
    return s;
  const double cell = frame.side / static_cast<double>(1u << tile_level);
  char line[512];
  std::snprintf(line, sizeof(line), "%u,%u,%u,%.17g,%.17g,%.17g,%.17g,%zu,%zu,%s\n",
                tile, column, row, frame.min_x + column * cell,
                frame.min_y + row * cell, frame.min_x + (column + 1) * cell,
                frame.min_y + (row + 1) * cell, mesh.vertexCount(),
                mesh.triangleCount(), name.c_str());
  index_line = line;
  return Status::success();
}

/// Every rank learns whether any failed; the first failing rank's error wins.
Status agree(JobComm& comm, const Status& mine)
{
  std::vector<std::uint64_t> failed(static_cast<std::size_t>(comm.size()), 0);
  failed[static_cast<std::size_t>(comm.rank())] = mine.ok() ? 0 : 1;
  comm.sum(failed);
  const auto first = std::find(failed.begin(), failed.end(), 1u);
  if (first == failed.end())
    return Status::success();
  const int root = static_cast<int>(first - failed.begin());
  std::string bytes;
  if (comm.rank() == root)
    bytes = std::to_string(static_cast<int>(mine.code)) + " " + mine.message;
  comm.broadcast(bytes, root);
  const std::size_t space = bytes.find(' ');
  const auto code = static_cast<StatusCode>(std::stoi(bytes.substr(0, space)));
  const std::string message = bytes.substr(space + 1);
  return Status::error(code, comm.size() > 1
                                 ? "rank " + std::to_string(root) + ": " + message
                                 : message);
}

} // namespace

TileFrame frameOfMesh(const TriangleMesh& mesh,
                      const std::vector<std::uint8_t>* inserted)
{
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    if (inserted != nullptr && (*inserted)[v] != 0)
      continue;
    x0 = std::min(x0, mesh.xy[v].x);
    y0 = std::min(y0, mesh.xy[v].y);
    x1 = std::max(x1, mesh.xy[v].x);
    y1 = std::max(y1, mesh.xy[v].y);
  }
  return TileFrame::fromBounds(x0, y0, x1, y1);
}

void canonicalMesh(TriangleMesh& mesh, std::vector<std::uint8_t>* inserted)
{
  const TileFrame frame = frameOfMesh(mesh, inserted);
  const std::size_t nv = mesh.vertexCount();
  std::vector<std::uint32_t> code(nv);
  for (std::size_t v = 0; v < nv; ++v)
    code[v] = frame.code(mesh.xy[v]);
  std::vector<VertexId> order(nv);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](VertexId a, VertexId b) {
    return canonicalLess(code[a], mesh.xy[a], code[b], mesh.xy[b]);
  });
  std::vector<VertexId> rank(nv);
  TriangleMesh out;
  out.xy.resize(nv);
  out.z.resize(nv);
  std::vector<std::uint8_t> flags;
  for (std::size_t k = 0; k < nv; ++k) {
    rank[order[k]] = static_cast<VertexId>(k);
    out.xy[k] = mesh.xy[order[k]];
    out.z[k] = mesh.z[order[k]];
    if (inserted != nullptr)
      flags.push_back((*inserted)[order[k]]);
  }
  std::vector<std::array<VertexId, 3>> tris(mesh.triangleCount());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    std::array<VertexId, 3> g = {rank[mesh.triangles[3 * t]],
                                 rank[mesh.triangles[3 * t + 1]],
                                 rank[mesh.triangles[3 * t + 2]]};
    const int k = g[0] < g[1] ? (g[0] < g[2] ? 0 : 2) : (g[1] < g[2] ? 1 : 2);
    std::rotate(g.begin(), g.begin() + k, g.end());
    tris[t] = g;
  }
  std::sort(tris.begin(), tris.end());
  for (const auto& g : tris)
    out.triangles.insert(out.triangles.end(), g.begin(), g.end());
  out.rebuildHalfedges();
  mesh = std::move(out);
  if (inserted != nullptr)
    inserted->swap(flags);
}

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
  const int rank = comm.rank(), ranks = comm.size();
  Status status;
  if (options.vts.reconstruction.trim || options.vts.reconstruction.fill)
    status =
        Status::error(StatusCode::INVALID_PARAMETER,
                      "trimming and hole filling do not run tiled yet: turn them off "
                      "(--no-trim --no-fill) or raise the memory limit so the job "
                      "runs in memory");
  if (status.ok())
    status = validateOptions(options.vts);
  MeshFileFormat format;
  if (status.ok())
    status = meshFileFormatFromPath(output, format);
  if (!status.ok())
    return status; // the same on every rank
  const auto progress = [&](const char* phase, std::uint64_t done,
                            std::uint64_t total) {
    if (options.progress && rank == 0)
      options.progress(TiledProgress{phase, done, total});
  };
  // This rank's sources: a contiguous range, after the lower ranks'.
  const std::size_t first_source =
      inputs.count * static_cast<std::size_t>(rank) / static_cast<std::size_t>(ranks);
  const std::size_t last_source = inputs.count * static_cast<std::size_t>(rank + 1) /
                                  static_cast<std::size_t>(ranks);
  const auto readMine = [&](const PointSink& sink) {
    for (std::size_t k = first_source; k < last_source; ++k)
      if (Status s = inputs.read(k, sink); !s.ok())
        return s;
    return Status::success();
  };

  // 1. Scan: count and exact bounds of the finite points, over all ranks.
  auto start = Clock::now();
  std::vector<double> low = {HUGE_VAL, HUGE_VAL}, high = {-HUGE_VAL, -HUGE_VAL};
  std::vector<std::uint64_t> counts = {0, 0}; // points, non-finite
  status = readMine([&](const double* xyz, std::size_t n) {
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
    progress("scanning", counts[0], 0);
    return Status::success();
  });
  if (!(status = agree(comm, status)).ok())
    return status;
  const std::uint64_t my_points = counts[0];
  comm.sum(counts);
  comm.min(low);
  comm.max(high);
  report.points = counts[0];
  report.non_finite_dropped = counts[1];
  const std::uint64_t finite = report.points - report.non_finite_dropped;
  if (finite == 0)
    return Status::error(StatusCode::EMPTY_INPUT, "no finite point in the input");
  const double x0 = low[0], y0 = low[1], x1 = high[0], y1 = high[1];
  const TileFrame frame = TileFrame::fromBounds(x0, y0, x1, y1);
  report.seconds_scan = secondsSince(start);

  // 2. Levels: tiles sized by the memory limit shared by the workers (and at most
  //    TILE_POINTS_MAX), blocks of about BLOCK_POINTS. Every rank computes the same.
  unsigned workers = options.threads != 0
                         ? options.threads
                         : std::max(1u, std::thread::hardware_concurrency());
  const double fill = std::max(1.0 / 1024, std::max(x1 - x0, frame.side / 1e6) *
                                               std::max(y1 - y0, frame.side / 1e6) /
                                               (frame.side * frame.side));
  constexpr int MAX_BLOCK_LEVEL = 10; // 4^10 blocks: the index stays ~60 MB
  // Blocks of about 512 points: a thinner first halo than 1024 (1.44 points loaded
  // per point instead of 1.88 at 1e7, 10% faster), and the index stays small.
  constexpr double BLOCK_POINTS = 512.0;
  // Tiles of at most half a million points even when memory allows more: a tile and
  // its halo then stay near the caches, and 64 such tiles ran as fast as the whole
  // in memory (docs/scaling.md §5).
  constexpr double TILE_POINTS_MAX = 5e5;
  double tile_target = std::max(
      1e4, std::min(TILE_POINTS_MAX,
                    static_cast<double>(options.memory_limit) / 400.0 / workers));
  if (ranks > 1) // a few tiles per rank, or the ranks would wait for one another
    tile_target = std::min(tile_target,
                           std::max(1e4, static_cast<double>(finite) / (4.0 * ranks)));
  int tile_level = options.tile_level >= 0
                       ? std::min(options.tile_level, MAX_BLOCK_LEVEL)
                       : levelFor(finite, fill, tile_target, MAX_BLOCK_LEVEL);
  int block_level = options.block_level >= 0
                        ? std::min(options.block_level, MAX_BLOCK_LEVEL)
                        : levelFor(finite, fill, BLOCK_POINTS, MAX_BLOCK_LEVEL);
  // At least 8 x 8 blocks per tile, so that the first halo (one ring) is thin.
  block_level = std::max(block_level, std::min(tile_level + 3, MAX_BLOCK_LEVEL));
  tile_level = std::min(tile_level, block_level);
  report.tile_level = tile_level;
  report.block_level = block_level;
  {
    // The least this job can run in: the block index (counts, offsets, boxes, the
    // pyramid, each worker's flags), a bucket buffer per tile, and each worker
    // meshing a tile of the smallest size (1e4 points at ~400 B with its halo).
    const double blocks = std::ldexp(1.0, 2 * block_level);
    const double minimum = blocks * (62.0 + workers) +
                           std::ldexp(1.0, 2 * tile_level) * 1536.0 + workers * 4e6;
    if (static_cast<double>(options.memory_limit) < minimum)
      return Status::error(
          StatusCode::INVALID_PARAMETER,
          "--memory-limit " + std::to_string(options.memory_limit >> 20) +
              " MiB is below the " +
              std::to_string(static_cast<std::uint64_t>(minimum) >> 20) +
              " MiB this job needs at least (" + std::to_string(workers) +
              " tiles of 10000 points meshed at once, an index of " +
              std::to_string(static_cast<std::uint64_t>(blocks)) +
              " blocks): raise it, or lower --threads");
  }

  // 3. One temporary folder (rank 0 makes it, every rank writes into it).
  start = Clock::now();
  TempFolder temp;
  std::string folder;
  if (rank == 0) {
    status = temp.create(options.temp_parent);
    folder = temp.path();
  }
  if (!(status = agree(comm, status)).ok())
    return status;
  comm.broadcast(folder, 0);

  // 4. Bucket this rank's points into its part files, then order the tiles (shared
  //    out over the ranks) and share the block index.
  const std::size_t tiles = std::size_t{1} << (2 * tile_level);
  const std::size_t buffer_points = std::clamp<std::size_t>(
      static_cast<std::size_t>(options.memory_limit / 8 / (tiles * 24)), 64, 16384);
  BlockStore store(folder, frame, tile_level, block_level, buffer_points, rank, ranks);
  std::vector<double> chunk;
  std::uint64_t fed = 0, bucketed = 0;
  status = readMine([&](const double* xyz, std::size_t n) {
    chunk.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (finitePoint(xyz + 3 * i))
        chunk.insert(chunk.end(), xyz + 3 * i, xyz + 3 * i + 3);
    fed += n;
    bucketed += chunk.size() / 3;
    progress("bucketing", fed * static_cast<std::uint64_t>(ranks), report.points);
    return store.add(chunk.data(), chunk.size() / 3);
  });
  std::vector<double>().swap(chunk);
  if (status.ok() && fed != my_points)
    status = Status::error(
        StatusCode::IO_ERROR,
        "the input changed while it was read: " + std::to_string(my_points) +
            " points the first time, " + std::to_string(fed) + " the second");
  if (status.ok())
    status = store.flush();
  if (!(status = agree(comm, status)).ok())
    return status;
  {
    std::vector<std::uint64_t> bucketed_all = {bucketed};
    comm.sum(bucketed_all);
    if (bucketed_all[0] != finite)
      return Status::error(StatusCode::IO_ERROR, "the input changed while it was read");
  }
  progress("ordering", 0, 0);
  for (std::uint32_t t = static_cast<std::uint32_t>(rank); t < tiles && status.ok();
       t += static_cast<std::uint32_t>(ranks))
    status = store.orderTile(t);
  if (!(status = agree(comm, status)).ok())
    return status;
  store.shareIndex(comm);
  report.temp_bytes = store.bytesOnDisk(); // every rank's points, after shareIndex
  report.seconds_bucket = secondsSince(start);

  // 5. Global vertex ids: prefix sums of the distinct points per block.
  const std::vector<std::uint64_t>& distinct = store.blockDistinct();
  std::vector<std::uint64_t> first_vertex(distinct.size() + 1, 0);
  std::partial_sum(distinct.begin(), distinct.end(), first_vertex.begin() + 1);
  report.vertices = first_vertex.back();
  if (report.vertices >
      static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
    return Status::error(
        StatusCode::INVALID_PARAMETER,
        std::to_string(report.vertices) +
            " distinct points do not fit the 32-bit indices of one mesh "
            "file");
  if (report.vertices < 3)
    return Status::error(StatusCode::TOO_FEW_POINTS,
                         "fewer than 3 distinct XY positions (" +
                             std::to_string(report.vertices) + ")");

  // 6. Tiles: each worker of each rank takes the next tile of the shared counter, so
  //    ranks that finish early take more (tiles are unequal on real data). Each
  //    writes its result file; nothing depends on who meshed what.
  start = Clock::now();
  std::vector<std::uint32_t> occupied_tiles, mine; // mine: meshed here
  for (std::uint32_t t = 0; t < tiles; ++t)
    if (store.tilePoints(t) != 0)
      occupied_tiles.push_back(t);
  comm.startTasks();
  report.tiles = occupied_tiles.size();
  const KnownSpace space(frame, block_level, store.blockPoints(), store.blockBounds(),
                         store.globalHull());
  TileContext context;
  context.frame = &frame;
  context.store = &store;
  context.space = &space;
  context.block_first_vertex = &first_vertex;
  context.options = options.vts;
  workers = std::max(
      1u, std::min<unsigned>(workers, static_cast<unsigned>(occupied_tiles.size())));
  context.options.threads = std::max(
      1u, (options.threads != 0 ? options.threads
                                : std::max(1u, std::thread::hardware_concurrency())) /
              workers);
  std::mutex mutex;
  Status failure;
  std::vector<std::uint64_t> stats = {0, 0, 0}; // points loaded, largest tile, rounds
  unsigned max_rounds = 0;
  const auto work = [&]() {
    LoadedBlocks flags(space.blockCount(), 0);
    TileResult tile;
    for (;;) {
      {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!failure.ok())
          return;
      }
      const std::uint64_t k = comm.nextTask();
      if (k >= occupied_tiles.size())
        return;
      const std::uint32_t t = occupied_tiles[static_cast<std::size_t>(k)];
      Status s = triangulateTile(context, t, flags, tile);
      if (s.ok())
        s = writeTileResult(resultPath(folder, t), tile);
      const std::lock_guard<std::mutex> lock(mutex);
      if (!s.ok()) {
        if (failure.ok())
          failure =
              Status::error(s.code, "tile " + std::to_string(t) + ": " + s.message);
        return;
      }
      mine.push_back(static_cast<std::uint32_t>(k));
      stats[0] += tile.points_loaded;
      stats[1] = std::max(stats[1], tile.points_loaded);
      max_rounds = std::max(max_rounds, tile.rounds);
      stats[2] += tile.rounds;
      progress("meshing", k + 1, occupied_tiles.size());
    }
  };
  std::vector<std::thread> pool;
  for (unsigned w = 1; w < workers; ++w)
    pool.emplace_back(work);
  work();
  for (std::thread& thread : pool)
    thread.join();
  if (!(status = agree(comm, failure)).ok())
    return status;
  std::vector<double> largest = {static_cast<double>(stats[1]),
                                 static_cast<double>(max_rounds)};
  comm.max(largest);
  std::vector<std::uint64_t> loaded = {stats[0], stats[2]};
  comm.sum(loaded);
  report.points_loaded = loaded[0];
  report.rounds = loaded[1];
  report.max_tile_points = static_cast<std::uint64_t>(largest[0]);
  report.max_rounds = static_cast<unsigned>(largest[1]);
  report.seconds_mesh = secondsSince(start);

  // 7. Tile meshes (each rank its own tiles), then rank 0's index.
  if (!options.tile_output.empty()) {
    progress("writing tiles", 0, 0);
    VertexOwners owners;
    owners.tiles = occupied_tiles;
    const int shift = 2 * (block_level - tile_level);
    for (std::uint32_t t : occupied_tiles)
      owners.first.push_back(first_vertex[std::size_t{t} << shift]);
    owners.first.push_back(first_vertex.back());
    // Each rank writes the tiles it meshed; their index lines, "k line", go to all.
    std::vector<std::string> lines(occupied_tiles.size());
    std::string my_lines;
    for (std::size_t i = 0; i < mine.size() && status.ok(); ++i) {
      std::string line;
      status = writeTileMesh(folder, options.tile_output, frame, tile_level, owners,
                             mine[i], line);
      my_lines += std::to_string(mine[i]) + " " + line;
    }
    if (!(status = agree(comm, status)).ok())
      return status;
    for (int root = 0; root < ranks; ++root) {
      std::string bytes = my_lines;
      comm.broadcast(bytes, root);
      for (std::size_t at = 0; at < bytes.size();) {
        const std::size_t gap = bytes.find(' ', at), end = bytes.find('\n', at);
        lines[std::stoul(bytes.substr(at, gap - at))] =
            bytes.substr(gap + 1, end - gap);
        at = end + 1;
      }
    }
    if (rank == 0) {
      AtomicFile index(options.tile_output + "/index.csv");
      status = index.open();
      if (status.ok()) {
        index.write("tile,column,row,x0,y0,x1,y1,vertices,triangles,file\n");
        for (const std::string& line : lines)
          index.write(line);
        status = index.commit();
      }
    }
    if (!(status = agree(comm, status)).ok())
      return status;
  }

  // 8. Rank 0 writes the file, atomically, from the result files in tile order.
  start = Clock::now();
  progress("writing", 0, 0);
  if (rank == 0) {
    TileResultsMesh mesh(folder, occupied_tiles);
    status = mesh.scan();
    if (status.ok() && mesh.vertexCount() != report.vertices)
      status = Status::error(StatusCode::INTERNAL_ERROR,
                             "tiles wrote " + std::to_string(mesh.vertexCount()) +
                                 " vertices, the block index counts " +
                                 std::to_string(report.vertices));
    report.triangles = mesh.triangleCount();
    if (status.ok())
      status = writeMesh(output, mesh, write_options, &report.written);
  }
  status = agree(comm, status);
  std::vector<std::uint64_t> triangles = {report.triangles};
  comm.sum(triangles);
  report.triangles = triangles[0];
  report.seconds_write = secondsSince(start);
  comm.barrier(); // every rank is done with the folder before rank 0 removes it
  return status;
}

} // namespace pcl_vts
