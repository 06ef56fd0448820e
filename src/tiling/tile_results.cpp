// Tile result files and what is read back from them (tile_results.h).
#include "tile_results.h"
#include "tile_vertices.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <limits>
#include <memory>
#include <unistd.h>

namespace pcl_vts {
namespace {

bool exactInFloat(double v)
{
  return std::fabs(v) <= std::numeric_limits<float>::max() &&
         static_cast<double>(static_cast<float>(v)) == v;
}

std::string ioFailure(const char* what, const std::string& path, int err)
{
  std::string why = std::strerror(err);
  if (err == ENOSPC || err == EDQUOT || err == EFBIG)
    why += " (the temporary folder is full: free space there or choose another folder)";
  return std::string("cannot ") + what + " '" + path + "': " + why;
}

} // namespace

std::string resultPath(const std::string& folder, std::uint32_t tile)
{
  return folder + "/result_" + std::to_string(tile) + ".bin";
}

namespace {

/// A result file's header: vertex count, triangle count, all float-exact, checksum.
constexpr std::size_t HEADER_WORDS = 4;

using FilePtr = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

Status shortFile(const std::string& path)
{
  return Status::error(StatusCode::IO_ERROR,
                       "cannot read back '" + path + "': shorter than its header says");
}

/// Opens tile's result file and reads its header.
Status openResult(const std::string& path, FilePtr& file,
                  std::uint64_t (&header)[HEADER_WORDS])
{
  file.reset(std::fopen(path.c_str(), "rb"));
  if (!file)
    return Status::error(StatusCode::IO_ERROR, ioFailure("open", path, errno));
  if (std::fread(header, sizeof(header), 1, file.get()) != 1)
    return shortFile(path);
  return Status::success();
}

} // namespace

Status writeTileResult(const std::string& path, const TileResult& tile)
{
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr)
    return Status::error(StatusCode::IO_ERROR, ioFailure("create", path, errno));
  bool exact = true;
  for (double v : tile.xyz)
    exact = exact && exactInFloat(v);
  const std::uint64_t header[HEADER_WORDS] = {
      tile.xyz.size() / 3, tile.triangles.size() / 3, exact ? 1u : 0u,
      vertexChecksum(tile.xyz)};
  bool ok = std::fwrite(header, sizeof(header), 1, file) == 1;
  ok = ok && (tile.triangles.empty() ||
              std::fwrite(tile.triangles.data(), sizeof(std::uint32_t),
                          tile.triangles.size(), file) == tile.triangles.size());
  const int err = errno;
  if (std::fclose(file) != 0 || !ok)
    return Status::error(StatusCode::IO_ERROR,
                         ioFailure("write", path, ok ? errno : err));
  return Status::success();
}

Status TileResultFiles::readVertices(std::uint32_t tile, std::uint64_t count,
                                     std::uint64_t checksum,
                                     std::vector<double>& xyz) const
{
  if (Status s = rebuildTileVertices(*store, *frame, tile, rule, xyz); !s.ok())
    return s;
  if (xyz.size() != 3 * count || vertexChecksum(xyz) != checksum)
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "tile " + std::to_string(tile) + ": its " +
                             std::to_string(xyz.size() / 3) +
                             " vertices rebuilt from its points differ from the " +
                             std::to_string(count) + " it triangulated");
  return Status::success();
}

Status TileResultFiles::read(std::uint32_t tile, TileMeshData& data,
                             bool vertices) const
{
  const std::string path = resultPath(folder, tile);
  FilePtr file(nullptr, &std::fclose);
  std::uint64_t header[HEADER_WORDS];
  if (Status s = openResult(path, file, header); !s.ok())
    return s;
  data.triangles.resize(3 * header[1]);
  if (std::fread(data.triangles.data(), sizeof(std::uint32_t), data.triangles.size(),
                 file.get()) != data.triangles.size())
    return shortFile(path);
  data.xyz.clear();
  return vertices ? readVertices(tile, header[0], header[3], data.xyz)
                  : Status::success();
}

TileResultsMesh::TileResultsMesh(const TileResultFiles& files,
                                 std::vector<std::uint32_t> tiles)
    : files_(files)
    , tiles_(std::move(tiles))
    , released_(tiles_.size(), 0)
{}

Status TileResultsMesh::scan()
{
  nv_ = nt_ = 0;
  exact_ = true;
  vertices_.clear();
  for (std::uint32_t t : tiles_) {
    FilePtr file(nullptr, &std::fclose);
    std::uint64_t header[HEADER_WORDS];
    if (Status s = openResult(resultPath(files_.folder, t), file, header); !s.ok())
      return s;
    nv_ += header[0];
    nt_ += header[1];
    exact_ = exact_ && header[2] != 0;
    vertices_.push_back({header[0], header[3]});
  }
  return Status::success();
}

