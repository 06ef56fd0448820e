#include <pcl_vts/core/grid_triangulator.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace pcl_vts {
namespace {

/// The growing triangulation: flat arrays plus, per vertex, the list of its outgoing
/// open halfedges (those still waiting for the triangle on their right). An open
/// halfedge has no twin yet, so its slot in `halfedges` holds the list link instead,
/// tagged with OPEN: no extra array.
// Searches handed to the threads at once. Fixed (not per thread count) so that the
// output does not depend on the number of threads.
constexpr std::size_t BATCH_SIZE = 256;

/// The vertices used by the edges of one batch: a small open-addressing set, cleared
/// per batch.
class VertexSet {
 public:
  void clear() { std::fill(slots_.begin(), slots_.end(), INVALID_ID); }

  /// Inserts both vertices if neither is present; false (and no change) otherwise.
  bool insert(VertexId a, VertexId b)
  {
    if (contains(a) || contains(b))
      return false;
    add(a);
    add(b);
    return true;
  }

 private:
  static constexpr std::size_t SIZE = 4 * 2 * BATCH_SIZE; // load <= 1/4
  static std::size_t slot(VertexId v) { return (v * 2654435761u) & (SIZE - 1); }
  bool contains(VertexId v) const
  {
    for (std::size_t i = slot(v);; i = (i + 1) & (SIZE - 1)) {
      if (slots_[i] == v)
        return true;
      if (slots_[i] == INVALID_ID)
        return false;
    }
  }
  void add(VertexId v)
  {
    std::size_t i = slot(v);
    while (slots_[i] != INVALID_ID)
      i = (i + 1) & (SIZE - 1);
    slots_[i] = v;
  }
  std::vector<VertexId> slots_ = std::vector<VertexId>(SIZE, INVALID_ID);
};

class RegionGrowth {
 public:
  static constexpr HalfedgeId OPEN = 0x80000000u;
  static constexpr HalfedgeId NIL = 0x7ffffffeu; ///< end of an open list
  /// Halfedge ids must stay below NIL.
  static constexpr std::size_t MAX_TRIANGLES = NIL / 3;

  RegionGrowth(std::size_t vertices, std::size_t expected_triangles,
               std::vector<VertexId>& triangles, std::vector<HalfedgeId>& halfedges)
      : triangles_(triangles)
      , halfedges_(halfedges)
      , open_head_(vertices, NIL)
  {
    triangles_.clear();
    halfedges_.clear();
    triangles_.reserve(3 * expected_triangles);
    halfedges_.reserve(3 * expected_triangles);
  }

  HalfedgeId addTriangle(VertexId v0, VertexId v1, VertexId v2)
  {
    const auto e = static_cast<HalfedgeId>(triangles_.size());
    for (VertexId v : {v0, v1, v2}) {
      triangles_.push_back(v);
      halfedges_.push_back(INVALID_ID);
    }
    return e;
  }

  VertexId origin(HalfedgeId e) const { return triangles_[e]; }
  VertexId target(HalfedgeId e) const { return triangles_[nextHalfedge(e)]; }
  bool hasTwin(HalfedgeId e) const { return halfedges_[e] < OPEN; }

  void link(HalfedgeId e, HalfedgeId f)
  {
    halfedges_[e] = f;
    halfedges_[f] = e;
  }

  /// Links e with its open twin if that exists; otherwise e becomes open.
  /// Returns true when e is new open work.
  bool linkOrOpen(HalfedgeId e)
  {
    const VertexId from = origin(e), to = target(e);
    HalfedgeId prev = NIL;
    for (HalfedgeId h = open_head_[to]; h != NIL; prev = h, h = nextOpen(h))
      if (target(h) == from) {
        unlink(to, prev, h);
        link(e, h);
        return false;
      }
    halfedges_[e] = OPEN | open_head_[from];
    open_head_[from] = e;
    return true;
  }

