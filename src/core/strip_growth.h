// Region growing inside one vertical strip of grid columns (internal to the
// triangulator). A strip grows every Delaunay triangle that has a vertex in its
// columns, starting from certified seed edges, and keeps the ones it *owns*: those
// whose leftmost vertex (smallest column) lies in the strip. Every triangle has one
// owner, so the strips together tile the hull; they share only the read-only grid,
// so they can run on different threads, and each strip's result depends on nothing
// but the strip: the output is the same for every thread count.
#pragma once

#include "local_delaunay.h"

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/cell_pyramid.h>
#include <pcl_vts/core/mediatrix_search.h>
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <tuple>
#include <utility>
#include <vector>

namespace pcl_vts {
namespace detail {

/// Strips of 2^shift grid columns, numbered left to right (strip of column i is
/// i >> shift); a triangle belongs to the strip of its smallest vertex column.
struct StripLayout {
  std::uint32_t shift = 0; ///< log2 of the strip width in columns
  std::uint32_t count = 1; ///< number of strips
};

/// Strips fixed by the grid alone (never by the thread count): about 32 of them, at
/// least 32 columns wide, so the triangles grown twice along strip borders stay a few
/// percent of the work; or `columns` wide when that is not 0 (a power of two).
StripLayout stripLayoutFor(const CellGrid& grid, std::uint32_t columns = 0);

/// The points of the cells of `w`.
PCL_VTS_CORE_EXPORT std::size_t windowPoints(const CellGrid& grid, const CellWindow& w);

/// Cache blocks' layout (docs/scaling.md): a strip's blocks are bands of rows cut into
/// blocks of columns. Taller blocks load fewer ring points (loaded twice) and leave
/// fewer block borders to the search; MAX_BLOCK_POINTS keeps a window's arrays (about
/// 250 bytes a point) in the cache, MAX_BLOCKS_TALL its cells (sparse bands of
/// clustered points grew to hundreds of mostly empty rows: +3 % instructions at 1e6).
constexpr std::size_t MAX_BLOCK_POINTS = 4608;
constexpr std::uint32_t MAX_BLOCKS_TALL = 3;

/// The end of the block of columns from column i0 of a strip ending at end_column:
/// `block` columns, or the strip's end when fewer than block / 2 would be left to a
/// block of their own (the grid's right side, whose last strip's columns are not a
/// multiple of `block`: a thin block loads about as many ring points as its own).
PCL_VTS_CORE_EXPORT std::uint32_t
blockColumnEnd(std::uint32_t i0, std::uint32_t end_column, std::uint32_t block);

/// The end of the band of block rows from row j0 of the strip [first_column,
/// end_column): `block` rows, more by `block` rows at a time while each of the band's
/// blocks (blockColumnEnd) holds at most MAX_BLOCK_POINTS points, up to
/// MAX_BLOCKS_TALL times `block`; then a rest of fewer than block / 2 rows (the grid's
/// top) is joined to the band when each block still holds at most MAX_BLOCK_POINTS
/// (ISPRS FSite8, 105 x 105 cells: one band of 105 rows instead of 96 + 9).
PCL_VTS_CORE_EXPORT std::uint32_t blockBandEnd(const CellGrid& grid,
                                               std::uint32_t first_column,
                                               std::uint32_t end_column,
                                               std::uint32_t j0, std::uint32_t block);

/// The hull's directed edges v->w (interior on the left), for membership tests: a bit
/// per point plus the sorted hull links, so it costs n/8 bytes, not 4n.
class HullEdges {
 public:
  HullEdges(std::size_t points, const std::vector<VertexId>& hull);
  bool contains(VertexId v, VertexId w) const
  {
    if (((on_hull_[v >> 6] >> (v & 63)) & 1u) == 0)
      return false;
    const auto it = std::lower_bound(links_.begin(), links_.end(),
                                     std::pair<VertexId, VertexId>{v, 0});
    return it != links_.end() && it->first == v && it->second == w;
  }

