// Cache blocks (docs/scaling.md, "Cache blocks"): the Delaunay triangulation of the
// points of a block of grid cells and a ring of cells around it, by Bowyer-Watson
// insertion inside a finite super triangle, with the exact predicates and the
// tie-break of predicates.h. A triangle of real points whose circumdisk lies inside
// the loaded window (shrunk by the grid slack; open on the grid border) is proven
// final: no unloaded point can be inside or on its circle, so it is a triangle of the
// global (perturbed) Delaunay triangulation. Internal to the core.
#pragma once

#include "uninit_allocator.h"

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/error_bounds.h>
#include <pcl_vts/core/point2.h>
#include <pcl_vts/core/predicates.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pcl_vts {
namespace detail {

/// The loaded window: cells [i0, i1) x [j0, j1).
struct CellWindow {
  std::uint32_t i0, i1, j0, j1;
};

/// A box that holds every point of the grid, inside or on its sides: finality on
/// the grid's border (LocalDelaunay::finalInGrid) asks that a disk meet none of it
/// outside the window.
struct GridBox {
  double x_lo, x_hi, y_lo, y_hi;
  /// The grid's cells grown by twice the slack (every point lies within the slack of
  /// its cell's rectangle).
  static GridBox ofCells(const CellGrid& grid)
  {
    return {grid.origin_x - 2 * grid.slack,
            grid.origin_x + grid.nx * grid.cell_size + 2 * grid.slack,
            grid.origin_y - 2 * grid.slack,
            grid.origin_y + grid.ny * grid.cell_size + 2 * grid.slack};
  }
  /// The points' own bounding box (exact: the least and greatest coordinates), at
  /// most ofCells's; a whole cell less on the sides where the grid's cells run past
  /// the last point (the grid's upper and right sides mostly), so that more hull
  /// triangles there are final.
  PCL_VTS_CORE_EXPORT static GridBox ofPoints(const CellGrid& grid);
};

/// Bowyer-Watson triangulation of one window, arrays reused from window to window.
/// Triangle t: vertices v[3t..3t+2] (local indices, CCW), halfedge i of t goes
/// v[3t+i] -> v[3t+(i+1)%3]; twin(t, i) is its twin as 16u + j (halfedge j of u) or
/// -1, read from the working records (no copy-out). Local vertices 0..2 are the
/// super triangle; vertex k >= 3 is grid point ids[k].
class LocalDelaunay {
 public:
  /// Triangulates the window's points (cells at multiples of 4 from its corner first,
  /// then of 2, then the rest, each round in snake order: the mesh covers the window
  /// early, so cavities stay small). False when the window is too large for floating
  /// point (a super triangle coordinate would not be finite): nothing is proven then.
  /// in_core[k]: local vertex k lies in a cell of `core`.
  bool triangulate(const CellGrid& grid, const CellWindow& window,
                   const CellWindow& core);

  /// Calls keep(t) for every triangle of real points whose circumdisk is proven to
  /// lie inside the window's known space.
  template <typename Keep>
  void forEachFinal(const CellGrid& grid, const CellWindow& window, Keep&& keep) const
  {
    forEachFinal(
        grid, window, GridBox::ofCells(grid), [](std::size_t) { return true; }, keep);
  }

  /// The same for the triangles of real points with wanted(t) only: the bound (two
  /// divisions, three square roots) is computed for those alone. `box` holds every
  /// point of the grid (GridBox).
  template <typename Wanted, typename Keep>
  void forEachFinal(const CellGrid& grid, const CellWindow& window, const GridBox& box,
                    Wanted&& wanted, Keep&& keep) const;

  /// The twin of halfedge i of triangle t: 16u + j for halfedge j of triangle u
  /// (twinTriangle, twinEdge), or -1.
  std::int32_t twin(std::size_t t, std::uint32_t i) const { return rec_[t].adj[i]; }
  static std::uint32_t twinTriangle(std::int32_t twin)
  {
    return static_cast<std::uint32_t>(twin) >> 4;
  }
  static std::uint32_t twinEdge(std::int32_t twin)
  {
    return static_cast<std::uint32_t>(twin) & 15u;
  }
  /// Corner i of triangle t (p[v[3t + i]], from the triangle's records).
  const Point2& corner(std::size_t t, std::uint32_t i) const
  {
    return i < 2 ? corners_[t].p[i] : rec_[t].apex;
  }
  std::size_t triangleCount() const { return triangles_; }

  // Resized without a fill (each window writes every entry it reads).
  std::vector<Point2, UninitAllocator<Point2>> p;
  std::vector<std::int32_t, UninitAllocator<std::int32_t>> v;
  std::vector<std::uint32_t, UninitAllocator<std::uint32_t>> ids;
  std::vector<std::uint8_t, UninitAllocator<std::uint8_t>> in_core;

