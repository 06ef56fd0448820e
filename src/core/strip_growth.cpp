#include "local_delaunay.h"
#include "release_memory.h"
#include "strip_growth.h"

#include <pcl_vts/core/predicates.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pcl_vts {
namespace detail {
namespace {

/// Open-list heads of the vertices outside the strip that its triangles touch: a
/// small open-addressing map (the strip's own vertices use the shared array).
class ForeignHeads {
 public:
  HalfedgeId& operator[](VertexId v)
  {
    if (2 * (size_ + 1) > keys_.size())
      grow();
    std::size_t i = slot(v);
    while (keys_[i] != v && keys_[i] != INVALID_ID)
      i = (i + 1) & (keys_.size() - 1);
    if (keys_[i] == INVALID_ID) {
      keys_[i] = v;
      heads_[i] = OPEN_LIST_END;
      ++size_;
    }
    return heads_[i];
  }

 private:
  std::size_t slot(VertexId v) const { return (v * 2654435761u) & (keys_.size() - 1); }
  void grow()
  {
    std::vector<VertexId> keys = std::move(keys_);
    std::vector<HalfedgeId> heads = std::move(heads_);
    keys_.assign(std::max<std::size_t>(64, 2 * keys.size()), INVALID_ID);
    heads_.assign(keys_.size(), OPEN_LIST_END);
    for (std::size_t k = 0; k < keys.size(); ++k)
      if (keys[k] != INVALID_ID) {
        std::size_t i = slot(keys[k]);
        while (keys_[i] != INVALID_ID)
          i = (i + 1) & (keys_.size() - 1);
        keys_[i] = keys[k];
        heads_[i] = heads[k];
      }
  }

  std::vector<VertexId> keys_;
  std::vector<HalfedgeId> heads_;
  std::size_t size_ = 0;
};

/// The open edges, lowest grid row first: the strip is grown bottom-up like a sweep,
/// so the frontier spans a few rows of the strip and its points stay in cache.
class RowQueue {
 public:
  explicit RowQueue(std::uint32_t rows)
      : rows_(rows)
  {}
  bool empty() const { return size_ == 0; }
  void push(HalfedgeId e, std::uint32_t row)
  {
    rows_[row].push_back(e);
    lowest_ = std::min(lowest_, row);
    ++size_;
  }
  HalfedgeId pop()
  {
    while (rows_[lowest_].empty())
      ++lowest_;
    const HalfedgeId e = rows_[lowest_].back();
    rows_[lowest_].pop_back();
    --size_;
    return e;
  }

 private:
  std::vector<std::vector<HalfedgeId>> rows_;
  std::uint32_t lowest_ = 0;
  std::size_t size_ = 0;
};

/// A block of the occupancy pyramid and its squared distance to a query point.
struct NearBlock {
  double key;
  std::uint32_t level, i, j;
};

class Growth {
 public:
  Growth(const CellGrid& grid, const CellPyramid& pyramid, const StripLayout& layout,
         std::uint32_t strip, const HullEdges& hull, MediatrixSearch& search,
         HalfedgeId* open_head, StripMesh& mesh, bool cache_blocks,
         const std::function<StripSink*()>& claim, LocalDelaunay* blocks,
         const GridBox* box)
      : grid_(grid)
      , pyramid_(pyramid)
      , hull_(hull)
      , search_(search)
      , open_head_(open_head)
      , mesh_(mesh)
      , first_column_(strip << layout.shift)
      , end_column_(std::min(grid.nx, (strip + 1) << layout.shift))
      , low_(first_column_ == 0 ? -std::numeric_limits<double>::infinity()
                                : static_cast<double>(first_column_))
      , high_(end_column_ == grid.nx ? std::numeric_limits<double>::infinity()
                                     : static_cast<double>(end_column_))
      , cache_blocks_(cache_blocks)
      , claim_(claim)
      , blocks_dt_(blocks)
      , box_(box != nullptr ? *box : GridBox::ofCells(grid))
  {}

  Status run()
  {
    // Every vertex of the strip gets a seed unless an earlier growth reached it: the
    // triangles around a reached vertex are all grown (its edges are expandable), so
    // in the end each owned triangle, whose leftmost vertex is in the strip, exists.
    reserve();
    if (cache_blocks_) {
      if (Status s = addProvenTriangles(); !s.ok())
        return s;
      if (Status s = grow(); !s.ok())
        return s;
    }
    // Once every strip vertex is reached the scan would seed nothing: it stops (its
    // reads of open_head_ missed the cache, row after row).
    for (std::uint32_t j = 0; j < grid_.ny && reached_ < strip_vertices_; ++j) {
      const CellId row = grid_.cellId(0, j);
      for (VertexId v = grid_.start(row + first_column_),
                    end = grid_.start(row + end_column_);
           v < end; ++v) {
        if (open_head_[v] != UNREACHED)
          continue;
        if (Status s = seedAt(v); !s.ok())
          return s;
        if (Status s = grow(); !s.ok())
          return s;
      }
    }
    finish();
    return Status::success();
  }