  void close(HalfedgeId e)
  {
    const VertexId from = origin(e);
    HalfedgeId prev = NIL;
    for (HalfedgeId h = open_head_[from]; h != NIL; prev = h, h = nextOpen(h))
      if (h == e) {
        unlink(from, prev, h);
        halfedges_[e] = INVALID_ID;
        return;
      }
  }

  /// Halfedges still open at the end lie on the hull: they have no twin.
  void finish()
  {
    for (HalfedgeId& t : halfedges_)
      if (t >= OPEN)
        t = INVALID_ID;
  }

 private:
  HalfedgeId nextOpen(HalfedgeId h) const { return halfedges_[h] & ~OPEN; }

  void unlink(VertexId v, HalfedgeId prev, HalfedgeId h)
  {
    if (prev == NIL)
      open_head_[v] = nextOpen(h);
    else
      halfedges_[prev] = OPEN | nextOpen(h);
  }

  std::vector<VertexId>& triangles_;
  std::vector<HalfedgeId>& halfedges_;
  std::vector<HalfedgeId> open_head_;
};

/// Runs batches of independent third-point searches on several threads. Each thread
/// owns a MediatrixSearch (its heap); the grid is shared read-only. Results land in
/// per-query slots, so they do not depend on which thread computed them.
class SearchTeam {
 public:
  struct Query {
    VertexId a, b; ///< search left of a->b
  };

  SearchTeam(const CellGrid& grid, const CellPyramid& pyramid,
             const CellSubdivision& subdivision, unsigned threads)
  {
    for (unsigned t = 0; t < std::max(threads, 1u); ++t)
      searches_.emplace_back(grid, pyramid, subdivision);
    for (unsigned t = 1; t < searches_.size(); ++t)
      workers_.emplace_back([this, t] { workerLoop(t); });
  }

  ~SearchTeam()
  {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    start_.notify_all();
    for (std::thread& w : workers_)
      w.join();
  }

  SearchTeam(const SearchTeam&) = delete;
  SearchTeam& operator=(const SearchTeam&) = delete;

  VertexId findOne(VertexId a, VertexId b) { return searches_[0].findThirdPoint(a, b); }

  /// results[k] = third point left of queries[k].
  void run(const std::vector<Query>& queries, std::vector<VertexId>& results)
  {
    results.resize(queries.size());
    queries_ = &queries;
    results_ = &results;
    next_.store(0);
    if (!workers_.empty()) {
      std::lock_guard<std::mutex> lock(mutex_);
      busy_ = static_cast<unsigned>(workers_.size());
      ++generation_;
    }
    start_.notify_all();
    work(0);
    if (!workers_.empty()) {
      std::unique_lock<std::mutex> lock(mutex_);
      done_.wait(lock, [this] { return busy_ == 0; });
    }
  }

  SearchStats stats() const
  {
    SearchStats sum;
    for (const MediatrixSearch& s : searches_) {
      sum.local += s.stats().local;
      sum.widened += s.stats().widened;
      sum.cells_visited += s.stats().cells_visited;
      sum.points_tested += s.stats().points_tested;
    }
    return sum;
  }

 private:
  static constexpr std::size_t CHUNK = 16;

  void work(unsigned t)
  {
    const std::vector<Query>& q = *queries_;
    std::vector<VertexId>& r = *results_;
    for (std::size_t k = next_.fetch_add(CHUNK); k < q.size();
         k = next_.fetch_add(CHUNK))
      for (std::size_t i = k; i < std::min(k + CHUNK, q.size()); ++i)
        r[i] = searches_[t].findThirdPoint(q[i].a, q[i].b);
  }

  void workerLoop(unsigned t)
  {
    std::uint64_t seen = 0;
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        start_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_)
          return;
        seen = generation_;
      }
      work(t);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (--busy_ == 0)
          done_.notify_one();
      }
    }
  }

  std::vector<MediatrixSearch> searches_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  std::uint64_t generation_ = 0;
  unsigned busy_ = 0;
  bool stop_ = false;
  const std::vector<Query>* queries_ = nullptr;
  std::vector<VertexId>* results_ = nullptr;
  std::atomic<std::size_t> next_{0};
};

} // namespace

