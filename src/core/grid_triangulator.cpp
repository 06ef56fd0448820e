#include "release_memory.h"
#include "strip_growth.h"

#include <pcl_vts/core/grid_triangulator.h>
#include <pcl_vts/core/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <mutex>
#include <string>

namespace pcl_vts {
namespace {

using detail::StripMesh;

using BorderRecord = detail::BorderHalfedge;

/// Appends a compacted strip to the mesh: its triangles, its twins shifted, its
/// border halfedges (global ids) added to `border`. `release`: the strip's pages are
/// handed back as they are copied (the strip's arrays are emptied next), so that a
/// large strip and the output it goes to are not both resident at once.
void appendStrip(const StripMesh& strip, bool release, std::vector<VertexId>& triangles,
                 std::vector<HalfedgeId>& halfedges, std::vector<BorderRecord>& border)
{
  const auto shift = static_cast<HalfedgeId>(halfedges.size());
  // Copied (insert: no zeroing first) and shifted a cache-sized chunk at a time.
  constexpr std::size_t CHUNK = 1u << 14;
  const VertexId* vertices = strip.triangles.data();
  const void* populated = nullptr;
  for (std::size_t begin = 0; begin < strip.triangles.size(); begin += CHUNK) {
    const std::size_t end = std::min(strip.triangles.size(), begin + CHUNK);
    // The output's slots (reserved for the whole mesh, written in full) faulted in a
    // chunk ahead (populateAhead) instead of a trap per page.
    detail::populateAhead(triangles, end - begin, populated);
    triangles.insert(triangles.end(), vertices + begin, vertices + end);
    if (release)
      detail::releasePages(vertices + begin, vertices + end);
  }
  const HalfedgeId* local = strip.halfedges.data();
  populated = nullptr;
  for (std::size_t begin = 0; begin < strip.halfedges.size(); begin += CHUNK) {
    const std::size_t end = std::min(strip.halfedges.size(), begin + CHUNK);
    const std::size_t at = halfedges.size();
    detail::populateAhead(halfedges, end - begin, populated);
    halfedges.insert(halfedges.end(), local + begin, local + end);
    if (shift != 0) // the first strip's ids stay
      for (std::size_t k = at; k < halfedges.size(); ++k)
        if (halfedges[k] != INVALID_ID)
          halfedges[k] += shift;
    if (release)
      detail::releasePages(local + begin, local + end);
  }
  for (const BorderRecord& r : strip.border)
    border.push_back({r.low, r.high, r.halfedge + shift});
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

/// Strips merged in strip order as they are grown, so that the merge (a serial chain)
/// runs beside the growth of the later strips and each strip is freed soon after it
/// is grown: a worker that finishes strip s (growStrip compacts it), then, unless
/// another worker holds the merge, appends every strip from the first unmerged one on
/// that is ready. The arrays depend on the layout alone, not on the thread count or
/// the order the strips finish in.
class StripMerge {
 public:
  StripMerge(std::uint32_t count, unsigned workers, std::size_t expected, bool release,
             std::vector<VertexId>& triangles, std::vector<HalfedgeId>& halfedges)
      : strips_(count)
      , results_(count)
      , ready_(count, 0)
      , appended_(count, 0)
      , reuse_end_(count - std::min<std::uint32_t>(count, workers))
      , release_above_(6 * expected / std::max<std::uint32_t>(1, count))
      , release_(release)
      , triangles_(triangles)
      , halfedges_(halfedges)
  {
    triangles_.clear();
    halfedges_.clear();
    if (count > 1) { // one strip: reserved once grown (see claim)
      triangles_.reserve(3 * expected);
      halfedges_.reserve(3 * expected);
    }
  }

  /// The mesh strip s grows into: empty, on the arrays of a strip already merged
  /// when one is free (their pages already resident: no page faults), except for the
  /// last strip of each worker: those get arrays of their own size, so that the
  /// merge's peak (the output nearly full) holds no spare arrays.
  StripMesh& strip(std::uint32_t s)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    ++taken_;
    if (s < reuse_end_ && !spare_.empty()) {
      strips_[s] = std::move(spare_.back());
      spare_.pop_back();
    }
    return strips_[s];
  }

  /// Asked by strip s once grown: the output itself when s is the next strip to merge
  /// and no merge runs (the caller then holds the merge until grown(s)), unless its
  /// pages would be handed back as it is copied (see appendStrip's `release`; without
  /// release_ none are, so every strip may take this path, the last one included).
  detail::StripSink* claim(std::uint32_t s)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const bool last_use = s >= reuse_end_ || taken_ >= reuse_end_;
    // One strip is the whole mesh: appended once grown instead, when its worker's
    // kernel arrays, the cells and open_head are freed, so that the output's
    // allocation reuses their resident memory rather than fresh pages.
    if (strips_.size() == 1 || merging_ || merged_ != s || failed_ ||
        (release_ && (last_use || strips_[s].triangles.size() > release_above_)))
      return nullptr;
    merging_ = true;
    appended_[s] = 1;
    return &sink_;
  }

