// The tiled job (tiled_mesh.h): scan -> bucket -> order -> tiles -> stream out.
#include "block_store.h"
#include "known_space.h"
#include "temp_folder.h"
#include "tile_triangulation.h"

#include <pcl_vts/tiling/tiled_mesh.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numeric>

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

/// A file written once, then read back in order in chunks.
class SpoolFile {
 public:
  ~SpoolFile()
  {
    if (file_ != nullptr)
      std::fclose(file_);
  }
  Status open(const std::string& path)
  {
    path_ = path;
    file_ = std::fopen(path.c_str(), "w+b");
    if (file_ == nullptr)
      return error("create", errno);
    return Status::success();
  }
  Status append(const void* data, std::size_t bytes)
  {
    if (bytes != 0 && std::fwrite(data, 1, bytes, file_) != bytes)
      return error("write", errno);
    return Status::success();
  }
  Status finishWriting()
  {
    if (std::fflush(file_) != 0)
      return error("write", errno);
    return Status::success();
  }
  /// Reads the whole file from the start, `chunk` bytes at a time.
  template <typename Visit>
  Status forEachChunk(std::size_t chunk, const Visit& visit) const
  {
    std::rewind(file_);
    std::vector<char> buffer(chunk);
    for (;;) {
      const std::size_t got = std::fread(buffer.data(), 1, chunk, file_);
      if (got > 0)
        visit(buffer.data(), got);
      if (got < chunk) {
        if (std::ferror(file_))
          return error("read back", errno);
        return Status::success();
      }
    }
  }

 private:
  Status error(const char* what, int err) const
  {
    std::string why = std::strerror(err);
    if (err == ENOSPC || err == EDQUOT || err == EFBIG)
      why += " (the temporary folder is full: choose another with --temp-dir)";
    return Status::error(StatusCode::IO_ERROR,
                         std::string("cannot ") + what + " '" + path_ + "': " + why);
  }
  std::string path_;
  std::FILE* file_ = nullptr;
};

/// The streamed mesh: vertices (3 doubles) and triangles (3 uint32) in spool files.
class SpooledMesh : public MeshSource {
 public:
  SpooledMesh(const SpoolFile& vertices, const SpoolFile& triangles, std::uint64_t nv,
              std::uint64_t nt, bool exact)
      : vertices_(vertices)
      , triangles_(triangles)
      , nv_(nv)
      , nt_(nt)
      , exact_(exact)
  {}
  std::uint64_t vertexCount() const override { return nv_; }
  std::uint64_t triangleCount() const override { return nt_; }
  bool exactInFloat() const override { return exact_; }
  bool hasInsertedFlags() const override { return false; }
  Status forEachVertex(const VertexVisit& visit) const override
  {
    return vertices_.forEachChunk(CHUNK * 24, [&](const char* data, std::size_t bytes) {
      double xyz[3];
      for (std::size_t at = 0; at + 24 <= bytes; at += 24) {
        std::memcpy(xyz, data + at, 24);
        visit(xyz[0], xyz[1], xyz[2], false);
      }
    });
  }
  Status forEachTriangle(const TriangleVisit& visit) const override
  {
    return triangles_.forEachChunk(
        CHUNK * 12, [&](const char* data, std::size_t bytes) {
          std::uint32_t t[3];
          for (std::size_t at = 0; at + 12 <= bytes; at += 12) {
            std::memcpy(t, data + at, 12);
            visit(t[0], t[1], t[2]);
          }
        });
  }