 private:
  /// Halfedge ids from FOREIGN on are the foreign triangles' (grown but not owned:
  /// their leftmost vertex is left of the strip), kept apart so that the owned ones
  /// are numbered as in the output from the start (no compaction). A multiple of 3.
  static constexpr HalfedgeId FOREIGN = 0x60000000u;
  VertexId vertexAt(HalfedgeId e) const
  {
    return e < FOREIGN ? mesh_.triangles[e] : foreign_triangles_[e - FOREIGN];
  }
  HalfedgeId& slot(HalfedgeId e)
  {
    return e < FOREIGN ? mesh_.halfedges[e] : foreign_halfedges_[e - FOREIGN];
  }
  HalfedgeId slotValue(HalfedgeId e) const
  {
    return e < FOREIGN ? mesh_.halfedges[e] : foreign_halfedges_[e - FOREIGN];
  }
  static constexpr const char* STRIP_FULL =
      "more triangles in one strip than its 32-bit halfedge ids hold";
  /// Room for `count` more triangles of either kind below the ids' limits.
  bool roomFor(std::size_t count) const
  {
    return mesh_.triangles.size() / 3 + count < FOREIGN / 3 &&
           foreign_triangles_.size() / 3 + count < (OPEN_LIST_END - FOREIGN) / 3;
  }
  VertexId origin(HalfedgeId e) const { return vertexAt(e); }
  VertexId target(HalfedgeId e) const { return vertexAt(nextHalfedge(e)); }
  /// The column coordinate of v before truncation: column(x) = clamp(floor(t)), so
  /// comparing t with the strip's integer bounds decides membership the same way.
  double columnCoordinate(VertexId v) const
  {
    return (grid_.points[v].x - grid_.origin_x) * grid_.inv_cell_size;
  }
  bool inStrip(VertexId v) const
  {
    const double t = columnCoordinate(v);
    return t >= low_ && t < high_;
  }
  bool isOpen(HalfedgeId e) const
  {
    const HalfedgeId h = slotValue(e);
    return h >= OPEN && h != CLOSED;
  }
  HalfedgeId nextOpen(HalfedgeId e) const { return slotValue(e) & ~OPEN; }
  HalfedgeId& head(VertexId v, bool in_strip)
  {
    return in_strip ? open_head_[v] : foreign_[v];
  }

  void reserve()
  {
    // Grown: about 2 owned triangles per vertex, and the triangles across the strip's
    // left border, owned by the strip on the left (about 1.6 per point of a column on
    // each side): the arrays are reserved for them too, so that they are not
    // reallocated (copied, and faulted in twice) near the end of a strip.
    std::size_t vertices = 0, border = 0;
    const std::uint32_t border_column = first_column_ > 0 ? first_column_ - 1 : 0;
    for (std::uint32_t j = 0; j < grid_.ny; ++j) {
      const CellId row = grid_.cellId(0, j);
      vertices += grid_.start(row + end_column_) - grid_.start(row + first_column_);
      border += grid_.start(row + first_column_ + 1) - grid_.start(row + border_column);
    }
    strip_vertices_ = vertices;
    const std::size_t expected = 2 * vertices + 2 * border + vertices / 32 + 64;
    // Arrays too small for this strip are reallocated with room for a somewhat larger
    // next strip that reuses them (their pages then stay resident).
    if (mesh_.triangles.capacity() < 3 * expected) {
      const std::size_t room = expected + expected / 8;
      mesh_.triangles.reserve(3 * room);
      mesh_.halfedges.reserve(3 * room);
    }
    // Arrays reused from a larger strip (StripMerge::strip): their resident pages
    // beyond this strip's need are handed back, not kept beside the output.
    releasePages(mesh_.triangles.data() + 3 * expected,
                 mesh_.triangles.data() + mesh_.triangles.capacity());
    releasePages(mesh_.halfedges.data() + 3 * expected,
                 mesh_.halfedges.data() + mesh_.halfedges.capacity());
    populated_triangles_ = populated_halfedges_ = nullptr;
  }