 private:
  std::vector<std::uint64_t> on_hull_;
  std::vector<std::pair<VertexId, VertexId>> links_; ///< (v, next hull vertex), by v
};

/// The halfedge slot states of strip growth, in one table. Halfedge ids stay below
/// OPEN_LIST_END, so a slot never mistakes an id for a state.
///   StripMesh::halfedges while a strip grows: a twin (< OPEN_LIST_END); OPEN | next,
///     an open halfedge whose `next` is the following open halfedge of the same origin
///     (or OPEN_LIST_END); or CLOSED, no twin and never one (the right side of a hull
///     edge), the state a new slot starts in.
///   open_head, per grid point: UNREACHED (no triangle of its strip touches it yet),
///     OPEN_LIST_END (reached, no open halfedge) or its first open halfedge.
/// Once grown (growStrip's result) the owned triangles alone are left (numbered so
/// from the start: the growth keeps the others apart): a strip-local twin or HULL
/// (INVALID_ID: no twin in the strip, see StripMesh::border).
enum HalfedgeSlot : HalfedgeId {
  OPEN_LIST_END = 0x7ffffffeu, ///< end of an open-halfedge list
  OPEN = 0x80000000u,          ///< flag of an open halfedge; the rest links the list
  CLOSED = INVALID_ID,         ///< while growing: no twin, never one
  HULL = INVALID_ID,           ///< once grown: no twin in the strip
  UNREACHED = 0xffffffffu,     ///< open_head of a point no triangle touches yet
};
/// A halfedge of an owned triangle whose twin another strip owns.
struct BorderHalfedge {
  VertexId low, high;  ///< the edge's vertices, sorted
  HalfedgeId halfedge; ///< strip-local id, then global once merged
  bool operator<(const BorderHalfedge& r) const
  {
    return std::tie(low, high, halfedge) < std::tie(r.low, r.high, r.halfedge);
  }
};

/// What one strip grew; its halfedge slots are in the HalfedgeSlot table. Once grown:
/// the owned triangles only, strip-local ids from 0 in the order grown.
struct StripMesh {
  /// 3 per owned triangle, numbered in the order grown (the growth keeps the others
  /// apart); resized without a fill (written after).
  std::vector<VertexId, UninitAllocator<VertexId>> triangles;
  std::vector<HalfedgeId, UninitAllocator<HalfedgeId>> halfedges; ///< 1 per halfedge
  std::vector<BorderHalfedge> border; ///< once grown: the halfedges left HULL for this
};

/// The mesh's arrays, which a grown strip may append its owned triangles to directly
/// (instead of compacting them in its own arrays for a later copy): ids shifted to
/// global ones, border halfedges listed with global ids.
struct StripSink {
  std::vector<VertexId>& triangles;
  std::vector<HalfedgeId>& halfedges;
  std::vector<BorderHalfedge>& border;
};

/// Grows strip `strip` of `layout`. `open_head` (one slot per grid point, filled with
/// UNREACHED, see HalfedgeSlot) is shared by all strips: a strip only touches the slots
/// of its own vertices, where it keeps the head of each vertex's list of open
/// halfedges. `cache_blocks`: the triangles proven by block-local triangulations are
/// added first (docs/scaling.md, "Cache blocks"); the same triangles, another order.
/// `claim`,
/// when set, is asked once the strip is grown: a sink it returns receives the owned
/// triangles (`mesh` is then left as grown), else they are compacted in `mesh`.
/// `blocks`, when set: the caller's block triangulator (one per worker, reused strip
/// after strip: its arrays' pages stay resident); else one of the strip's own.
/// `box`, when set: a box holding every grid point (GridBox::ofPoints, computed once
/// for all strips), for the blocks' finality on the grid's border; else
/// GridBox::ofCells.
Status growStrip(const CellGrid& grid, const CellPyramid& pyramid,
                 const StripLayout& layout, std::uint32_t strip, const HullEdges& hull,
                 MediatrixSearch& search, HalfedgeId* open_head, StripMesh& mesh,
                 bool cache_blocks = false,
                 const std::function<StripSink*()>& claim = {},
                 LocalDelaunay* blocks = nullptr, const GridBox* box = nullptr);

} // namespace detail
} // namespace pcl_vts
