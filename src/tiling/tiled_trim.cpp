// Trimming a tiled mesh, one sweep over the tiles per step (tiled_trim.h):
//   send (each triangle to the tiles of its other corners) -> own spacing ->
//   local spacing -> classify -> gather the fans of the oversized -> peel in memory.
#include "tile_sweep.h"
#include "tiled_trim.h"

#include <pcl_vts/core/point_spacing.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

namespace pcl_vts {

std::string positionsPath(const std::string& folder)
{
  return folder + "/post_xyz.bin";
}

std::string ownSpacingPath(const std::string& folder)
{
  return folder + "/post_own.bin";
}

namespace {

std::string crossPath(const std::string& folder, std::size_t k)
{
  return folder + "/trim_around_" + std::to_string(k) + ".bin";
}

/// One tile's vertices and every triangle around them: those it owns and those
/// other tiles own and sent it.
struct TileAround {
  std::uint64_t lo = 0, hi = 0; ///< its vertex ids
  TileMeshData data;
  std::vector<std::uint32_t> around; ///< owned, then sent
  /// Neighbours of each vertex lo + i: ids[start[i] .. start[i + 1]), sorted.
  std::vector<std::size_t> start;
  std::vector<std::uint32_t> ring;
};

Status loadAround(const TileResultFiles& results, const VertexOwners& owners, int ranks,
                  std::size_t k, TileAround& tile)
{
  const std::string& folder = results.folder;
  tile.lo = owners.first[k];
  tile.hi = owners.first[k + 1];
  if (Status s = results.read(owners.tiles[k], tile.data, false); !s.ok())
    return s;
  tile.around = tile.data.triangles;
  for (int r = 0; r < ranks; ++r) // the triangles each rank sent it
    if (Status s =
            readWords(crossPath(folder, k) + "." + std::to_string(r), tile.around, 3);
        !s.ok())
      return s;
  // The rings: both other corners of every triangle around a vertex, once each.
  // Counted into rows first, then each short row sorted: no sort of the whole tile.
  const std::size_t n = static_cast<std::size_t>(tile.hi - tile.lo);
  std::vector<std::size_t> row(n + 1, 0);
  for (const std::uint32_t v : tile.around)
    if (v >= tile.lo && v < tile.hi)
      row[v - tile.lo + 1] += 2;
  for (std::size_t i = 0; i < n; ++i)
    row[i + 1] += row[i];
  std::vector<std::uint32_t> all(row[n]);
  std::vector<std::size_t> fill(row.begin(), row.end() - 1);
  for (std::size_t t = 0; t < tile.around.size(); t += 3)
    for (std::size_t j = 0; j < 3; ++j) {
      const std::uint32_t v = tile.around[t + j];
      if (v < tile.lo || v >= tile.hi)
        continue;
      std::size_t& at = fill[v - tile.lo];
      all[at++] = tile.around[t + (j + 1) % 3];
      all[at++] = tile.around[t + (j + 2) % 3];
    }
  tile.start.assign(n + 1, 0);
  tile.ring.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const auto first = all.begin() + static_cast<std::ptrdiff_t>(row[i]);
    const auto last = all.begin() + static_cast<std::ptrdiff_t>(row[i + 1]);
    std::sort(first, last);
    tile.ring.insert(tile.ring.end(), first, std::unique(first, last));
    tile.start[i + 1] = tile.ring.size();
  }
  return Status::success();
}

/// Values of the vertices a tile looks at: its own range read at once, the others
/// (neighbours in other tiles) one by one.
class Lookup {
 public:
  Lookup(const VertexRecords& file, std::size_t doubles)
      : file_(file)
      , doubles_(doubles)
  {}
  Status load(const TileAround& tile, const std::vector<std::uint32_t>& ids)
  {
    lo_ = tile.lo;
    hi_ = tile.hi;
    mine_.resize(static_cast<std::size_t>(hi_ - lo_) * doubles_);
    if (Status s = file_.read(lo_, static_cast<std::size_t>(hi_ - lo_), mine_.data());
        !s.ok())
      return s;
    foreign_.clear();
    for (const std::uint32_t id : ids)
      if (id < lo_ || id >= hi_)
        foreign_.emplace(id, 0);
    values_.resize(foreign_.size() * doubles_);
    std::size_t slot = 0;
    for (auto& [id, at] : foreign_) {
      at = slot;
      if (Status s = file_.read(id, 1, values_.data() + slot * doubles_); !s.ok())
        return s;
      ++slot;
    }
    return Status::success();
  }
  const double* operator[](std::uint32_t id) const
  {
    if (id >= lo_ && id < hi_)
      return mine_.data() + static_cast<std::size_t>(id - lo_) * doubles_;
    return values_.data() + foreign_.at(id) * doubles_;
  }