  HalfedgeId addTriangle(VertexId a, VertexId b, VertexId c)
  {
    const double ta = columnCoordinate(a), tb = columnCoordinate(b),
                 tc = columnCoordinate(c);
    // Owned: the leftmost vertex column is in the strip (one vertex is, so none is
    // right of it).
    const bool owned = ta >= low_ && tb >= low_ && tc >= low_;
    auto& triangles = owned ? mesh_.triangles : foreign_triangles_;
    auto& halfedges = owned ? mesh_.halfedges : foreign_halfedges_;
    const auto e = static_cast<HalfedgeId>(triangles.size()) + (owned ? 0 : FOREIGN);
    int k = 0;
    for (const auto& [v, t] : {std::pair{a, ta}, std::pair{b, tb}, std::pair{c, tc}}) {
      triangles.push_back(v);
      halfedges.push_back(CLOSED);
      corner_in_strip_[k++] = t >= low_ && t < high_;
      if (t >= low_ && t < high_ && open_head_[v] == UNREACHED) {
        open_head_[v] = OPEN_LIST_END; // reached: its star will be grown
        ++reached_;
      }
    }
    return e;
  }

  void link(HalfedgeId e, HalfedgeId f)
  {
    slot(e) = f;
    slot(f) = e;
  }

  /// Links e with its open twin if that exists; otherwise e becomes open.
  /// Returns true when e is new open work.
  bool linkOrOpen(HalfedgeId e, bool from_in_strip, bool to_in_strip)
  {
    const VertexId from = origin(e), to = target(e);
    HalfedgeId& first = head(to, to_in_strip);
    HalfedgeId prev = OPEN_LIST_END;
    for (HalfedgeId h = first; h != OPEN_LIST_END; prev = h, h = nextOpen(h))
      if (target(h) == from) {
        if (prev == OPEN_LIST_END)
          first = nextOpen(h);
        else
          slot(prev) = OPEN | nextOpen(h);
        link(e, h);
        return false;
      }
    HalfedgeId& own = head(from, from_in_strip);
    slot(e) = OPEN | own;
    own = e;
    return true;
  }

  /// Removes open e from its origin's list; it ends CLOSED.
  void close(HalfedgeId e, bool origin_in_strip)
  {
    HalfedgeId& first = head(origin(e), origin_in_strip);
    HalfedgeId prev = OPEN_LIST_END;
    for (HalfedgeId h = first; h != OPEN_LIST_END; prev = h, h = nextOpen(h))
      if (h == e) {
        if (prev == OPEN_LIST_END)
          first = nextOpen(h);
        else
          slot(prev) = OPEN | nextOpen(h);
        slot(e) = CLOSED;
        return;
      }
  }

  /// Links or opens the halfedges k0..2 of the triangle just added (whose corners'
  /// strip membership addTriangle noted). Growth crosses an edge only next to a strip
  /// vertex: it stays in the stars of the strip's vertices, which hold every owned
  /// triangle.
  void openEdges(HalfedgeId t0, int k0)
  {
    for (int k = k0; k < 3; ++k) {
      const bool from_in = corner_in_strip_[k], to_in = corner_in_strip_[(k + 1) % 3];
      const HalfedgeId g = t0 + static_cast<HalfedgeId>(k);
      if (linkOrOpen(g, from_in, to_in) && (from_in || to_in))
        pool_.push(g, grid_.row(grid_.points[origin(g)].y));
    }
  }

  Status grow()
  {
    while (!pool_.empty()) {
      const HalfedgeId e = pool_.pop();
      if (!isOpen(e))
        continue;
      const VertexId x = origin(e), y = target(e);
      if (hull_.contains(x, y)) {
        close(e, inStrip(x)); // the right side of a hull edge is outside
        continue;
      }
      const VertexId p = search_.findThirdPoint(y, x);
      if (p == INVALID_ID)
        return Status::error(StatusCode::INTERNAL_ERROR,
                             "no Delaunay triangle found across interior edge " +
                                 std::to_string(x) + "-" + std::to_string(y));
      if (!roomFor(1))
        return Status::error(StatusCode::CAPACITY_EXCEEDED, STRIP_FULL);
      const HalfedgeId f = addTriangle(y, x, p);
      close(e, corner_in_strip_[1]);
      link(f, e);
      openEdges(f, 1);
    }
    return Status::success();
  }