Status TileResultsMesh::checkNotReleased(std::size_t k, std::uint8_t bit) const
{
  if (release_ && (released_[k] & bit) != 0)
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "tile " + std::to_string(tiles_[k]) +
                             ": a result section read again after its release");
  return Status::success();
}

Status TileResultsMesh::forEachVertex(const VertexVisit& visit) const
{
  if (vertices_.size() != tiles_.size())
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "the tile results' vertices read before their headers");
  std::vector<double> xyz;
  for (std::size_t k = 0; k < tiles_.size(); ++k) {
    const std::uint32_t t = tiles_[k];
    if (Status s = checkNotReleased(k, 1); !s.ok())
      return s;
    if (Status s = files_.readVertices(t, vertices_[k][0], vertices_[k][1], xyz);
        !s.ok())
      return s;
    for (std::size_t v = 0; v < xyz.size(); v += 3)
      visit(xyz[v], xyz[v + 1], xyz[v + 2], false);
    if (release_) { // the tile's points are read for the last time
      files_.store->releaseTileFile(t);
      if ((released_[k] |= 1) == 3)
        ::unlink(resultPath(files_.folder, t).c_str());
    }
  }
  return Status::success();
}

Status TileResultsMesh::forEachTriangle(const TriangleVisit& visit) const
{
  std::vector<std::uint32_t> buffer;
  for (std::size_t k = 0; k < tiles_.size(); ++k) {
    const std::uint32_t t = tiles_[k];
    if (Status s = checkNotReleased(k, 2); !s.ok())
      return s;
    const std::string path = resultPath(files_.folder, t);
    FilePtr file(nullptr, &std::fclose);
    std::uint64_t header[HEADER_WORDS];
    if (Status s = openResult(path, file, header); !s.ok())
      return s;
    // One sequential read per tile, in chunks.
    for (std::uint64_t done = 0; done < header[1];) {
      const std::size_t n =
          static_cast<std::size_t>(std::min<std::uint64_t>(header[1] - done, 1 << 16));
      buffer.resize(3 * n);
      if (std::fread(buffer.data(), sizeof(std::uint32_t), buffer.size(), file.get()) !=
          buffer.size())
        return shortFile(path);
      for (std::size_t j = 0; j < buffer.size(); j += 3)
        visit(buffer[j], buffer[j + 1], buffer[j + 2]);
      done += n;
    }
    file.reset();
    if (release_ && (released_[k] |= 2) == 3)
      ::unlink(path.c_str());
  }
  return Status::success();
}

std::size_t VertexOwners::tileOf(std::uint64_t id) const
{
  return static_cast<std::size_t>(std::upper_bound(first.begin(), first.end(), id) -
                                  first.begin()) -
         1;
}

namespace {

/// The final ids of a run with inserted points: input ids shifted by the points
/// inserted before them (tiled_fill.h), and back.
struct FinalIds {
  const TileMeshEdits* edits;
  std::uint64_t finalOf(std::uint64_t input) const
  {
    if (edits == nullptr || edits->inputs_before == nullptr)
      return input;
    const std::vector<std::uint64_t>& before = *edits->inputs_before;
    return input +
           static_cast<std::uint64_t>(
               std::upper_bound(before.begin(), before.end(), input) - before.begin());
  }
  /// How many inserted points have final ids below f (inserted j has the final id
  /// before[j] + j, increasing in j).
  std::size_t insertedBelow(std::uint64_t f) const
  {
    if (edits == nullptr || edits->inputs_before == nullptr)
      return 0;
    const std::vector<std::uint64_t>& before = *edits->inputs_before;
    std::size_t low = 0, high = before.size();
    while (low < high) {
      const std::size_t mid = (low + high) / 2;
      if (before[mid] + mid < f)
        low = mid + 1;
      else
        high = mid;
    }
    return low;
  }
  /// The inserted point with final id f (its index), or SIZE_MAX for an input.
  std::size_t insertedAt(std::uint64_t f) const
  {
    const std::size_t j = insertedBelow(f);
    const std::vector<std::uint64_t>* before =
        edits != nullptr ? edits->inputs_before : nullptr;
    return before != nullptr && j < before->size() && (*before)[j] + j == f ? j
                                                                            : SIZE_MAX;
  }
  /// The input id of a final id that is not inserted.
  std::uint64_t inputOf(std::uint64_t f) const { return f - insertedBelow(f); }
};

} // namespace

