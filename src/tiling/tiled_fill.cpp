// Hole filling on a tiled mesh, in sweeps over the tiles (tiled_fill.h):
//   grow rings from the removed triangles' corners -> gather the part -> select the
//   global median spacing -> fill the part -> place the inserted points.
#include "tile_sweep.h"
#include "tiled_fill.h"

#include <pcl_vts/core/point_spacing.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

namespace pcl_vts {
namespace {

bool contains(const std::vector<std::uint32_t>& sorted, std::uint32_t v)
{
  return std::binary_search(sorted.begin(), sorted.end(), v);
}

/// An input vertex's id once the inserted points are placed: shifted by those before.
std::uint32_t finalIdOf(const std::vector<std::uint64_t>& inputs_before,
                        std::uint64_t id)
{
  const auto shift = std::upper_bound(inputs_before.begin(), inputs_before.end(), id) -
                     inputs_before.begin();
  return static_cast<std::uint32_t>(id + static_cast<std::uint64_t>(shift));
}

void sortUnique(std::vector<std::uint32_t>& ids)
{
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
}

/// Every triangle with a corner in `region` (sorted, on every rank), in the global
/// order (on rank 0); with `removed`, less those.
Status trianglesTouching(const TileResultFiles& results, const VertexOwners& owners,
                         const SweepTeam& team,
                         const std::vector<std::uint32_t>& region,
                         const std::vector<TriangleKey>* removed,
                         std::vector<TriangleKey>& found)
{
  const auto findings = [&](std::size_t k) {
    return results.folder + "/post_touching_" + std::to_string(k) + ".bin";
  };
  Status s = team.forEachTile(owners.tiles.size(), [&](std::size_t k) {
    TileMeshData data;
    if (Status r = results.read(owners.tiles[k], data, false); !r.ok())
      return r;
    std::vector<TriangleKey> touching;
    for (std::size_t t = 0; t < data.triangles.size(); t += 3) {
      const TriangleKey key{data.triangles[t], data.triangles[t + 1],
                            data.triangles[t + 2]};
      if (contains(region, key[0]) || contains(region, key[1]) ||
          contains(region, key[2]))
        touching.push_back(key);
    }
    std::remove(findings(k).c_str()); // the last sweep's
    return writeFindings(findings(k), touching);
  });
  found.clear();
  std::vector<TriangleKey> tile;
  for (std::size_t k = 0; s.ok() && team.comm.rank() == 0 && k < owners.tiles.size();
       ++k) {
    tile.clear();
    s = readFindings(findings(k), tile);
    for (const TriangleKey& key : tile)
      if (removed == nullptr ||
          !std::binary_search(removed->begin(), removed->end(), key))
        found.push_back(key);
  }
  return agree(team.comm, s);
}

/// Each vertex's median edge over the triangles of mesh, for the vertices listed
/// (local ids); 0 for one without triangles (as measurePointSpacing leaves it).
std::vector<double> medianEdges(const TriangleMesh& mesh,
                                const std::vector<VertexId>& vertices)
{
  std::vector<std::vector<VertexId>> ring(mesh.vertexCount());
  std::vector<bool> wanted(mesh.vertexCount(), false);
  for (const VertexId v : vertices)
    wanted[v] = true;
  for (std::size_t e = 0; e < mesh.triangles.size(); ++e) {
    const VertexId v = mesh.triangles[e];
    if (!wanted[v])
      continue;
    ring[v].push_back(mesh.triangles[nextHalfedge(static_cast<HalfedgeId>(e))]);
    ring[v].push_back(mesh.triangles[prevHalfedge(static_cast<HalfedgeId>(e))]);
  }
  std::vector<double> out;
  std::vector<double> lengths;
  for (const VertexId v : vertices) {
    std::vector<VertexId>& r = ring[v];
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    lengths.clear();
    for (const VertexId w : r) {
      const double dx = mesh.xy[v].x - mesh.xy[w].x, dy = mesh.xy[v].y - mesh.xy[w].y;
      lengths.push_back(std::sqrt(dx * dx + dy * dy));
    }
    out.push_back(r.empty() ? 0.0 : medianOf(lengths));
  }
  return out;
}

/// The upper median of the spacing file's positive values, with `changed` (sorted
/// ids) taking `changed_values` instead: a radix selection on the bits of the doubles
/// (positive doubles order as their bit patterns), 16 bits per pass over the file.
Status selectMedian(const VertexRecords& own, std::uint64_t count,
                    const std::vector<std::uint32_t>& changed,
                    const std::vector<double>& changed_values, double& median)
{
  auto bitsOf = [](double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof(bits));
    return bits;
  };
  // Passes over every value: visit(bits) for each positive one.
  auto forEachValue = [&](const auto& visit) {
    std::vector<double> chunk;
    std::size_t next_changed = 0;
    for (std::uint64_t first = 0; first < count; first += chunk.size()) {
      chunk.resize(
          static_cast<std::size_t>(std::min<std::uint64_t>(count - first, 1 << 20)));
      if (Status s = own.read(first, chunk.size(), chunk.data()); !s.ok())
        return s;
      for (std::size_t i = 0; i < chunk.size(); ++i) {
        double v = chunk[i];
        if (next_changed < changed.size() && changed[next_changed] == first + i)
          v = changed_values[next_changed++];
        if (v > 0.0)
          visit(bitsOf(v));
      }
    }
    return Status::success();
  };
  std::uint64_t total = 0;
  if (Status s = forEachValue([&](std::uint64_t) { ++total; }); !s.ok())
    return s;
  median = 0.0;
  if (total == 0)
    return Status::success();
  std::uint64_t rank = total / 2; // as medianOf: the element at size / 2
  std::uint64_t prefix = 0;
  std::vector<std::uint64_t> histogram(1 << 16);
  for (int shift = 48; shift >= 0; shift -= 16) {
    std::fill(histogram.begin(), histogram.end(), 0);
    const std::uint64_t high_mask = shift == 48 ? 0 : ~std::uint64_t{0} << (shift + 16);
    Status s = forEachValue([&](std::uint64_t bits) {
      if ((bits & high_mask) == prefix)
        ++histogram[(bits >> shift) & 0xffff];
    });
    if (!s.ok())
      return s;
    std::uint64_t digit = 0;
    while (rank >= histogram[digit])
      rank -= histogram[digit++];
    prefix |= digit << shift;
  }
  std::memcpy(&median, &prefix, sizeof(median));
  return Status::success();
}

} // namespace