  /// Cache blocks (docs/scaling.md): each block of the strip's cells is triangulated
  /// with a ring of cells around it (LocalDelaunay), and every triangle proven final
  /// there that has a vertex in the strip is added once, by the block holding its
  /// smallest strip vertex, its edges linked or opened as if it had been grown. The
  /// growth then only searches from the open edges (near voids, the hull, corners).
  Status addProvenTriangles()
  {
    constexpr std::uint32_t BLOCK = 32, RING = 1;
    LocalDelaunay strip_dt;
    LocalDelaunay& dt = blocks_dt_ != nullptr ? *blocks_dt_ : strip_dt;
    for (std::uint32_t cj0 = 0, cj1 = 0; cj0 < grid_.ny; cj0 = cj1) {
      cj1 = blockBandEnd(grid_, first_column_, end_column_, cj0, BLOCK);
      for (std::uint32_t ci0 = first_column_, ci1 = 0; ci0 < end_column_; ci0 = ci1) {
        ci1 = blockColumnEnd(ci0, end_column_, BLOCK);
        const CellWindow core{ci0, ci1, cj0, cj1};
        if (pointsIn(core) == 0)
          continue;
        const CellWindow window{
            core.i0 > RING ? core.i0 - RING : 0, std::min(grid_.nx, core.i1 + RING),
            core.j0 > RING ? core.j0 - RING : 0, std::min(grid_.ny, core.j1 + RING)};
        if (!dt.triangulate(grid_, window, core))
          continue;
        if (!roomFor(dt.v.size() / 3))
          return Status::error(StatusCode::CAPACITY_EXCEEDED, STRIP_FULL);
        addBlock(dt, window);
      }
    }
    return Status::success();
  }

  /// The points of the cells of `w`.
  std::size_t pointsIn(const CellWindow& w) const { return windowPoints(grid_, w); }