  /// Strip s grown (and compacted, or appended through claim) with `result`.
  void grown(std::uint32_t s, Status result)
  {
    results_[s] = std::move(result);
    std::unique_lock<std::mutex> lock(mutex_);
    ready_[s] = 1;
    if (merging_ && appended_[s] == 0)
      return; // the worker merging appends s once it gets there
    merging_ = true;
    while (merged_ < strips_.size() && ready_[merged_] != 0) {
      const std::uint32_t next = merged_;
      // Its arrays are not reused when every strip that could is taken.
      const bool last_use = next >= reuse_end_ || taken_ >= reuse_end_;
      lock.unlock();
      if (!results_[next].ok())
        failed_ = true;
      if (!failed_ && appended_[next] == 0 && strips_.size() == 1) {
        triangles_.reserve(strips_[next].triangles.size());
        halfedges_.reserve(strips_[next].halfedges.size());
      }
      if (!failed_ && appended_[next] == 0)
        appendStrip(strips_[next],
                    release_ &&
                        (last_use || strips_[next].triangles.size() > release_above_),
                    triangles_, halfedges_, border_);
      StripMesh spare = std::move(strips_[next]);
      strips_[next] = StripMesh();
      spare.triangles.clear();
      spare.halfedges.clear();
      spare.border.clear();
      lock.lock();
      // Kept for a strip still to be grown (its pages stay resident, so growing
      // there faults none in); freed once every strip is taken.
      if (taken_ < reuse_end_)
        spare_.push_back(std::move(spare));
      ++merged_;
      lock.unlock();
      spare = StripMesh();
      // Else the strips already merged stay resident beside the output.
      if (release_)
        detail::releaseFreedMemory();
      lock.lock();
    }
    merging_ = false;
    if (taken_ >= reuse_end_ && !spare_.empty()) {
      // No strip left to reuse them: the spare arrays are freed.
      std::vector<StripMesh> spare = std::move(spare_);
      spare_.clear();
      lock.unlock();
      spare.clear();
      if (release_)
        detail::releaseFreedMemory();
    }
  }

  /// Once every strip is grown and merged: the first error in strip order, or the
  /// border halfedges paired, each seen once from each side.
  Status finish(std::size_t expected)
  {
    for (const Status& s : results_)
      if (!s.ok())
        return s;
    const std::size_t owned = triangles_.size() / 3;
    if (owned != expected)
      return Status::error(
          StatusCode::INTERNAL_ERROR,
          "region growing produced " + std::to_string(owned) +
              " triangles, expected 2n - h - 2 = " + std::to_string(expected));
    std::sort(border_.begin(), border_.end());
    for (std::size_t k = 0; k < border_.size(); k += 2) {
      if (k + 1 == border_.size() || border_[k].low != border_[k + 1].low ||
          border_[k].high != border_[k + 1].high)
        return Status::error(StatusCode::INTERNAL_ERROR,
                             "strip border edge " + std::to_string(border_[k].low) +
                                 "-" + std::to_string(border_[k].high) +
                                 " has no twin");
      halfedges_[border_[k].halfedge] = border_[k + 1].halfedge;
      halfedges_[border_[k + 1].halfedge] = border_[k].halfedge;
    }
    return Status::success();
  }