Status fillTiledMesh(const TileResultFiles& results, const VertexOwners& owners,
                     const TileFrame& frame, const FillOptions& options,
                     const TiledTrim& trim, JobComm& comm, unsigned workers,
                     const std::function<void(std::uint64_t, std::uint64_t)>& report,
                     TiledFill& fill)
{
  const std::string& folder = results.folder;
  fill = TiledFill{};
  if (Status s = validateFillOptions(options); !s.ok())
    return s;
  // The part: every kept triangle within max(1, rim_rings) rings of a rim vertex,
  // so that each rim vertex, its neighbours and the spline's sample rings have their
  // whole fans (rings grown over all triangles: a superset of the trimmed rings).
  // Rank 0 knows the removed triangles; every rank sweeps.
  std::vector<std::uint32_t> rims;
  for (const TriangleKey& key : trim.removed)
    rims.insert(rims.end(), key.begin(), key.end());
  sortUnique(rims);
  broadcastIds(comm, rims);
  if (rims.empty())
    return Status::success(); // a Delaunay triangulation has no hole
  std::vector<std::uint32_t> region = rims;
  std::vector<TriangleKey> triangles;
  const std::size_t rings = std::max<std::size_t>(1, options.rim_rings);
  SweepProgress progress(report, (rings + 1) * owners.tiles.size() /
                                     static_cast<std::size_t>(comm.size()));
  const SweepTeam team{comm, workers, progress};
  for (std::size_t ring = 0; ring < rings; ++ring) {
    if (Status s = trianglesTouching(results, owners, team, region, nullptr, triangles);
        !s.ok())
      return s;
    for (const TriangleKey& key : triangles)
      region.insert(region.end(), key.begin(), key.end());
    sortUnique(region);
    broadcastIds(comm, region);
  }
  if (Status s =
          trianglesTouching(results, owners, team, region, &trim.removed, triangles);
      !s.ok())
    return s;
  if (comm.rank() != 0)
    return Status::success(); // rank 0 fills
  std::vector<std::uint32_t> ids;
  for (const TriangleKey& key : triangles)
    ids.insert(ids.end(), key.begin(), key.end());
  ids.insert(ids.end(), rims.begin(), rims.end()); // also those left without triangles
  sortUnique(ids);
  VertexRecords positions(positionsPath(folder), 3), own(ownSpacingPath(folder), 1);
  if (Status s = positions.open(); !s.ok())
    return s;
  if (Status s = own.open(); !s.ok())
    return s;
  TriangleMesh part;
  if (Status s = loadPart(positions, ids, triangles, part); !s.ok())
    return s;
  if (!part.rebuildHalfedges())
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "the triangles around the holes are not manifold");

  // The global median spacing of the trimmed mesh: the rim vertices lost edges, every
  // other vertex keeps the spacing measured before the trim.
  std::vector<VertexId> rim_local;
  for (const std::uint32_t v : rims)
    rim_local.push_back(localIdOf(ids, v));
  const std::vector<double> rim_own = medianEdges(part, rim_local);
  MeshPart whole;
  if (Status s =
          selectMedian(own, owners.first.back(), rims, rim_own, whole.global_spacing);
      !s.ok())
    return s;
  std::vector<bool> is_rim(ids.size(), false);
  for (const VertexId v : rim_local)
    is_rim[v] = true;
  whole.real_boundary = [&](HalfedgeId e) { return is_rim[part.triangles[e]]; };
  const std::size_t part_vertices = part.vertexCount();
  const std::size_t part_corners = part.triangles.size();
  if (Status s = fillHolesOfPart(part, options, &whole, fill.result); !s.ok())
    return s;
  fill.result.inserted.clear();

  // The inserted points in canonical order, each after the input vertices smaller
  // than it (found by bisection over the positions file, which is in canonical order).
  const std::uint64_t inputs = owners.first.back();
  std::vector<VertexId> order;
  for (VertexId v = static_cast<VertexId>(part_vertices); v < part.vertexCount(); ++v)
    order.push_back(v);
  std::vector<std::uint32_t> code(part.vertexCount(), 0);
  for (const VertexId v : order)
    code[v] = frame.code(part.xy[v]);
  std::sort(order.begin(), order.end(), [&](VertexId a, VertexId b) {
    return canonicalLess(code[a], part.xy[a], code[b], part.xy[b]);
  });
  if (inputs + order.size() >
      static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "the filled mesh has more vertices than the 32-bit indices of "
                         "one mesh file hold");
  std::vector<VertexId> final_of_inserted(part.vertexCount(), 0);
  for (std::size_t j = 0; j < order.size(); ++j) {
    const VertexId v = order[j];
    std::uint64_t low = 0, high = inputs; // inputs in [0, low) are smaller
    while (low < high) {
      const std::uint64_t mid = low + (high - low) / 2;
      double p[3];
      if (Status s = positions.read(mid, 1, p); !s.ok())
        return s;
      const Point2 q{p[0], p[1]};
      if (canonicalLess(frame.code(q), q, code[v], part.xy[v]))
        low = mid + 1;
      else
        high = mid;
    }
    fill.inserted.push_back({part.xy[v].x, part.xy[v].y, part.z[v]});
    fill.inputs_before.push_back(low);
    final_of_inserted[v] = static_cast<VertexId>(low + j);
  }
  for (std::size_t e = part_corners; e < part.triangles.size(); e += 3) {
    TriangleKey key;
    for (int k = 0; k < 3; ++k) {
      const VertexId v = part.triangles[e + static_cast<std::size_t>(k)];
      key[static_cast<std::size_t>(k)] = v < part_vertices
                                             ? finalIdOf(fill.inputs_before, ids[v])
                                             : final_of_inserted[v];
    }
    std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
    fill.added.push_back(key);
  }
  std::sort(fill.added.begin(), fill.added.end());
  return Status::success();
}