  /// Adds the proven triangles of one triangulated block: vertices, ownership and the
  /// twins inside the block written in place; only the other edges go through the
  /// open lists (another block's triangle, or the search's work). The triangles, their
  /// order and the open lists' order are those of one addTriangle per kept triangle
  /// followed by one linkOrOpen per edge not paired in the block. Not inlined into
  /// addProvenTriangles: GCC 12 did so once that caller grew, and its loops then
  /// took 7 % more instructions (callgrind, jittered 1e5).
  [[gnu::noinline]] void addBlock(const LocalDelaunay& dt, const CellWindow& window)
  {
    // Per local vertex, once: in the strip, right of its left border (the owned
    // test), and its owner key: (id + 1) * 2, plus 1 unless it is a strip vertex of
    // the block's core; all ones outside the strip, 1 for the super triangle. The
    // smallest key of a triangle is then its smallest strip vertex's, even iff the
    // triangle has no super vertex and that vertex is in the core.
    constexpr std::uint8_t IN_STRIP = 1, NOT_LEFT = 2, USED = 8;
    constexpr std::uint64_t NOT_OURS = ~std::uint64_t{0};
    const std::size_t vertices = dt.p.size();
    vertex_flags_.resize(vertices);
    owner_key_.resize(vertices);
    std::uint8_t* const flags = vertex_flags_.data();
    std::uint64_t* const key = owner_key_.data();
    for (std::size_t k = 0; k < 3; ++k) { // the super triangle
      flags[k] = 0;
      key[k] = 1;
    }
    for (std::size_t k = 3; k < vertices; ++k) {
      const double t = (dt.p[k].x - grid_.origin_x) * grid_.inv_cell_size;
      const bool in = t >= low_ && t < high_;
      flags[k] =
          static_cast<std::uint8_t>((in ? IN_STRIP : 0) | (t >= low_ ? NOT_LEFT : 0));
      key[k] =
          in ? ((std::uint64_t{dt.ids[k]} + 1) << 1 | (dt.in_core[k] != 0 ? 0u : 1u))
             : NOT_OURS;
      // Its open-list head, read once its triangles are kept: asked for now, so that
      // the line is in cache by then (a strip vertex's head is far from the others').
      if (in)
        __builtin_prefetch(open_head_ + dt.ids[k]);
    }
    // Kept: the owner test (cheap) first, then the finality bound. Each kept triangle
    // gets its first strip halfedge at once (twin_of, CLOSED for the others) and its
    // corners are marked USED.
    const std::size_t local_triangles = dt.triangleCount();
    const std::int32_t* const tv = dt.v.data();
    const auto first = static_cast<HalfedgeId>(mesh_.triangles.size());
    const auto first_foreign =
        FOREIGN + static_cast<HalfedgeId>(foreign_triangles_.size());
    kept_twin_.assign(local_triangles, CLOSED);
    HalfedgeId* const twin_of = kept_twin_.data();
    // Written by index (no capacity check per triangle): room for every triangle.
    if (kept_.size() < local_triangles)
      kept_.resize(local_triangles);
    std::uint32_t* const kept = kept_.data();
    std::size_t kept_count = 0;
    HalfedgeId next = first, next_foreign = first_foreign;
    dt.forEachFinal(
        grid_, window, box_,
        [&](std::size_t t) {
          const std::uint64_t k0 = key[tv[3 * t]], k1 = key[tv[3 * t + 1]],
                              k2 = key[tv[3 * t + 2]];
          return (std::min(k0, std::min(k1, k2)) & 1u) == 0;
        },
        [&](std::size_t t) {
          kept[kept_count++] = static_cast<std::uint32_t>(t);
          std::uint8_t& f0 = flags[tv[3 * t]];
          std::uint8_t& f1 = flags[tv[3 * t + 1]];
          std::uint8_t& f2 = flags[tv[3 * t + 2]];
          // Owned (owned ids) or foreign (from FOREIGN on), in the order kept.
          HalfedgeId& slot_id = (f0 & f1 & f2 & NOT_LEFT) != 0 ? next : next_foreign;
          twin_of[t] = slot_id;
          slot_id += 3;
          f0 |= USED;
          f1 |= USED;
          f2 |= USED;
        });
    if (kept_count == 0)
      return;
    const std::size_t added = (next - first) / 3,
                      foreign = (next_foreign - first_foreign) / 3;
    const VertexId* const ids = dt.ids.data();
    // The strip vertices of the kept triangles are reached (their stars will be
    // grown): tested once per vertex, not once per corner, before any open list is
    // read.
    for (std::size_t k = 3; k < vertices; ++k)
      if ((flags[k] & (IN_STRIP | USED)) == (IN_STRIP | USED) &&
          open_head_[ids[k]] == UNREACHED) {
        open_head_[ids[k]] = OPEN_LIST_END;
        ++reached_;
      }
    // Faulted in a chunk ahead (populateAhead) instead of a trap per page.
    populateAhead(mesh_.triangles, 3 * added, populated_triangles_);
    populateAhead(mesh_.halfedges, 3 * added, populated_halfedges_);
    mesh_.triangles.resize(mesh_.triangles.size() + 3 * added);
    mesh_.halfedges.resize(mesh_.halfedges.size() + 3 * added);
    foreign_triangles_.resize(foreign_triangles_.size() + 3 * foreign);
    foreign_halfedges_.resize(foreign_halfedges_.size() + 3 * foreign);
    // One pass in the order kept: corners and the twins inside the block, written in
    // place; the other edges are listed and then go through the open lists in the
    // same order (an open list never holds an edge paired in the block).
    open_edges_.clear();
    // The arrays' starts in locals: open_edges_'s push_back would make the compiler
    // reload them from the vectors at every triangle.
    VertexId* const owned_vertices = mesh_.triangles.data();
    HalfedgeId* const owned_twins = mesh_.halfedges.data();
    VertexId* const foreign_vertices = foreign_triangles_.data();
    HalfedgeId* const foreign_twins = foreign_halfedges_.data();
    for (std::size_t i = 0; i < kept_count; ++i) {
      const std::uint32_t t = kept[i];
      const HalfedgeId f = twin_of[t];
      VertexId* const out =
          f < FOREIGN ? owned_vertices + f : foreign_vertices + (f - FOREIGN);
      HalfedgeId* const halfedges =
          f < FOREIGN ? owned_twins + f : foreign_twins + (f - FOREIGN);
      const std::int32_t* const c = tv + 3 * static_cast<std::size_t>(t);
      out[0] = ids[c[0]];
      out[1] = ids[c[1]];
      out[2] = ids[c[2]];
      // The local twins, halfedge j of triangle u: u's first strip halfedge plus j.
      const std::int32_t o[3] = {dt.twin(t, 0), dt.twin(t, 1), dt.twin(t, 2)};
      for (std::uint32_t k = 0; k < 3; ++k) {
        const HalfedgeId base =
            o[k] >= 0 ? twin_of[LocalDelaunay::twinTriangle(o[k])] : HalfedgeId{CLOSED};
        if (base != CLOSED)
          halfedges[k] = base + LocalDelaunay::twinEdge(o[k]);
        else
          open_edges_.push_back({t, k});
      }
    }
    for (const auto& [t, k] : open_edges_) {
      const std::int32_t* const c = tv + 3 * static_cast<std::size_t>(t);
      const auto from = static_cast<std::size_t>(c[k]);
      const auto to = static_cast<std::size_t>(c[k == 2 ? 0 : k + 1]);
      const bool from_in = (flags[from] & IN_STRIP) != 0;
      const bool to_in = (flags[to] & IN_STRIP) != 0;
      const HalfedgeId g = static_cast<HalfedgeId>(twin_of[t] + k);
      if (linkOrOpen(g, from_in, to_in) && (from_in || to_in))
        pool_.push(g, grid_.row(dt.corner(t, k).y));
    }
  }