  /// The finality tests of forEachFinal, pure functions of a triangle's corners and
  /// the window (x_lo..y_hi, already shrunk by the grid slack): true only when the
  /// circumdisk lies strictly inside it, rounding included (test_block_finality
  /// checks that against exact arithmetic). finalByVertices is the cheap sufficient
  /// condition tried first; finalTriangle decides the rest.
  static bool finalTriangle(const Point2& a, const Point2& b, const Point2& c,
                            double x_lo, double x_hi, double y_lo, double y_hi);
  static bool finalByVertices(const Point2& a, const Point2& b, const Point2& c,
                              double x_lo, double x_hi, double y_lo, double y_hi,
                              double margin);
  /// For windows on the grid's border: true only when the circumdisk, rounding
  /// included, meets none of the grid's box [gx_lo, gx_hi] x [gy_lo, gy_hi] outside
  /// the window (x_lo..y_hi, infinite on the grid's sides): no point lies outside the
  /// grid's box, so the disks of hull triangles, which reach far out of the grid,
  /// are final when the part of them over the grid is inside the window.
  static bool finalInGrid(const Point2& a, const Point2& b, const Point2& c,
                          double x_lo, double x_hi, double y_lo, double y_hi,
                          double gx_lo, double gx_hi, double gy_lo, double gy_hi);

 private:
  /// Inserts local vertices 3 .. count - 1 in order.
  void insertPoints(std::size_t count);
  void outsideBox(const Point2& q, double cx, double cy, double d);
  void reserveTriangles(std::size_t count);