/// Writes tile k's mesh (its owned triangles, every vertex they use and its own
/// vertices, ids renumbered in global order) and returns its index line.
Status writeTileMesh(const TileResultFiles& files, const std::string& out_folder,
                     const TileFrame& frame, int tile_level, const VertexOwners& owners,
                     const TileMeshEdits* edits, std::size_t k, std::string& index_line)
{
  const std::uint32_t tile = owners.tiles[k];
  TileMeshData own;
  if (Status s = files.read(tile, own, true); !s.ok())
    return s;
  const FinalIds final_ids{edits};
  const std::size_t tiles = owners.tiles.size();
  const std::uint64_t inserted_count =
      edits != nullptr && edits->inserted != nullptr ? edits->inserted->size() : 0;
  const std::uint64_t lo = k == 0 ? 0 : final_ids.finalOf(owners.first[k]);
  const std::uint64_t hi = k + 1 == tiles ? owners.first[tiles] + inserted_count
                                          : final_ids.finalOf(owners.first[k + 1]);
  // Its triangles, in final ids: those it owns less the trimmed ones, and the hole
  // patches' whose smallest vertex is its own.
  std::vector<TriangleKey> triangles;
  for (std::size_t t = 0; t < own.triangles.size(); t += 3) {
    const TriangleKey key{own.triangles[t], own.triangles[t + 1], own.triangles[t + 2]};
    if (edits != nullptr && edits->removed != nullptr &&
        std::binary_search(edits->removed->begin(), edits->removed->end(), key))
      continue;
    triangles.push_back({static_cast<std::uint32_t>(final_ids.finalOf(key[0])),
                         static_cast<std::uint32_t>(final_ids.finalOf(key[1])),
                         static_cast<std::uint32_t>(final_ids.finalOf(key[2]))});
  }
  if (edits != nullptr && edits->added != nullptr)
    for (const TriangleKey& key : *edits->added)
      if (key[0] >= lo && key[0] < hi)
        triangles.push_back(key);
  std::sort(triangles.begin(), triangles.end());
  std::vector<std::uint64_t> ids;
  for (std::uint64_t v = lo; v < hi; ++v)
    ids.push_back(v);
  for (const TriangleKey& key : triangles)
    for (std::uint32_t v : key)
      if (v < lo || v >= hi)
        ids.push_back(v);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  TriangleMesh mesh;
  mesh.xy.resize(ids.size());
  mesh.z.resize(ids.size());
  std::vector<std::uint8_t> flags(ids.size(), 0);
  std::size_t neighbour = SIZE_MAX;
  TileMeshData other;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (const std::size_t j = final_ids.insertedAt(ids[i]); j != SIZE_MAX) {
      const std::array<double, 3>& p = (*edits->inserted)[j];
      mesh.xy[i] = {p[0], p[1]};
      mesh.z[i] = p[2];
      flags[i] = 1;
      continue;
    }
    const std::uint64_t input = final_ids.inputOf(ids[i]);
    const std::size_t owner = owners.tileOf(input);
    const TileMeshData* data = &own;
    if (owner != k) {
      if (owner != neighbour) {
        if (Status s = files.read(owners.tiles[owner], other, true); !s.ok())
          return s;
        neighbour = owner;
      }
      data = &other;
    }
    const std::size_t at = 3 * static_cast<std::size_t>(input - owners.first[owner]);
    mesh.xy[i] = {data->xyz[at], data->xyz[at + 1]};
    mesh.z[i] = data->xyz[at + 2];
  }
  mesh.triangles.reserve(3 * triangles.size());
  for (const TriangleKey& key : triangles)
    for (std::uint32_t v : key)
      mesh.triangles.push_back(static_cast<VertexId>(
          std::lower_bound(ids.begin(), ids.end(), std::uint64_t{v}) - ids.begin()));
  const std::uint32_t column = gatherBits(tile), row = gatherBits(tile >> 1);
  const std::string name =
      "tile_" + std::to_string(column) + "_" + std::to_string(row) + ".ply";
  MeshWriteOptions options;
  options.comment =
      "pcl_vts tile " + std::to_string(column) + " " + std::to_string(row) +
      " of level " + std::to_string(tile_level) +
      (edits == nullptr ? ": its triangles of the global Delaunay triangulation"
                        : ": its triangles of the global surface mesh");
  if (edits != nullptr && edits->inserted != nullptr)
    options.inserted = &flags; // hole filling ran: its points are marked
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

} // namespace pcl_vts