Status triangulateGrid(const CellGrid& grid, const CellPyramid& pyramid,
                       const CellSubdivision& subdivision,
                       const std::vector<VertexId>& hull,
                       std::vector<VertexId>& triangles,
                       std::vector<HalfedgeId>& halfedges, SearchStats& stats,
                       unsigned threads)
{
  const std::size_t n = grid.points.size();
  const std::size_t h = hull.size();
  const std::size_t expected = 2 * n - h - 2;
  if (expected > RegionGrowth::MAX_TRIANGLES)
    return Status::error(StatusCode::INVALID_PARAMETER,
                         std::to_string(n) + " points need " +
                             std::to_string(expected) +
                             " triangles, beyond the 32-bit halfedge range");
  // hull_next[v] = w when v->w is a hull edge (interior on its left).
  std::vector<VertexId> hull_next(n, INVALID_ID);
  for (std::size_t k = 0; k < h; ++k)
    hull_next[hull[k]] = hull[(k + 1) % h];

  SearchTeam team(grid, pyramid, subdivision, threads);
  RegionGrowth growth(n, expected, triangles, halfedges);
  std::vector<HalfedgeId> pool;

  // Seed: the first hull edge is Delaunay in every triangulation of the points.
  const VertexId a = hull[0], b = hull[1];
  const VertexId c = team.findOne(a, b);
  if (c == INVALID_ID)
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "no point found left of the seed hull edge");
  const HalfedgeId seed = growth.addTriangle(a, b, c);
  for (HalfedgeId e : {seed + 1, seed + 2})
    if (growth.linkOrOpen(e))
      pool.push_back(e);

  // The pool is drained in batches: the searches of a batch run in parallel, then
  // their triangles are added in batch order. Each answer is the unique Delaunay
  // triangle across its edge whatever else was added meanwhile, so an edge that an
  // earlier triangle of the batch already closed is simply skipped. The batch size is
  // fixed, so the output is the same for any number of threads.
  std::vector<HalfedgeId> batch, deferred;
  VertexSet batch_vertices;
  std::vector<SearchTeam::Query> queries;
  std::vector<VertexId> apex;
  while (!pool.empty()) {
    batch.clear();
    queries.clear();
    deferred.clear();
    batch_vertices.clear();
    while (!pool.empty() && batch.size() < BATCH_SIZE) {
      const HalfedgeId e = pool.back();
      pool.pop_back();
      if (growth.hasTwin(e))
        continue;
      const VertexId x = growth.origin(e), y = growth.target(e);
      if (hull_next[x] == y)
        continue; // the right side of a hull edge is outside
      // Two open edges of one future triangle share a vertex: keeping the edges of a
      // batch vertex-disjoint means no triangle is searched twice.
      if (!batch_vertices.insert(x, y)) {
        deferred.push_back(e);
        continue;
      }
      batch.push_back(e);
      queries.push_back({y, x});
    }
    pool.insert(pool.end(), deferred.rbegin(), deferred.rend());
    team.run(queries, apex);
    for (std::size_t k = 0; k < batch.size(); ++k) {
      const HalfedgeId e = batch[k];
      if (growth.hasTwin(e))
        continue;
      const VertexId x = growth.origin(e), y = growth.target(e), p = apex[k];
      if (p == INVALID_ID)
        return Status::error(StatusCode::INTERNAL_ERROR,
                             "no Delaunay triangle found across interior edge " +
                                 std::to_string(x) + "-" + std::to_string(y));
      growth.close(e);
      const HalfedgeId f = growth.addTriangle(y, x, p);
      growth.link(f, e);
      for (HalfedgeId g : {f + 1, f + 2})
        if (growth.linkOrOpen(g))
          pool.push_back(g);
    }
  }
  growth.finish();
  stats = team.stats();
  if (triangles.size() != 3 * expected)
    return Status::error(
        StatusCode::INTERNAL_ERROR,
        "region growing produced " + std::to_string(triangles.size() / 3) +
            " triangles, expected 2n - h - 2 = " + std::to_string(expected));
  return Status::success();
}

} // namespace pcl_vts