  /// Points near v sorted by floating-point distance; the exact nearest neighbour is
  /// among them. Blocks of the occupancy pyramid are visited nearest first, so empty
  /// space costs a few large blocks, until the next block is farther than the best
  /// point found (with a margin for rounding).
  void seedCandidates(VertexId v)
  {
    candidates_.clear();
    const Point2 pv = grid_.points[v];
    double best = std::numeric_limits<double>::infinity();
    const auto farther = [](const NearBlock& l, const NearBlock& r) {
      return l.key > r.key;
    };
    blocks_.clear();
    blocks_.push_back(
        {0.0, static_cast<std::uint32_t>(pyramid_.levels.size() - 1), 0, 0});
    while (!blocks_.empty()) {
      std::pop_heap(blocks_.begin(), blocks_.end(), farther);
      const NearBlock block = blocks_.back();
      blocks_.pop_back();
      if (block.key > best * (1.0 + 1e-6))
        break;
      if (block.level == 0) {
        const CellId c = grid_.cellId(block.i, block.j);
        for (VertexId w = grid_.start(c), end = grid_.start(c + 1); w < end; ++w) {
          const double dx = grid_.points[w].x - pv.x, dy = grid_.points[w].y - pv.y;
          const double d2 = dx * dx + dy * dy;
          if (w != v) {
            candidates_.emplace_back(d2, w);
            best = std::min(best, d2);
          }
        }
        continue;
      }
      // The block's points lie within its rectangle widened by the grid slack.
      forEachOccupiedChild(
          pyramid_, block.level, block.i, block.j,
          [&](std::uint32_t ci, std::uint32_t cj) {
            const double key =
                blockRect(grid_, block.level - 1, ci, cj).squaredDistance(pv.x, pv.y);
            blocks_.push_back({key, block.level - 1, ci, cj});
            std::push_heap(blocks_.begin(), blocks_.end(), farther);
          });
    }
    std::sort(candidates_.begin(), candidates_.end());
  }

  /// Starts growing at v from an edge v-w proved Delaunay: the apexes on its two sides
  /// are found by the exact search, and the edge is in the triangulation iff the right
  /// apex is outside the circle of the left triangle (or it is a hull edge). The exact
  /// nearest neighbour always passes, so trying candidates by distance ends.
  Status seedAt(VertexId v)
  {
    seedCandidates(v);
    for (const auto& [d2, w] : candidates_) {
      const VertexId p = search_.findThirdPoint(v, w);
      const VertexId q = search_.findThirdPoint(w, v);
      bool delaunay = false;
      if (p != INVALID_ID && q != INVALID_ID)
        delaunay = incirclePerturbed(grid_.points[v], grid_.points[w], grid_.points[p],
                                     grid_.points[q]) == Sign::NEGATIVE;
      else if (p != INVALID_ID || q != INVALID_ID)
        delaunay = hull_.contains(v, w) || hull_.contains(w, v);
      if (!delaunay)
        continue;
      HalfedgeId e = CLOSED, f = CLOSED;
      if (p != INVALID_ID) {
        e = addTriangle(v, w, p);
        openEdges(e, 1);
      }
      if (q != INVALID_ID) {
        f = addTriangle(w, v, q);
        openEdges(f, 1);
      }
      if (e != CLOSED && f != CLOSED)
        link(e, f);
      return Status::success();
    }
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "no Delaunay edge found at point " + std::to_string(v));
  }

  /// The owned triangles, numbered as in the output from the start (foreign ones
  /// apart), their twins rewritten in place: a twin in the strip kept when owned,
  /// else HULL, the halfedge listed in mesh_.border when its twin is foreign or it is
  /// still open off the hull (another strip owns the twin).
  void finish()
  {
    if (StripSink* const sink = claim_ ? claim_() : nullptr) {
      appendTo(*sink);
      return;
    }
    rewriteTwins(mesh_.triangles.data(), mesh_.halfedges.data(), 0,
                 mesh_.halfedges.size(), 0, mesh_.border);
  }

