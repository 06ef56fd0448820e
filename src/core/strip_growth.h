// Region growing inside one vertical strip of grid columns (internal to the
// triangulator). A strip grows every Delaunay triangle that has a vertex in its
// columns, starting from certified seed edges, and keeps the ones it *owns*: those
// whose leftmost vertex (smallest column) lies in the strip. Every triangle has one
// owner, so the strips together tile the hull; they share only the read-only grid,
// so they can run on different threads, and each strip's result depends on nothing
// but the strip: the output is the same for every thread count.
#pragma once

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/cell_pyramid.h>
#include <pcl_vts/core/mediatrix_search.h>
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>

#include <algorithm>
#include <cstdint>
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

/// What one strip grew. Halfedge slots of owned triangles hold a strip-local twin
/// (of an owned triangle), BORDER (the twin belongs to another strip) or INVALID_ID
/// (hull).
struct StripMesh {
  static constexpr HalfedgeId BORDER = 0xfffffffdu;
  std::vector<VertexId> triangles;   ///< 3 per triangle grown (owned or not)
  std::vector<HalfedgeId> halfedges; ///< 1 per halfedge, see above (owned only)
  std::vector<bool> owned;           ///< 1 per triangle grown
  std::size_t owned_count = 0;
};

/// Grows strip `strip` of `layout`. `open_head` (one slot per grid point, filled with
/// UNREACHED) is shared by all strips: a strip only touches the slots of its own
/// vertices, where it keeps the head of each vertex's list of open halfedges.
Status growStrip(const CellGrid& grid, const CellPyramid& pyramid,
                 const StripLayout& layout, std::uint32_t strip, const HullEdges& hull,
                 MediatrixSearch& search, std::vector<HalfedgeId>& open_head,
                 StripMesh& mesh);

/// End of an open-halfedge list; halfedge ids stay below it.
constexpr HalfedgeId OPEN_LIST_END = 0x7ffffffeu;
/// The open_head value of a vertex no triangle of its strip touches yet.
constexpr HalfedgeId UNREACHED = 0xffffffffu;

} // namespace detail
} // namespace pcl_vts