  /// What the cavity search reads of a triangle, in one cache line: its last corner
  /// (the point whose insertion made it) and its in-circle coefficients about that
  /// corner (predicates.h, incircleCoefficients: computed once, when the triangle is
  /// made), its twins as halfedges 16t + i (no division by 3; see twinSlot) and whether
  /// its first two vertices are real points (the tight bound applies; the last one
  /// always is). The
  /// first two corners' coordinates (copied: no load through the vertex ids on the
  /// walk's critical path) are in corners_, read by the walk, the exact fallback and
  /// the finality pass.
  struct alignas(64) Record {
    Point2 apex;
    IncircleCoefficients k;
    std::array<std::int32_t, 3> adj;
    std::int32_t real;
  };
  struct Corners {
    std::array<Point2, 2> p;
  };
  /// Triangles per window: 16t + 2 must fit an int32.
  static constexpr std::size_t MAX_TRIANGLES = std::size_t{1} << 27;
  /// The twin slot of halfedge h = 16t + i, rec_[t].adj[i]: a record is 64 bytes, 16
  /// int32, so the slot's address is linear in h (4h bytes past the first record's
  /// adj): one scaled load on the cavity search's critical path instead of a shift,
  /// mask and multiply of t and i apart.
  static std::int32_t& twinSlot(Record* records, std::uint32_t h)
  {
    static_assert(sizeof(Record) == 16 * sizeof(std::int32_t), "16t + i addressing");
    return *reinterpret_cast<std::int32_t*>(reinterpret_cast<char*>(records) +
                                            offsetof(Record, adj) +
                                            4 * static_cast<std::size_t>(h));
  }
  /// The record of the triangle of halfedge h = 16t + i: 64t bytes are 4 (h - i)
  /// bytes, a mask and a scaled index instead of a shift and a multiply.
  static Record& recordOf(Record* records, std::uint32_t h)
  {
    return *reinterpret_cast<Record*>(reinterpret_cast<char*>(records) +
                                      4 * static_cast<std::size_t>(h & ~15u));
  }
  std::vector<Record, UninitAllocator<Record>> rec_;
  std::vector<Corners, UninitAllocator<Corners>> corners_;
  std::vector<std::uint32_t, UninitAllocator<std::uint32_t>> bad_, stack_;
  /// A cavity boundary edge: its first vertex and the halfedge across it (or -1).
  struct Edge {
    std::int32_t first, second;
  };
  std::vector<Edge, UninitAllocator<Edge>> boundary_;
  std::int32_t last_ = 0;
  std::size_t triangles_ = 0;
  /// Cells (di, dj) to insert, all written when listed.
  std::vector<std::array<std::uint32_t, 2>,
              UninitAllocator<std::array<std::uint32_t, 2>>>
      order_;
  std::uint32_t order_width_ = 0, order_height_ = 0;
  double orient_bound_ = 0.0, incircle_wide_bound_ = 0.0, incircle_tight_bound_ = 0.0;
  /// Where the pages faulted in ahead of the writes end, per array written in full by
  /// a window (p, ids, in_core, rec_, corners_, v; see populateFirst).
  std::array<const void*, 6> populated_{};
};

inline bool LocalDelaunay::finalTriangle(const Point2& a, const Point2& b,
                                         const Point2& c, double x_lo, double x_hi,
                                         double y_lo, double y_hi)
{
  // The circumdisk grown by a bound on its rounding, the tiles' rule too
  // (error_bounds.h); a flat triangle proves nothing.
  const CircumdiskBound disk = boundCircumdisk(a, b, c);
  return !disk.unbounded && disk.center.x - disk.radius > x_lo &&
         disk.center.x + disk.radius < x_hi && disk.center.y - disk.radius > y_lo &&
         disk.center.y + disk.radius < y_hi;
}

inline bool LocalDelaunay::finalInGrid(const Point2& a, const Point2& b,
                                       const Point2& c, double x_lo, double x_hi,
                                       double y_lo, double y_hi, double gx_lo,
                                       double gx_hi, double gy_lo, double gy_hi)
{
  const CircumdiskBound disk = boundCircumdisk(a, b, c);
  if (disk.unbounded)
    return false;
  const double r2 = disk.radius * disk.radius * (1.0 + 1e-12);
  // The disk misses the closed rectangle [x0, x1] x [y0, y1] (none when empty): the
  // squared distance from its centre, each difference, square and sum rounded to
  // nearest (a relative error under 5 units in the last place, far inside 1e-12;
  // an underflow only lowers it), exceeds the squared radius (an overflow: not).
  const auto misses = [&disk, r2](double x0, double x1, double y0, double y1) {
    if (!(x0 <= x1 && y0 <= y1))
      return true;
    const double dx = std::max(std::max(x0 - disk.center.x, disk.center.x - x1), 0.0);
    const double dy = std::max(std::max(y0 - disk.center.y, disk.center.y - y1), 0.0);
    return (dx * dx + dy * dy) * (1.0 - 1e-12) > r2;
  };
  // The grid's box outside the open window: the slabs beyond each of its sides.
  return misses(x_hi, gx_hi, gy_lo, gy_hi) && misses(gx_lo, x_lo, gy_lo, gy_hi) &&
         misses(gx_lo, gx_hi, y_hi, gy_hi) && misses(gx_lo, gx_hi, gy_lo, y_lo);
}

/// A sufficient condition for finalTriangle's bound without its divisions and square
/// roots, tried first. Every point of the circumdisk (radius R) lies within 2R of each
/// vertex (R of the centre, which is R from the vertex), so the disk is inside the box
/// when the vertices' extreme coordinates are more than 2R inside it: with P the
/// product of the squared sides and det = 2 cross(b - a, c - a), 4R^2 = 4P / det^2, so
/// the test is 4P < (G |det|)^2, G the least of those four distances. Each computed
/// quantity is within a few units in the last place of its value (differences of
/// input coordinates are correctly rounded, the sides' squares are kept in
/// [1e-100, 1e100], so no product under- or overflows), and det within Shewchuk's
/// orient2d bound (3.3e-16 of |t1| + |t2|, 4e-16 used): the relative factor 1e-5 and
/// `margin` (an absolute 1e-14 of the window's coordinates) exceed them with room.
/// They exceed as well finalTriangle's own allowance (1e-7 of r + |b| + |c| <= 5e-7 R,
/// 1e-15 of |a|, and its roundings), and the flatness test is finalTriangle's: a
/// triangle passing here passes finalTriangle, so the triangles kept are the same.
inline bool LocalDelaunay::finalByVertices(const Point2& a, const Point2& b,
                                           const Point2& c, double x_lo, double x_hi,
                                           double y_lo, double y_hi, double margin)
{
#if defined(__SSE2__)
  // The same operations on (x, y) lanes: the same values, fewer instructions (the
  // extremes are selections: _mm_min_pd and _mm_max_pd agree with std::min and
  // std::max but for the sign of a zero, which no comparison below sees).
  const __m128d pa = _mm_loadu_pd(&a.x), pb = _mm_loadu_pd(&b.x),
                pc = _mm_loadu_pd(&c.x);
  const __m128d ab = _mm_sub_pd(pb, pa), ac = _mm_sub_pd(pc, pa),
                bc = _mm_sub_pd(pc, pb);
  const __m128d t12 = _mm_mul_pd(ab, _mm_shuffle_pd(ac, ac, 1)); // (bx cy, by cx)
  const double t1 = _mm_cvtsd_f64(t12), t2 = _mm_cvtsd_f64(_mm_unpackhi_pd(t12, t12));
  const __m128d ab2 = _mm_mul_pd(ab, ab), ac2 = _mm_mul_pd(ac, ac),
                bc2 = _mm_mul_pd(bc, bc);
  const __m128d sides =
      _mm_add_pd(_mm_unpacklo_pd(ab2, ac2), _mm_unpackhi_pd(ab2, ac2)); // (b2, c2)
  const double b2 = _mm_cvtsd_f64(sides),
               c2 = _mm_cvtsd_f64(_mm_unpackhi_pd(sides, sides));
  const double e2 = _mm_cvtsd_f64(_mm_add_sd(bc2, _mm_unpackhi_pd(bc2, bc2)));
  const __m128d top = _mm_max_pd(pa, _mm_max_pd(pb, pc));    // (max x, max y)
  const __m128d bottom = _mm_min_pd(pa, _mm_min_pd(pb, pc)); // (min x, min y)
  const __m128d gaps = _mm_min_pd(_mm_sub_pd(top, _mm_set_pd(y_lo, x_lo)),
                                  _mm_sub_pd(_mm_set_pd(y_hi, x_hi), bottom));
  const double g =
      _mm_cvtsd_f64(_mm_min_sd(gaps, _mm_unpackhi_pd(gaps, gaps))) - margin;
#else
  const double bx = b.x - a.x, by = b.y - a.y;
  const double cx = c.x - a.x, cy = c.y - a.y;
  const double ex = c.x - b.x, ey = c.y - b.y;
  const double t1 = bx * cy, t2 = by * cx;
  const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy, e2 = ex * ex + ey * ey;
  const double g = std::min(std::min(std::max(a.x, std::max(b.x, c.x)) - x_lo,
                                     x_hi - std::min(a.x, std::min(b.x, c.x))),
                            std::min(std::max(a.y, std::max(b.y, c.y)) - y_lo,
                                     y_hi - std::min(a.y, std::min(b.y, c.y)))) -
                   margin;
#endif
  const double det = 2.0 * (t1 - t2);
  const double sum = std::fabs(t1) + std::fabs(t2);
  const double lo = std::min(b2, std::min(c2, e2)), hi = std::max(b2, std::max(c2, e2));
  const double q = std::fabs(det) - (8e-16 * sum + 1e-300);
  const double gq = g * q;
  return std::fabs(det) > 1e-6 * sum && lo >= 1e-100 && hi <= 1e100 && q > 0.0 &&
         g > 0.0 && 4.0 * (b2 * c2 * e2) * (1.0 + 1e-5) < gq * gq;
}

template <typename Wanted, typename Keep>
void LocalDelaunay::forEachFinal(const CellGrid& grid, const CellWindow& w,
                                 const GridBox& box, Wanted&& wanted, Keep&& keep) const
{
  const double c = grid.cell_size;
  const double inf = std::numeric_limits<double>::infinity();
  // A point of an unloaded cell lies within the slack of its cell's rectangle.
  const double x0 = grid.origin_x + w.i0 * c, x1 = grid.origin_x + w.i1 * c;
  const double y0 = grid.origin_y + w.j0 * c, y1 = grid.origin_y + w.j1 * c;
  const double x_lo = w.i0 == 0 ? -inf : x0 + 2 * grid.slack;
  const double x_hi = w.i1 == grid.nx ? inf : x1 - 2 * grid.slack;
  const double y_lo = w.j0 == 0 ? -inf : y0 + 2 * grid.slack;
  const double y_hi = w.j1 == grid.ny ? inf : y1 - 2 * grid.slack;
  // Bounds |a.x| + |a.y| of every loaded point (within a cell of the window) and the
  // window's own coordinates.
  const double margin = 1e-14 * (std::max(std::fabs(x0), std::fabs(x1)) +
                                 std::max(std::fabs(y0), std::fabs(y1)) + 4 * c);
  // Every point lies in `box`: windows on the grid's border also get finalInGrid.
  const bool border = w.i0 == 0 || w.i1 == grid.nx || w.j0 == 0 || w.j1 == grid.ny;
  const double gx_lo = box.x_lo, gx_hi = box.x_hi, gy_lo = box.y_lo, gy_hi = box.y_hi;
  // The corners' coordinates from the records (no lookup through the vertex ids).
  // `real`: the first two vertices are real points; the last one is for every
  // triangle but the super triangle, whose record says it is not.
  const Record* const R = rec_.data();
  const Corners* const C = corners_.data();
  for (std::size_t t = 0; t < triangles_; ++t) {
    const Record& r = R[t];
    const Corners& f = C[t];
    if (r.real != 0 && wanted(t) &&
        (finalByVertices(f.p[0], f.p[1], r.apex, x_lo, x_hi, y_lo, y_hi, margin) ||
         finalTriangle(f.p[0], f.p[1], r.apex, x_lo, x_hi, y_lo, y_hi) ||
         (border && finalInGrid(f.p[0], f.p[1], r.apex, x_lo, x_hi, y_lo, y_hi, gx_lo,
                                gx_hi, gy_lo, gy_hi))))
      keep(t);
  }
}

} // namespace detail
} // namespace pcl_vts