  /// twins[i] = ownTwin of halfedge first + i, in order. Four at a time where all four
  /// are owned twins (below FOREIGN: shifted, the common case), else one by one.
  void rewriteTwins(const VertexId* v, HalfedgeId* twins, std::size_t first,
                    std::size_t count, HalfedgeId shift,
                    std::vector<BorderHalfedge>& border) const
  {
    std::size_t i = 0;
#if defined(__SSE2__)
    // e < FOREIGN unsigned: (e ^ 0x80000000) < (FOREIGN ^ 0x80000000) signed.
    const __m128i flip = _mm_set1_epi32(static_cast<int>(0x80000000u));
    const __m128i limit = _mm_set1_epi32(static_cast<int>(FOREIGN ^ 0x80000000u));
    const __m128i add = _mm_set1_epi32(static_cast<int>(shift));
    for (; i + 4 <= count; i += 4) {
      auto* const at = reinterpret_cast<__m128i*>(twins + i);
      const __m128i e = _mm_loadu_si128(at);
      const __m128i owned = _mm_cmplt_epi32(_mm_xor_si128(e, flip), limit);
      if (_mm_movemask_epi8(owned) == 0xffff) {
        _mm_storeu_si128(at, _mm_add_epi32(e, add));
        continue;
      }
      for (std::size_t k = i; k < i + 4; ++k)
        twins[k] =
            ownTwin(v, twins[k], static_cast<HalfedgeId>(first + k), shift, border);
    }
#endif
    for (; i < count; ++i)
      twins[i] =
          ownTwin(v, twins[i], static_cast<HalfedgeId>(first + i), shift, border);
  }

  /// The output twin of owned halfedge g (twin e while grown), ids shifted by
  /// `shift`; a border halfedge is listed in `border` and gets HULL.
  HalfedgeId ownTwin(const VertexId* v, HalfedgeId e, HalfedgeId g, HalfedgeId shift,
                     std::vector<BorderHalfedge>& border) const
  {
    if (e < FOREIGN)
      return shift + e;
    const VertexId a = v[g], b = v[nextHalfedge(g)];
    if (e < OPEN || (e != CLOSED && !hull_.contains(a, b)))
      border.push_back({std::min(a, b), std::max(a, b), shift + g});
    return HULL;
  }

  /// finish's result written to the end of the mesh's arrays instead: the same
  /// values as the strip's appended there (ids shifted by the halfedges already in
  /// the mesh), without the strip's copy in between.
  void appendTo(StripSink& sink) const
  {
    const VertexId* const v = mesh_.triangles.data();
    const HalfedgeId* const h = mesh_.halfedges.data();
    const std::size_t count = mesh_.halfedges.size();
    const auto shift = static_cast<HalfedgeId>(sink.halfedges.size());
    // The output's slots (reserved for the whole mesh, written in full) faulted in a
    // chunk ahead (populateAhead) instead of a trap per page.
    constexpr std::size_t STEP = 3u << 10;
    const void* populated_triangles = nullptr;
    const void* populated_halfedges = nullptr;
    for (std::size_t begin = 0; begin < count; begin += STEP) {
      const std::size_t end = std::min(count, begin + STEP);
      populateAhead(sink.triangles, end - begin, populated_triangles);
      populateAhead(sink.halfedges, end - begin, populated_halfedges);
      sink.triangles.insert(sink.triangles.end(), v + begin, v + end);
      // Copied in bulk, then each twin rewritten in place (no push_back per
      // halfedge: its capacity check and size update cost more than the rewrite).
      const std::size_t at = sink.halfedges.size();
      sink.halfedges.insert(sink.halfedges.end(), h + begin, h + end);
      rewriteTwins(v, sink.halfedges.data() + at, begin, end - begin, shift,
                   sink.border);
    }
  }