 private:
  const VertexRecords& file_;
  std::size_t doubles_;
  std::uint64_t lo_ = 0, hi_ = 0;
  std::vector<double> mine_, values_;
  std::map<std::uint32_t, std::size_t> foreign_;
};

/// A sweep's files and team.
struct Pass {
  const TileResultFiles& results;
  const std::string& folder;
  const VertexOwners& owners;
  const SweepTeam& team;
  std::size_t tiles() const { return owners.tiles.size(); }
  /// What tile k found in a sweep, for rank 0.
  std::string findings(const char* what, std::size_t k) const
  {
    return folder + "/post_" + what + "_" + std::to_string(k) + ".bin";
  }
};

/// Step 1: positions by id, and every triangle sent to the tiles of its corners
/// that do not own it (into files per receiving tile and sending rank: no two
/// writers share a file).
Status sendTriangles(const Pass& pass, const VertexRecords& positions)
{
  std::mutex mutex; // one writer of this rank's files at a time
  const std::string rank = "." + std::to_string(pass.team.comm.rank());
  return pass.team.forEachTile(pass.tiles(), [&](std::size_t k) {
    TileMeshData data;
    if (Status s = pass.results.read(pass.owners.tiles[k], data, true); !s.ok())
      return s;
    if (Status s = positions.write(pass.owners.first[k], data.xyz); !s.ok())
      return s;
    std::map<std::size_t, std::vector<std::uint32_t>> outbox;
    for (std::size_t t = 0; t < data.triangles.size(); t += 3) {
      std::size_t sent = k;
      for (int j = 1; j < 3; ++j) { // corner 0, the smallest, is k's own
        const std::size_t u = pass.owners.tileOf(data.triangles[t + j]);
        if (u == k || u == sent)
          continue; // owned here, or sent already
        sent = u;
        std::vector<std::uint32_t>& box = outbox[u];
        box.insert(box.end(), data.triangles.begin() + static_cast<std::ptrdiff_t>(t),
                   data.triangles.begin() + static_cast<std::ptrdiff_t>(t + 3));
      }
    }
    const std::lock_guard<std::mutex> lock(mutex);
    for (const auto& [u, ids] : outbox)
      if (Status s = appendWords(crossPath(pass.folder, u) + rank, ids); !s.ok())
        return s;
    return Status::success();
  });
}

double distance(const double* p, const double* q)
{
  const double dx = p[0] - q[0], dy = p[1] - q[1];
  return std::sqrt(dx * dx + dy * dy); // as measurePointSpacing
}

/// Steps 2 and 3: per vertex the median of its edges (own), then the median of its
/// own and its neighbours' (local), as measurePointSpacing.
Status measureSpacing(const Pass& pass, const VertexRecords& positions,
                      const VertexRecords& own, const VertexRecords& local)
{
  for (const bool second : {false, true}) {
    Status s = pass.team.forEachTile(pass.tiles(), [&](std::size_t k) {
      TileAround tile;
      if (Status r =
              loadAround(pass.results, pass.owners, pass.team.comm.size(), k, tile);
          !r.ok())
        return r;
      Lookup lookup(second ? own : positions, second ? 1 : 3);
      if (Status r = lookup.load(tile, tile.ring); !r.ok())
        return r;
      const std::size_t n = static_cast<std::size_t>(tile.hi - tile.lo);
      std::vector<double> out(n, 0.0), values;
      for (std::size_t i = 0; i < n; ++i) {
        if (tile.start[i] == tile.start[i + 1])
          continue; // no triangle: 0, as in memory
        const auto v = static_cast<std::uint32_t>(tile.lo + i);
        values.clear();
        if (second)
          values.push_back(*lookup[v]);
        for (std::size_t q = tile.start[i]; q < tile.start[i + 1]; ++q)
          values.push_back(second ? *lookup[tile.ring[q]]
                                  : distance(lookup[v], lookup[tile.ring[q]]));
        out[i] = medianOf(values);
      }
      return (second ? local : own).write(tile.lo, out);
    });
    if (!s.ok())
      return s;
  }
  return Status::success();
}

/// An oversized triangle and its flags, as a tile writes it for rank 0.
struct Oversized {
  TriangleKey key;
  std::uint32_t flags;
};

/// Step 4: the oversized triangles of every tile, with their flags, in tile order
/// (on rank 0).
Status classify(const Pass& pass, const TrimOptions& options,
                const VertexRecords& positions, const VertexRecords& local,
                std::vector<TriangleKey>& oversized, std::vector<std::uint8_t>& flags)
{
  Status s = pass.team.forEachTile(pass.tiles(), [&](std::size_t k) {
    TileAround tile;
    tile.lo = pass.owners.first[k];
    tile.hi = pass.owners.first[k + 1];
    if (Status r = pass.results.read(pass.owners.tiles[k], tile.data, false); !r.ok())
      return r;
    Lookup xy(positions, 3), spacing(local, 1);
    if (Status r = xy.load(tile, tile.data.triangles); !r.ok())
      return r;
    if (Status r = spacing.load(tile, tile.data.triangles); !r.ok())
      return r;
    const std::vector<std::uint32_t>& ids = tile.data.triangles;
    std::vector<Oversized> found;
    for (std::size_t t = 0; t < ids.size(); t += 3) {
      const double scale =
          std::max({*spacing[ids[t]], *spacing[ids[t + 1]], *spacing[ids[t + 2]]});
      const double* p[3] = {xy[ids[t]], xy[ids[t + 1]], xy[ids[t + 2]]};
      const TriangleSize size =
          classifyTriangle(Point2{p[0][0], p[0][1]}, Point2{p[1][0], p[1][1]},
                           Point2{p[2][0], p[2][1]}, scale, options);
      if (size.oversized)
        found.push_back(
            {TriangleKey{ids[t], ids[t + 1], ids[t + 2]},
             static_cast<std::uint32_t>(OVERSIZED | (size.void_seed ? VOID_SEED : 0))});
    }
    return writeFindings(pass.findings("oversized", k), found);
  });
  std::vector<Oversized> found;
  for (std::size_t k = 0; s.ok() && pass.team.comm.rank() == 0 && k < pass.tiles();
       ++k) {
    found.clear();
    s = readFindings(pass.findings("oversized", k), found);
    for (const Oversized& o : found) {
      oversized.push_back(o.key);
      flags.push_back(static_cast<std::uint8_t>(o.flags));
    }
  }
  return agree(pass.team.comm, s);
}

/// Step 5: every triangle with a corner in `corners` (sorted, on every rank), in
/// tile order (on rank 0).
Status gatherFans(const Pass& pass, const std::vector<std::uint32_t>& corners,
                  std::vector<TriangleKey>& fans)
{
  Status s = pass.team.forEachTile(pass.tiles(), [&](std::size_t k) {
    TileMeshData data;
    if (Status r = pass.results.read(pass.owners.tiles[k], data, false); !r.ok())
      return r;
    std::vector<TriangleKey> found;
    for (std::size_t t = 0; t < data.triangles.size(); t += 3) {
      const TriangleKey key{data.triangles[t], data.triangles[t + 1],
                            data.triangles[t + 2]};
      if (std::any_of(key.begin(), key.end(), [&](std::uint32_t v) {
            return std::binary_search(corners.begin(), corners.end(), v);
          }))
        found.push_back(key);
    }
    return writeFindings(pass.findings("fans", k), found);
  });
  std::vector<TriangleKey> tile;
  for (std::size_t k = 0; s.ok() && pass.team.comm.rank() == 0 && k < pass.tiles();
       ++k) {
    s = readFindings(pass.findings("fans", k), tile);
    fans.insert(fans.end(), tile.begin(), tile.end());
  }
  return agree(pass.team.comm, s);
}

} // namespace