FilledMesh::FilledMesh(const MeshSource& base, const TiledFill& fill)
    : base_(base)
    , fill_(fill)
{
  const std::vector<std::uint64_t>& before = fill.inputs_before;
  for (std::uint64_t b = 0; !before.empty() && b <= (before.back() >> BLOCK_BITS); ++b)
    block_first_.push_back(static_cast<std::size_t>(
        std::lower_bound(before.begin(), before.end(), b << BLOCK_BITS) -
        before.begin()));
  exact_ = base.exactInFloat();
  for (const auto& p : fill.inserted)
    for (const double v : p)
      exact_ = exact_ && std::fabs(v) <= std::numeric_limits<float>::max() &&
               static_cast<double>(static_cast<float>(v)) == v;
}

VertexId FilledMesh::finalId(VertexId input) const
{
  // Once per corner of every triangle written: the block table, then the few
  // inserted points of the block, instead of a bisection over all of them.
  const std::vector<std::uint64_t>& before = fill_.inputs_before;
  const std::uint64_t b = std::uint64_t{input} >> BLOCK_BITS;
  std::size_t j = b < block_first_.size() ? block_first_[b] : before.size();
  while (j < before.size() && before[j] <= input)
    ++j;
  return input + static_cast<VertexId>(j);
}

Status FilledMesh::forEachVertex(const VertexVisit& visit) const
{
  std::size_t j = 0;
  std::uint64_t v = 0;
  auto insertedUpTo = [&](std::uint64_t input) {
    for (; j < fill_.inserted.size() && fill_.inputs_before[j] <= input; ++j)
      visit(fill_.inserted[j][0], fill_.inserted[j][1], fill_.inserted[j][2], true);
  };
  Status s = base_.forEachVertex([&](double x, double y, double z, bool inserted) {
    insertedUpTo(v++);
    visit(x, y, z, inserted);
  });
  insertedUpTo(std::numeric_limits<std::uint64_t>::max());
  return s;
}

Status FilledMesh::forEachTriangle(const TriangleVisit& visit) const
{
  std::size_t j = 0;
  auto addedBefore = [&](const TriangleKey& key) {
    for (; j < fill_.added.size() && fill_.added[j] < key; ++j)
      visit(fill_.added[j][0], fill_.added[j][1], fill_.added[j][2]);
  };
  Status s = base_.forEachTriangle([&](VertexId a, VertexId b, VertexId c) {
    const TriangleKey key{finalId(a), finalId(b), finalId(c)};
    addedBefore(key);
    visit(key[0], key[1], key[2]);
  });
  addedBefore(TriangleKey{std::numeric_limits<std::uint32_t>::max(),
                          std::numeric_limits<std::uint32_t>::max(),
                          std::numeric_limits<std::uint32_t>::max()});
  return s;
}

} // namespace pcl_vts