 private:
  std::vector<StripMesh> strips_;
  std::vector<Status> results_;
  std::mutex mutex_; ///< guards ready_, appended_, merged_, merging_, taken_, spare_
  std::vector<char> ready_;
  std::vector<char> appended_;    ///< written to the output by the strip's worker
  const std::uint32_t reuse_end_; ///< strips from here on get arrays of their own
  /// Strips with more vertex slots than this (twice the mean strip's) hand their
  /// pages back as they are appended: clustered input has strips of a third of the
  /// points, which would stay resident beside the output (and in the spare arrays).
  const std::size_t release_above_;
  const bool release_;           ///< freed memory handed back (RELEASE_MIN_POINTS)
  std::uint32_t taken_ = 0;      ///< strips handed to the workers
  std::vector<StripMesh> spare_; ///< merged strips' arrays, emptied, for reuse
  std::uint32_t merged_ = 0;
  bool merging_ = false;
  bool failed_ = false; ///< a strip failed: nothing more is appended
  std::vector<VertexId>& triangles_;
  std::vector<HalfedgeId>& halfedges_;
  std::vector<BorderRecord> border_; ///< global ids
  detail::StripSink sink_{triangles_, halfedges_, border_};
};

/// Grows every strip of the layout (any thread, any order) and merges them; the
/// search statistics summed over the workers; `grown` (when set) called once the last
/// strip is grown, before it is merged.
Status growAndMergeStrips(const CellGrid& grid, const CellPyramid& pyramid,
                          const CellSubdivision& subdivision,
                          const detail::HullEdges& hull_edges,
                          const detail::StripLayout& layout, unsigned threads,
                          bool cache_blocks, std::size_t expected,
                          std::vector<VertexId>& triangles,
                          std::vector<HalfedgeId>& halfedges, SearchStats& stats,
                          const std::function<void()>& grown)
{
  const unsigned workers = std::max(1u, std::min<unsigned>(threads, layout.count));
  // Allocated without a fill and filled by the workers' threads (at 1e7 points 40 MB
  // of page faults and writes, 0.016 s on one thread).
  const std::size_t n = grid.points.size();
  const bool release = n >= detail::RELEASE_MIN_POINTS;
  StripMerge merge(layout.count, workers, expected, release, triangles, halfedges);
  std::unique_ptr<HalfedgeId[]> open_head(new HalfedgeId[n]);
  parallelRanges(workers, n, [&open_head](std::size_t begin, std::size_t end) {
    // Faulted in a chunk ahead of the fill instead of a trap per page.
    constexpr std::size_t CHUNK = (std::size_t{1} << 16) / sizeof(HalfedgeId);
    for (std::size_t at = begin; at < end; at += CHUNK) {
      const std::size_t upto = std::min(end, at + CHUNK);
      detail::populatePages(open_head.get() + at, open_head.get() + upto);
      std::fill(open_head.get() + at, open_head.get() + upto, detail::UNREACHED);
    }
  });
  // The points' own box for the blocks' finality on the grid's border (a scan of the
  // border rows and columns only).
  const detail::GridBox box =
      cache_blocks ? detail::GridBox::ofPoints(grid) : detail::GridBox::ofCells(grid);
  std::vector<SearchStats> worker_stats(workers);
  std::atomic<std::uint32_t> next_strip{0}, strips_grown{0};
  const auto work = [&](unsigned w) {
    MediatrixSearch search(grid, pyramid, subdivision);
    detail::LocalDelaunay blocks; // reused strip after strip
    for (std::uint32_t s = next_strip++; s < layout.count; s = next_strip++) {
      Status result = detail::growStrip(
          grid, pyramid, layout, s, hull_edges, search, open_head.get(), merge.strip(s),
          cache_blocks, [&merge, s] { return merge.claim(s); }, &blocks, &box);
      if (layout.count == 1)
        blocks = detail::LocalDelaunay(); // freed before the output (StripMerge::claim)
      if (++strips_grown == layout.count) {
        // No strip reads the grid or open_head any more: both released before the
        // last strips are merged, when the output is nearly full (the peak).
        open_head.reset();
        if (grown)
          grown();
        if (release)
          detail::releaseFreedMemory();
      }
      merge.grown(s, std::move(result));
    }
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
  return merge.finish(expected);
}

} // namespace

Status triangulateGrid(const CellGrid& grid, const CellPyramid& pyramid,
                       const CellSubdivision& subdivision,
                       const std::vector<VertexId>& hull,
                       std::vector<VertexId>& triangles,
                       std::vector<HalfedgeId>& halfedges, SearchStats& stats,
                       unsigned threads, std::uint32_t strip_columns, bool cache_blocks,
                       const std::function<void()>& grown)
{
  const std::size_t n = grid.points.size();
  const std::size_t h = hull.size();
  if (Status s = checkTriangleCapacity(n, h); !s.ok())
    return s;
  const detail::HullEdges hull_edges(n, hull);
  // Strips are grown independently and merged in strip order: the arrays are the
  // same for every thread count.
  detail::StripLayout layout = detail::stripLayoutFor(grid, strip_columns);
  // Small inputs: wider strips, at least MIN_STRIP_POINTS points each on average
  // (still a layout of the grid alone). Each strip border costs triangles grown twice
  // and blocks cut short (a 5-column last strip of clustered 1e3); at 1e4 one strip
  // instead of 3 to 5 saved 3 % (jittered) to 11 % (clustered) of the triangulation.
  constexpr std::size_t MIN_STRIP_POINTS = 8192;
  if (strip_columns == 0)
    while (layout.count > 1 && layout.count > n / MIN_STRIP_POINTS) {
      ++layout.shift;
      layout.count = ((grid.nx - 1) >> layout.shift) + 1;
    }
  return growAndMergeStrips(grid, pyramid, subdivision, hull_edges, layout, threads,
                            cache_blocks, 2 * n - h - 2, triangles, halfedges, stats,
                            grown);
}

} // namespace pcl_vts