 private:
  static constexpr std::size_t CHUNK = 1 << 16;
  const SpoolFile& vertices_;
  const SpoolFile& triangles_;
  std::uint64_t nv_, nt_;
  bool exact_;
};

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
  report = TiledMeshReport{};
  if (options.vts.reconstruction.trim || options.vts.reconstruction.fill)
    return Status::error(
        StatusCode::INVALID_PARAMETER,
        "trimming and hole filling do not run tiled yet: turn them off "
        "(--no-trim --no-fill) or raise the memory limit so the job "
        "runs in memory");
  if (Status s = validateOptions(options.vts); !s.ok())
    return s;
  MeshFileFormat format;
  if (Status s = meshFileFormatFromPath(output, format); !s.ok())
    return s;
  const auto progress = [&](const char* phase, std::uint64_t done,
                            std::uint64_t total) {
    if (options.progress)
      options.progress(TiledProgress{phase, done, total});
  };

  // 1. Scan: count and exact bounds of the finite points.
  auto start = Clock::now();
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  Status status = feed([&](const double* xyz, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      const double* p = xyz + 3 * i;
      ++report.points;
      if (!finitePoint(p)) {
        ++report.non_finite_dropped;
        continue;
      }
      x0 = std::min(x0, p[0]);
      y0 = std::min(y0, p[1]);
      x1 = std::max(x1, p[0]);
      y1 = std::max(y1, p[1]);
    }
    progress("scanning", report.points, 0);
    return Status::success();
  });
  if (!status.ok())
    return status;
  const std::uint64_t finite = report.points - report.non_finite_dropped;
  if (finite == 0)
    return Status::error(StatusCode::EMPTY_INPUT, "no finite point in the input");
  const TileFrame frame = TileFrame::fromBounds(x0, y0, x1, y1);
  report.seconds_scan = secondsSince(start);

  // 2. Levels: tiles sized by the memory limit, blocks of about a thousand points.
  const double fill = std::max(1.0 / 1024, std::max(x1 - x0, frame.side / 1e6) *
                                               std::max(y1 - y0, frame.side / 1e6) /
                                               (frame.side * frame.side));
  constexpr int MAX_BLOCK_LEVEL = 10; // 4^10 blocks: bounds and flags stay ~40 MB
  const double tile_target =
      std::max(1e4, static_cast<double>(options.memory_limit) / 400.0);
  int tile_level = options.tile_level >= 0
                       ? std::min(options.tile_level, MAX_BLOCK_LEVEL)
                       : levelFor(finite, fill, tile_target, MAX_BLOCK_LEVEL);
  int block_level = options.block_level >= 0
                        ? std::min(options.block_level, MAX_BLOCK_LEVEL)
                        : levelFor(finite, fill, 1024.0, MAX_BLOCK_LEVEL);
  block_level = std::max(block_level, std::min(tile_level + 2, MAX_BLOCK_LEVEL));
  tile_level = std::min(tile_level, block_level);
  report.tile_level = tile_level;
  report.block_level = block_level;

  // 3. Bucket into tile files, then order each by block.
  start = Clock::now();
  TempFolder temp;
  if (!(status = temp.create(options.temp_parent)).ok())
    return status;
  const std::size_t tiles = std::size_t{1} << (2 * tile_level);
  const std::size_t buffer_points = std::clamp<std::size_t>(
      static_cast<std::size_t>(options.memory_limit / 8 / (tiles * 24)), 64, 16384);
  BlockStore store(temp.path(), frame, tile_level, block_level, buffer_points);
  std::vector<double> chunk;
  std::uint64_t bucketed = 0, fed = 0;
  status = feed([&](const double* xyz, std::size_t n) {
    chunk.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (finitePoint(xyz + 3 * i))
        chunk.insert(chunk.end(), xyz + 3 * i, xyz + 3 * i + 3);
    fed += n;
    bucketed += chunk.size() / 3;
    progress("bucketing", fed, report.points);
    return store.add(chunk.data(), chunk.size() / 3);
  });
  std::vector<double>().swap(chunk);
  if (status.ok() && (fed != report.points || bucketed != finite))
    status = Status::error(
        StatusCode::IO_ERROR,
        "the input changed while it was read: " + std::to_string(report.points) +
            " points the first time, " + std::to_string(fed) + " the second");
  if (status.ok()) {
    progress("ordering", 0, 0);
    status = store.finish();
  }
  if (!status.ok())
    return status;
  report.temp_bytes = store.bytesOnDisk();
  report.seconds_bucket = secondsSince(start);

  // 4. Global vertex ids: prefix sums of the distinct points per block.
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

  // 5. Tiles in Morton order: their vertex id ranges follow each other, so the
  //    spooled vertices and sorted owned triangles come out in canonical order.
  start = Clock::now();
  KnownSpace space(frame, block_level, store.blockPoints(), store.blockBounds());
  TileContext context;
  context.frame = &frame;
  context.store = &store;
  context.space = &space;
  context.block_first_vertex = &first_vertex;
  context.options = options.vts;
  SpoolFile vertices, triangles;
  if (!(status = vertices.open(temp.path() + "/vertices.bin")).ok() ||
      !(status = triangles.open(temp.path() + "/triangles.bin")).ok())
    return status;
  bool exact = true;
  std::uint64_t tiles_with_points = 0;
  for (std::size_t t = 0; t < tiles; ++t)
    tiles_with_points += store.tilePoints()[t] != 0;
  std::uint64_t vertices_written = 0;
  TileResult tile;
  for (std::uint32_t t = 0; t < tiles; ++t) {
    if (store.tilePoints()[t] == 0)
      continue;
    if (!(status = triangulateTile(context, t, tile)).ok())
      return Status::error(status.code,
                           "tile " + std::to_string(t) + ": " + status.message);
    ++report.tiles;
    report.points_loaded += tile.points_loaded;
    report.max_tile_points = std::max(report.max_tile_points, tile.points_loaded);
    report.max_rounds = std::max(report.max_rounds, tile.rounds);
    report.triangles += tile.triangles.size() / 3;
    vertices_written += tile.xyz.size() / 3;
    for (double v : tile.xyz)
      exact = exact && exactInFloat(v);
    if (!(status = vertices.append(tile.xyz.data(), tile.xyz.size() * sizeof(double)))
             .ok() ||
        !(status = triangles.append(tile.triangles.data(),
                                    tile.triangles.size() * sizeof(std::uint32_t)))
             .ok())
      return status;
    progress("meshing", report.tiles, tiles_with_points);
  }
  if (vertices_written != report.vertices)
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "tiles wrote " + std::to_string(vertices_written) +
                             " vertices, the block index counts " +
                             std::to_string(report.vertices));
  if (!(status = vertices.finishWriting()).ok() ||
      !(status = triangles.finishWriting()).ok())
    return status;
  report.seconds_mesh = secondsSince(start);

  // 6. The output file, atomically.
  start = Clock::now();
  progress("writing", 0, 0);
  const SpooledMesh mesh(vertices, triangles, report.vertices, report.triangles, exact);
  status = writeMesh(output, mesh, write_options, &report.written);
  report.seconds_write = secondsSince(start);
  return status;
}

} // namespace pcl_vts
