#include "release_memory.h"
#include "strip_growth.h"

#include <pcl_vts/core/grid_triangulator.h>
#include <pcl_vts/core/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <string>
#include <tuple>

namespace pcl_vts {
namespace {

using detail::StripMesh;

/// A halfedge of an owned triangle whose twin another strip owns.
struct BorderRecord {
  VertexId low, high;  ///< the edge's vertices, sorted
  HalfedgeId halfedge; ///< global id
  bool operator<(const BorderRecord& r) const
  {
    return std::tie(low, high, halfedge) < std::tie(r.low, r.high, r.halfedge);
  }
};

/// Appends the owned triangles of one strip to the output, translating strip-local
/// twins to global ids and collecting the border halfedges.
void appendStrip(StripMesh& strip, std::vector<VertexId>& triangles,
                 std::vector<HalfedgeId>& halfedges, std::vector<BorderRecord>& border)
{
  const std::size_t grown = strip.owned.size();
  const std::size_t first = triangles.size() / 3;
  // Global triangle of each owned local one (the output grows page by page, in
  // order, while the strips before it have been released).
  std::vector<TriangleId> global(grown);
  auto next = static_cast<TriangleId>(first);
  for (std::size_t t = 0; t < grown; ++t)
    global[t] = strip.owned[t] ? next++ : INVALID_ID;
  triangles.resize(3 * static_cast<std::size_t>(next));
  halfedges.resize(3 * static_cast<std::size_t>(next));
  const VertexId* local_v = strip.triangles.data();
  const HalfedgeId* local_h = strip.halfedges.data();
  for (std::size_t t = 0; t < grown; ++t) {
    if (global[t] == INVALID_ID)
      continue;
    const std::size_t out = 3 * static_cast<std::size_t>(global[t]);
    for (std::size_t k = 0; k < 3; ++k) {
      const VertexId a = local_v[3 * t + k];
      const HalfedgeId h = local_h[3 * t + k];
      triangles[out + k] = a;
      if (h == detail::BORDER) {
        const VertexId b = local_v[3 * t + (k == 2 ? 0 : k + 1)];
        border.push_back(
            {std::min(a, b), std::max(a, b), static_cast<HalfedgeId>(out + k)});
        halfedges[out + k] = INVALID_ID;
      } else {
        halfedges[out + k] = h == detail::HULL ? INVALID_ID : 3 * global[h / 3] + h % 3;
      }
    }
  }
  strip = StripMesh();
}

} // namespace

static_assert(MAX_MESH_TRIANGLES == detail::OPEN_LIST_END / 3,
              "the public limit follows the halfedge slot encoding");

Status checkTriangleCapacity(std::size_t points, std::size_t hull_vertices)
{
  const std::size_t expected = 2 * points - std::min(points, hull_vertices + 2);
  if (expected <= MAX_MESH_TRIANGLES)
    return Status::success();
  return Status::error(
      StatusCode::CAPACITY_EXCEEDED,
      std::to_string(points) + " points need " + std::to_string(expected) +
          " triangles, beyond the limit of " + std::to_string(MAX_MESH_TRIANGLES) +
          " (32-bit halfedge ids, about " +
          "357.9 million points); split the "
          "input into tiles");
}

namespace {

/// Grows every strip of the layout (any thread, any order) into `strips`; the search
/// statistics summed over the workers.
Status growStrips(const CellGrid& grid, const CellPyramid& pyramid,
                  const CellSubdivision& subdivision,
                  const detail::HullEdges& hull_edges,
                  const detail::StripLayout& layout, unsigned threads,
                  bool cache_blocks, std::vector<StripMesh>& strips, SearchStats& stats)
{
  strips.assign(layout.count, StripMesh());
  std::vector<Status> results(layout.count);
  std::vector<HalfedgeId> open_head(grid.points.size(), detail::UNREACHED);
  const unsigned workers = std::max(1u, std::min<unsigned>(threads, layout.count));
  std::vector<SearchStats> worker_stats(workers);
  std::atomic<std::uint32_t> next_strip{0};
  const auto work = [&](unsigned w) {
    MediatrixSearch search(grid, pyramid, subdivision);
    for (std::uint32_t s = next_strip++; s < layout.count; s = next_strip++)
      results[s] = detail::growStrip(grid, pyramid, layout, s, hull_edges, search,
                                     open_head, strips[s], cache_blocks);
    worker_stats[w] = search.stats();
  };
  runTeam(workers, work);
  stats = SearchStats();
  for (const SearchStats& s : worker_stats) {
    stats.local += s.local;
    stats.widened += s.widened;
    stats.cells_visited += s.cells_visited;
    stats.points_tested += s.points_tested;
  }
  for (const Status& s : results)
    if (!s.ok())
      return s;
  return Status::success();
}

/// Merges the strips in strip order (each released once appended), then pairs the
/// border halfedges, each seen once from each side.
Status mergeStrips(std::vector<StripMesh>& strips, std::size_t expected,
                   std::vector<VertexId>& triangles, std::vector<HalfedgeId>& halfedges)
{
  std::size_t owned = 0;
  for (const StripMesh& s : strips)
    owned += s.owned_count;
  if (owned != expected)
    return Status::error(
        StatusCode::INTERNAL_ERROR,
        "region growing produced " + std::to_string(owned) +
            " triangles, expected 2n - h - 2 = " + std::to_string(expected));
  triangles.clear();
  halfedges.clear();
  triangles.reserve(3 * expected);
  halfedges.reserve(3 * expected);
  std::vector<BorderRecord> border;
  for (StripMesh& s : strips) {
    appendStrip(s, triangles, halfedges, border);
    // Else the strips already merged stay resident beside the output.
    detail::releaseFreedMemory();
  }
  std::sort(border.begin(), border.end());
  for (std::size_t k = 0; k < border.size(); k += 2) {
    if (k + 1 == border.size() || border[k].low != border[k + 1].low ||
        border[k].high != border[k + 1].high)
      return Status::error(StatusCode::INTERNAL_ERROR,
                           "strip border edge " + std::to_string(border[k].low) + "-" +
                               std::to_string(border[k].high) + " has no twin");
    halfedges[border[k].halfedge] = border[k + 1].halfedge;
    halfedges[border[k + 1].halfedge] = border[k].halfedge;
  }
  return Status::success();
}

} // namespace

Status triangulateGrid(const CellGrid& grid, const CellPyramid& pyramid,
                       const CellSubdivision& subdivision,
                       const std::vector<VertexId>& hull,
                       std::vector<VertexId>& triangles,
                       std::vector<HalfedgeId>& halfedges, SearchStats& stats,
                       unsigned threads, std::uint32_t strip_columns, bool cache_blocks)
{
  const std::size_t n = grid.points.size();
  const std::size_t h = hull.size();
  if (Status s = checkTriangleCapacity(n, h); !s.ok())
    return s;
  const detail::HullEdges hull_edges(n, hull);
  // Strips are grown independently and merged in strip order: the arrays are the
  // same for every thread count.
  const detail::StripLayout layout = detail::stripLayoutFor(grid, strip_columns);
  std::vector<StripMesh> strips;
  if (Status s = growStrips(grid, pyramid, subdivision, hull_edges, layout, threads,
                            cache_blocks, strips, stats);
      !s.ok())
    return s;
  return mergeStrips(strips, 2 * n - h - 2, triangles, halfedges);
}

} // namespace pcl_vts