  const CellGrid& grid_;
  const CellPyramid& pyramid_;
  const HullEdges& hull_;
  MediatrixSearch& search_;
  HalfedgeId* open_head_;
  StripMesh& mesh_;
  const std::uint32_t first_column_;
  const std::uint32_t end_column_;
  const double low_; ///< column coordinates in [low_, high_) are in the strip
  const double high_;
  ForeignHeads foreign_;
  bool corner_in_strip_[3] = {false, false, false}; ///< of the last triangle added
  RowQueue pool_{grid_.ny};
  std::vector<std::pair<double, VertexId>> candidates_;
  std::vector<NearBlock> blocks_;
  const bool cache_blocks_;
  /// Per local halfedge of the block: its strip halfedge once added, or CLOSED.
  std::vector<HalfedgeId> kept_twin_;
  /// Local triangles added, in order (the first ones; sized for a whole block, without
  /// a fill).
  std::vector<std::uint32_t, UninitAllocator<std::uint32_t>> kept_;
  /// Halfedges (local triangle, edge) of the block's kept triangles left unpaired.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> open_edges_;
  // Per local vertex of the block: resized without a fill (written before read).
  std::vector<std::uint8_t, UninitAllocator<std::uint8_t>> vertex_flags_;
  std::vector<std::uint64_t, UninitAllocator<std::uint64_t>> owner_key_;
  std::vector<VertexId, UninitAllocator<VertexId>>
      foreign_triangles_; ///< from FOREIGN on
  std::vector<HalfedgeId, UninitAllocator<HalfedgeId>> foreign_halfedges_;
  const std::function<StripSink*()>& claim_; ///< see growStrip
  LocalDelaunay* const blocks_dt_;           ///< see growStrip; nullptr: one per strip
  const GridBox box_;                        ///< holds every grid point (growStrip)
  /// Where the pages of the strip's arrays populated ahead end (populateAhead).
  const void* populated_triangles_ = nullptr;
  const void* populated_halfedges_ = nullptr;
  std::size_t strip_vertices_ = 0; ///< grid points in the strip's columns
  std::size_t reached_ = 0;        ///< of them, those whose open_head_ is not UNREACHED
};

} // namespace

HullEdges::HullEdges(std::size_t points, const std::vector<VertexId>& hull)
    : on_hull_((points + 63) / 64, 0)
{
  links_.reserve(hull.size());
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const VertexId v = hull[k];
    on_hull_[v >> 6] |= std::uint64_t{1} << (v & 63);
    links_.emplace_back(v, hull[(k + 1) % hull.size()]);
  }
  std::sort(links_.begin(), links_.end());
}

std::size_t windowPoints(const CellGrid& grid, const CellWindow& w)
{
  std::size_t count = 0;
  for (std::uint32_t j = w.j0; j < w.j1; ++j)
    count +=
        grid.start(grid.cellId(w.i1 - 1, j) + 1) - grid.start(grid.cellId(w.i0, j));
  return count;
}

std::uint32_t blockColumnEnd(std::uint32_t i0, std::uint32_t end_column,
                             std::uint32_t block)
{
  const std::uint32_t i1 = std::min(end_column, i0 + block);
  return end_column - i1 < block / 2 ? end_column : i1;
}

std::uint32_t blockBandEnd(const CellGrid& grid, std::uint32_t first_column,
                           std::uint32_t end_column, std::uint32_t j0,
                           std::uint32_t block)
{
  const auto fits = [&grid, first_column, end_column, j0, block](std::uint32_t j1) {
    for (std::uint32_t i0 = first_column, i1 = 0; i0 < end_column; i0 = i1) {
      i1 = blockColumnEnd(i0, end_column, block);
      if (windowPoints(grid, {i0, i1, j0, j1}) > MAX_BLOCK_POINTS)
        return false;
    }
    return true;
  };
  std::uint32_t j1 = std::min(grid.ny, j0 + block);
  while (j1 < grid.ny && j1 - j0 < MAX_BLOCKS_TALL * block) {
    const std::uint32_t taller = std::min(grid.ny, j1 + block);
    if (!fits(taller))
      break;
    j1 = taller;
  }
  if (j1 < grid.ny && grid.ny - j1 < block / 2 && fits(grid.ny))
    j1 = grid.ny;
  return j1;
}

StripLayout stripLayoutFor(const CellGrid& grid, std::uint32_t columns)
{
  constexpr std::uint32_t TARGET_STRIPS = 32;
  constexpr std::uint32_t MIN_WIDTH_SHIFT = 5; // 32 columns
  StripLayout layout;
  if (columns != 0) {
    while ((1u << layout.shift) < columns)
      ++layout.shift;
  } else {
    layout.shift = MIN_WIDTH_SHIFT;
    while ((grid.nx >> layout.shift) > TARGET_STRIPS)
      ++layout.shift;
  }
  layout.count = ((grid.nx - 1) >> layout.shift) + 1;
  return layout;
}

Status growStrip(const CellGrid& grid, const CellPyramid& pyramid,
                 const StripLayout& layout, std::uint32_t strip, const HullEdges& hull,
                 MediatrixSearch& search, HalfedgeId* open_head, StripMesh& mesh,
                 bool cache_blocks, const std::function<StripSink*()>& claim,
                 LocalDelaunay* blocks, const GridBox* box)
{
  return Growth(grid, pyramid, layout, strip, hull, search, open_head, mesh,
                cache_blocks, claim, blocks, box)
      .run();
}

} // namespace detail
} // namespace pcl_vts