Status trimTiledMesh(const TileResultFiles& results, const VertexOwners& owners,
                     const TrimOptions& options, JobComm& comm, unsigned workers,
                     const SweepProgress::Report& report, TiledTrim& trim)
{
  const std::string& folder = results.folder;
  trim = TiledTrim{};
  if (Status s = validateTrimOptions(options); !s.ok())
    return s;
  VertexRecords positions(positionsPath(folder), 3), own(ownSpacingPath(folder), 1),
      local(folder + "/post_local.bin", 1);
  // Rank 0 makes the files, then every rank opens them.
  Status status;
  for (VertexRecords* file : {&positions, &own, &local})
    if (status.ok() && comm.rank() == 0)
      status = file->create();
  if (!(status = agree(comm, status)).ok())
    return status;
  for (VertexRecords* file : {&positions, &own, &local})
    if (status.ok() && comm.rank() != 0)
      status = file->openForWriting();
  if (!(status = agree(comm, status)).ok())
    return status;
  // Five sweeps: send, two spacings, classify, gather; this rank takes its share.
  SweepProgress progress(report, 5 * owners.tiles.size() /
                                     static_cast<std::size_t>(comm.size()));
  const SweepTeam team{comm, workers, progress};
  const Pass pass{results, folder, owners, team};
  if (Status s = sendTriangles(pass, positions); !s.ok())
    return s;
  if (Status s = measureSpacing(pass, positions, own, local); !s.ok())
    return s;
  std::vector<TriangleKey> oversized;
  std::vector<std::uint8_t> oversized_flags;
  if (Status s = classify(pass, options, positions, local, oversized, oversized_flags);
      !s.ok())
    return s;
  if (comm.rank() == 0 && !std::is_sorted(oversized.begin(), oversized.end()))
    status = Status::error(StatusCode::INTERNAL_ERROR,
                           "the tile results are not in the global triangle order");
  if (!(status = agree(comm, status)).ok())
    return status;

  // The sub-mesh: the oversized triangles and every triangle around their corners,
  // vertices renumbered in increasing global id, triangles in the global order.
  std::vector<std::uint32_t> corners;
  for (const TriangleKey& key : oversized)
    corners.insert(corners.end(), key.begin(), key.end());
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  broadcastIds(comm, corners);
  if (corners.empty())
    return Status::success();
  std::vector<TriangleKey> fans;
  if (Status s = gatherFans(pass, corners, fans); !s.ok())
    return s;
  if (comm.rank() != 0)
    return Status::success(); // rank 0 peels
  std::vector<std::uint32_t> ids;
  for (const TriangleKey& key : fans)
    ids.insert(ids.end(), key.begin(), key.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  TriangleMesh mesh;
  if (Status s = loadPart(positions, ids, fans, mesh); !s.ok())
    return s;
  std::vector<std::uint8_t> flags(fans.size(), 0);
  for (std::size_t t = 0; t < fans.size(); ++t) {
    const auto at = std::lower_bound(oversized.begin(), oversized.end(), fans[t]);
    if (at != oversized.end() && *at == fans[t])
      flags[t] = oversized_flags[static_cast<std::size_t>(at - oversized.begin())];
  }
  if (!mesh.rebuildHalfedges())
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "the triangles around the oversized ones are not manifold");
  std::vector<bool> removed;
  trim.result.kept_to_stay_manifold =
      peelOutwardTriangles(mesh, flags, options.open_voids, removed);
  std::vector<bool> keeps(ids.size(), false);
  for (std::size_t t = 0; t < fans.size(); ++t) {
    if (removed[t])
      trim.removed.push_back(fans[t]);
    else
      for (int j = 0; j < 3; ++j)
        keeps[mesh.triangles[3 * t + j]] = true;
  }
  trim.result.triangles_removed = trim.removed.size();
  // A corner of an oversized triangle has its whole fan here: lost if none is kept.
  for (const std::uint32_t v : corners)
    trim.result.vertices_lost += keeps[localIdOf(ids, v)] ? 0 : 1;
  trim.corners = std::move(corners);
  return Status::success();
}

Status TrimmedMesh::forEachTriangle(const TriangleVisit& visit) const
{
  // The stream is in the global order, as the removed list: a cursor walks both.
  std::size_t next = 0;
  return base_.forEachTriangle([&](VertexId a, VertexId b, VertexId c) {
    const TriangleKey key{a, b, c};
    while (next < removed_.size() && removed_[next] < key)
      ++next;
    if (next < removed_.size() && removed_[next] == key)
      return;
    visit(a, b, c);
  });
}

} // namespace pcl_vts
