#include "local_delaunay.h"
#include "release_memory.h"

#include <pcl_vts/core/predicates.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace pcl_vts {
namespace detail {
namespace {

/// Resizes an array whose entries need not survive: past its capacity a new block is
/// allocated and the old one freed, its entries not copied (the copy touched every
/// page of the new block: page faults on a small input). The capacity at least
/// doubles, as std::vector's growth (windows grow block after block: samp11 faulted
/// in 171 more pages with an eighth more a time), and starts an eighth past the size;
/// the new block is taken before the old one is freed, as std::vector does (freeing
/// first cost CSite1 about 2 %).
template <typename Vector>
void resizeDiscarding(Vector& vector, std::size_t size)
{
  if (vector.capacity() < size) {
    const std::size_t capacity = std::max(size + size / 8, 2 * vector.capacity());
    Vector fresh;
    fresh.reserve(capacity);
    vector.swap(fresh);
  }
  vector.resize(size);
}

/// Faults in the pages of the array's first `count` entries in one system call
/// (populatePages) from where the last call for it stopped (`populated`, in the
/// array's current block; anything else: from its start). A window writes these
/// entries in full; on a small input its arrays' pages are fresh (samp11: about 260
/// of the pipeline's 860 page faults), and a trap per page cost about 2.9 us on this
/// VM against 2.1 us populated (one mmap of 256 MB, touched page by page after
/// MADV_POPULATE_WRITE or not). The contents are not changed.
template <typename Vector>
void populateFirst(const Vector& vector, std::size_t count, const void*& populated)
{
  const auto address = [](const void* pointer) {
    return reinterpret_cast<std::uintptr_t>(pointer);
  };
  const void* const begin = vector.data();
  const void* const need = vector.data() + count;
  const void* const end = vector.data() + vector.capacity();
  const void* from = populated;
  if (address(from) < address(begin) || address(from) > address(end))
    from = begin;
  if (address(need) <= address(from))
    return;
  populatePages(from, need);
  populated = need;
}

} // namespace

GridBox GridBox::ofPoints(const CellGrid& grid)
{
  if (grid.points.empty())
    return ofCells(grid);
  // Cell lookup is monotone in x and in y (cell_grid.h): a point of a higher row has a
  // y at least that of every point of a lower row, so the least and greatest y are
  // among the points of the lowest and highest occupied rows, and the same holds for
  // x and the columns. A row's points are consecutive slots; a column's, one cell a
  // row.
  const double inf = std::numeric_limits<double>::infinity();
  GridBox box{inf, -inf, inf, -inf};
  const auto rowRange = [&grid](std::uint32_t j) {
    return std::pair<std::uint32_t, std::uint32_t>{grid.start(grid.cellId(0, j)),
                                                   grid.start(grid.cellId(0, j + 1))};
  };
  for (std::uint32_t j = 0; j < grid.ny && box.y_lo == inf; ++j)
    for (auto [k, end] = rowRange(j); k < end; ++k)
      box.y_lo = std::min(box.y_lo, grid.points[k].y);
  for (std::uint32_t j = grid.ny; j > 0 && box.y_hi == -inf; --j)
    for (auto [k, end] = rowRange(j - 1); k < end; ++k)
      box.y_hi = std::max(box.y_hi, grid.points[k].y);
  const auto column = [&grid](std::uint32_t i, auto&& visit) {
    for (std::uint32_t j = 0; j < grid.ny; ++j) {
      const CellId cell = grid.cellId(i, j);
      for (std::uint32_t k = grid.start(cell), end = grid.start(cell + 1); k < end; ++k)
        visit(grid.points[k].x);
    }
  };
  for (std::uint32_t i = 0; i < grid.nx && box.x_lo == inf; ++i)
    column(i, [&box](double x) { box.x_lo = std::min(box.x_lo, x); });
  for (std::uint32_t i = grid.nx; i > 0 && box.x_hi == -inf; --i)
    column(i - 1, [&box](double x) { box.x_hi = std::max(box.x_hi, x); });
  // Finite points give a finite box (ofCells otherwise: not expected).
  if (!(std::isfinite(box.x_lo) && std::isfinite(box.x_hi) && std::isfinite(box.y_lo) &&
        std::isfinite(box.y_hi)))
    return ofCells(grid);
  return box;
}

bool LocalDelaunay::triangulate(const CellGrid& grid, const CellWindow& w,
                                const CellWindow& core)
{
  const double c = grid.cell_size;
  const double x0 = grid.origin_x + w.i0 * c, x1 = grid.origin_x + w.i1 * c;
  const double y0 = grid.origin_y + w.j0 * c, y1 = grid.origin_y + w.j1 * c;
  const double cx = 0.5 * x0 + 0.5 * x1, cy = 0.5 * y0 + 0.5 * y1;
  // Points may sit a slack outside their cells: the super triangle is far wider.
  const double d = std::max(x1 - x0, y1 - y0) + c + std::fabs(cx) * 0x1p-40 +
                   std::fabs(cy) * 0x1p-40;
  const Point2 super[3] = {{cx - 10.0 * d, cy - 10.0 * d},
                           {cx + 10.0 * d, cy - 10.0 * d},
                           {cx, cy + 10.0 * d}};
  for (const Point2& s : super)
    if (!std::isfinite(s.x) || !std::isfinite(s.y))
      return false;
  // Semi-static filter bounds (predicates.h, BoxBounds): one box holds the super
  // triangle and every point (checked as the points are gathered), a tight one the
  // window's cells widened by one cell for the triangles of real points.
  const double tx_lo = x0 - c, tx_hi = x1 + c, ty_lo = y0 - c, ty_hi = y1 + c;
  const BoxBounds wide =
      boxBounds(std::min(cx - 10.0 * d, tx_lo), std::max(cx + 10.0 * d, tx_hi),
                std::min(cy - 10.0 * d, ty_lo), std::max(cy + 10.0 * d, ty_hi));
  orient_bound_ = wide.orient;
  // The in-circle tests use each triangle's coefficients (predicates.h,
  // coefficientBound).
  incircle_wide_bound_ =
      coefficientBound(std::min(cx - 10.0 * d, tx_lo), std::max(cx + 10.0 * d, tx_hi),
                       std::min(cy - 10.0 * d, ty_lo), std::max(cy + 10.0 * d, ty_hi));
  incircle_tight_bound_ = coefficientBound(tx_lo, tx_hi, ty_lo, ty_hi);
  // n points make 1 + 2n triangles (each insertion replaces a cavity of m triangles
  // by m + 2): the arrays are sized once per window, not per insertion.
  std::size_t n = 0;
  for (std::uint32_t j = w.j0; j < w.j1; ++j)
    n += grid.start(grid.cellId(w.i1 - 1, j) + 1) - grid.start(grid.cellId(w.i0, j));
  // Halfedges are 16t + i in int32 (Record): windows of more points are left to the
  // search (nothing proven), far beyond what a block of cells holds.
  if (1 + 2 * n > MAX_TRIANGLES)
    return false;
  reserveTriangles(1 + 2 * n);
  // Entries 3 .. 3 + n are all written below (the insertion order lists every cell of
  // the window once): resize, not assign, fills only what grows past the last window.
  resizeDiscarding(p, 3 + n);
  resizeDiscarding(ids, 3 + n);
  resizeDiscarding(in_core, 3 + n);
  populateFirst(p, 3 + n, populated_[0]);
  populateFirst(ids, 3 + n, populated_[1]);
  populateFirst(in_core, 3 + n, populated_[2]);
  populateFirst(rec_, 1 + 2 * n, populated_[3]);
  populateFirst(corners_, 1 + 2 * n, populated_[4]);
  populateFirst(v, 3 * (1 + 2 * n), populated_[5]);
  for (std::size_t s = 0; s < 3; ++s) {
    p[s] = super[s];
    ids[s] = INVALID_ID;
    in_core[s] = 0;
  }
  v[0] = 0;
  v[1] = 1;
  v[2] = 2;
  rec_[0] = {p[2], incircleCoefficients(p[0], p[1], p[2]), {-1, -1, -1}, 0};
  corners_[0] = {{p[0], p[1]}};
  triangles_ = 1;
  last_ = 0;
  // Insertion order: cells at multiples of 4 from the window's corner, then of 2, then
  // the rest, each round in snake order over the cell rows; the order depends only on
  // the window's size, so it is listed once per size.
  const std::uint32_t width = w.i1 - w.i0, height = w.j1 - w.j0;
  if (width != order_width_ || height != order_height_) {
    order_width_ = width;
    order_height_ = height;
    // Listed directly (the window sizes vary with the bands and the grid's border,
    // so this runs a few times per strip): a row dj of a round of stride s is a
    // multiple of s; in the rounds of stride 2 and 1 a row that is a multiple of 2s
    // holds only the odd multiples of s (the even ones were listed by the round
    // before); rows run left to right when dj is even, right to left when odd (only
    // in the round of stride 1).
    order_.resize(static_cast<std::size_t>(width) * height);
    std::size_t listed = 0;
    for (std::uint32_t stride = 4; stride >= 1; stride /= 2)
      for (std::uint32_t dj = 0; dj < height; dj += stride) {
        if ((dj & 1u) != 0) {
          for (std::uint32_t di = width; di-- > 0;)
            order_[listed++] = {di, dj};
          continue;
        }
        const bool odd_only = stride < 4 && dj % (2 * stride) == 0;
        const std::uint32_t step = odd_only ? 2 * stride : stride;
        for (std::uint32_t di = odd_only ? stride : 0; di < width; di += step)
          order_[listed++] = {di, dj};
      }
  }
  std::size_t k_local = 3;
  for (const std::array<std::uint32_t, 2>& cell_offset : order_) {
    const std::uint32_t i = w.i0 + cell_offset[0], j = w.j0 + cell_offset[1];
    const CellId cell = grid.cellId(i, j);
    const std::uint8_t inside =
        i >= core.i0 && i < core.i1 && j >= core.j0 && j < core.j1 ? 1 : 0;
    for (std::uint32_t k = grid.start(cell), end = grid.start(cell + 1); k < end; ++k) {
      const Point2& q = grid.points[k];
      if (!(q.x >= tx_lo && q.x <= tx_hi && q.y >= ty_lo && q.y <= ty_hi))
        outsideBox(q, cx, cy, d);
      ids[k_local] = k;
      in_core[k_local] = inside;
      p[k_local] = q;
      ++k_local;
    }
  }
  // Each walk starts from the triangle of the previous star that faces the point.
  insertPoints(k_local);
  v.resize(3 * triangles_);
  return true;
}

void LocalDelaunay::reserveTriangles(std::size_t count)
{
  // Nothing in these arrays is kept across the call (a new window, or the scratch
  // between two insertions): they grow without copying their old entries.
  if (rec_.size() < count) {
    resizeDiscarding(rec_, count);
    resizeDiscarding(corners_, count);
  }
  resizeDiscarding(v, 3 * count);
  if (bad_.size() < count + 3) {            // a cavity holds at most every triangle
    resizeDiscarding(bad_, count + 3);      // then the star's slots and the first again
    resizeDiscarding(boundary_, count + 3); // then the first edge again
    resizeDiscarding(stack_, 2 * count + 3);
  }
}

void LocalDelaunay::outsideBox(const Point2& q, double cx, double cy, double d)
{
  // Not expected (points lie within the slack of their cells); sound anyway: the
  // tight bound no longer applies, the wide one only while q is inside its box.
  const double inf = std::numeric_limits<double>::infinity();
  incircle_tight_bound_ = incircle_wide_bound_;
  if (!(q.x >= cx - 10.0 * d && q.x <= cx + 10.0 * d && q.y >= cy - 10.0 * d &&
        q.y <= cy + 10.0 * d))
    orient_bound_ = incircle_wide_bound_ = incircle_tight_bound_ = inf;
}

void LocalDelaunay::insertPoints(std::size_t count)
{
  // One loop over the points (not a call per point): the arrays' addresses, the
  // bounds, the walk's start and the triangle count stay in registers or the frame.
  const Point2* const P = p.data();
  std::int32_t* V = v.data();
  Record* R = rec_.data();
  Corners* C = corners_.data();
  std::uint32_t* bad = bad_.data();
  Edge* boundary = boundary_.data();
  std::uint32_t* stack = stack_.data();
  const double orient_bound = orient_bound_;
  const double bounds[2] = {incircle_wide_bound_, incircle_tight_bound_}; // by real
  std::uint32_t last = static_cast<std::uint32_t>(last_);
  std::size_t triangles = triangles_;
  for (std::size_t point = 3; point < count; ++point) {
    const auto k = static_cast<std::int32_t>(point);
    const Point2 q = P[k];
    const Point2& next = P[point + 1 < count ? point + 1 : point];
    // Visibility walk from the star triangle the last insertion chose (it ends in a
    // Delaunay mesh); the edge it came in by is not tested again. (A branch-free walk,
    // all three sides tested, was slower: the exits are well predicted.)
    std::uint32_t t = last;
    std::uint32_t entry = 3;
    for (;;) {
      const Record& r = R[t];
      const Corners& c = C[t];
      std::uint32_t e;
      if (entry != 0 &&
          orient2dInBox(c.p[0], c.p[1], q, orient_bound) == Sign::NEGATIVE)
        e = 0;
      else if (entry != 1 &&
               orient2dInBox(c.p[1], r.apex, q, orient_bound) == Sign::NEGATIVE)
        e = 1;
      else if (entry != 2 &&
               orient2dInBox(r.apex, c.p[0], q, orient_bound) == Sign::NEGATIVE)
        e = 2;
      else
        break;
      t = twinTriangle(r.adj[e]);
      entry = twinEdge(r.adj[e]);
    }
    // Cavity: the triangles whose perturbed circumcircle holds q, depth first from t.
    // It is a disk with every vertex on its boundary (its triangles' adjacency is a
    // tree), so no triangle is reached twice as bad and no marks are needed; entering
    // each bad triangle by one edge and taking its other two in counter-clockwise order
    // lists the boundary edges in counter-clockwise order around q: a closed chain,
    // edge j from boundary[j].first to boundary[j + 1].first. A triangle's last vertex
    // is the point whose insertion made it (the first super triangle, the only
    // exception, is never tested: the first cavity starts there), so `real` picks the
    // bound.
    std::size_t top = 0, bad_count = 0, boundary_count = 0;
    bad[bad_count++] = t;
    stack[top++] = 16 * t + 2;
    stack[top++] = 16 * t + 1;
    std::uint32_t h = 16 * t;
    for (;;) {
      const std::int32_t o = twinSlot(R, h);
      if (o >= 0) {
        const auto uo = static_cast<std::uint32_t>(o);
        const Record& n = recordOf(R, uo);
        const double det = incircleFromCoefficients(n.k, n.apex, q);
        const double bound = bounds[n.real]; // a load, no branch
        if (det > bound || (!(-det > bound) &&
                            incirclePerturbedOutOfLine(C[twinTriangle(o)].p[0],
                                                       C[twinTriangle(o)].p[1], n.apex,
                                                       q) == Sign::POSITIVE)) {
          bad[bad_count++] = twinTriangle(o);
          // The edges before e (taken later) and after e (taken now): (e + 2) % 3 and
          // (e + 1) % 3 read from 2-bit tables, no branch on e.
          const std::uint32_t e = twinEdge(o), base = uo - e;
          stack[top++] = base + ((0x12u >> (2 * e)) & 3u);
          h = base + ((0x09u >> (2 * e)) & 3u);
          continue;
        }
      }
      boundary[boundary_count++] = {V[3 * (h >> 4) + (h & 15u)], o};
      if (top == 0)
        break;
      h = stack[--top];
    }
    // The star of q over the chain: the cavity's slots, then new ones (a disk of m
    // boundary edges holds m - 2 triangles: two new slots), listed after the cavity's.
    // Each record is written once, its neighbours in the star known from the slots.
    boundary[boundary_count] = boundary[0]; // the chain closed
    const std::size_t first_new = triangles;
    triangles += 2;                 // boundary_count - bad_count
    if (3 * triangles > v.size()) { // only if the 1 + 2n count were wrong
      v.resize(6 * triangles);
      rec_.resize(2 * triangles);
      corners_.resize(2 * triangles);
      V = v.data();
      R = rec_.data();
      C = corners_.data();
    }
    // Two new slots (boundary_count is bad_count + 2), written as two: a loop over
    // bad_count .. boundary_count compiled to a vectorised loop with its checks.
    bad[bad_count] = static_cast<std::uint32_t>(first_new);
    bad[bad_count + 1] = static_cast<std::uint32_t>(first_new + 1);
    bad[boundary_count] = bad[0];
    std::uint32_t previous = bad[boundary_count - 1];
    // The next walk's start: the star triangle whose wedge at q holds the next point
    // (left of or on the ray from q through its first corner, right of the one through
    // its second), the last one if none does (the next point is q's neighbour in the
    // insertion order, mostly within a cell or two). Rounding only changes the start.
    // A chain vertex's point, offset from q and side of the ray to the next point serve
    // the two star triangles that share it (computed once, carried to the next edge).
    std::uint32_t start = previous;
    // What differs by target is a chain vertex (its point, offset from q, lift and side
    // of the ray to the next point) and how a star triangle's apex, coefficients and
    // corners are written from two of them; the walk around the chain is one loop.
#if defined(__SSE2__)
    // The same operations in (x, y) lanes, bit for bit: a vertex's offset o = p - q,
    // its lift ox^2 + oy^2 broadcast, o turned to (oy, -ox) (negation is exact), and
    // the side of the ray to the next point ox ny - oy nx. With u, w the offsets of a
    // star triangle's first two corners, lu (wy, -wx) - lw (uy, -ux) is (Bx, By): lane
    // 1 is (-lu wx) - (-lw ux), which is lw ux - lu wx (x - y is x + (-y) in IEEE
    // arithmetic, and the sum commutes); A = ux wy + uy (-wx), which is ux wy - uy wx:
    // predicates.h's incircleCoefficients(u, w).
    const __m128d qv = _mm_loadu_pd(&q.x);
    const __m128d nd = _mm_sub_pd(_mm_loadu_pd(&next.x), qv);
    const __m128d nyx = _mm_shuffle_pd(nd, nd, 1); // (ny, nx)
    const __m128d negate_high = _mm_set_pd(-0.0, 0.0);
    struct ChainVertex {
      __m128d p, o, turned, lift;
      std::uint32_t left, real; // real: a point, not a super triangle corner
    };
    const auto chainVertex = [&](std::int32_t id) {
      ChainVertex cv;
      cv.real = static_cast<std::uint32_t>(id >= 3);
      cv.p = _mm_loadu_pd(&P[id].x);
      const __m128d o = cv.o = _mm_sub_pd(cv.p, qv);
      const __m128d sq = _mm_mul_pd(o, o);
      const __m128d lift = _mm_add_sd(sq, _mm_unpackhi_pd(sq, sq));
      cv.lift = _mm_unpacklo_pd(lift, lift);
      cv.turned = _mm_xor_pd(_mm_shuffle_pd(o, o, 1), negate_high);
      const __m128d cross = _mm_mul_pd(o, nyx); // (ox ny, oy nx)
      cv.left = static_cast<std::uint32_t>(_mm_comige_sd(
          _mm_sub_sd(cross, _mm_unpackhi_pd(cross, cross)), _mm_setzero_pd()));
      return cv;
    };
    const auto writeTriangle = [&](Record& r, Corners& c, const ChainVertex& va,
                                   const ChainVertex& vb) {
      _mm_storeu_pd(&r.apex.x, qv);
      _mm_store_pd(r.k.b, _mm_sub_pd(_mm_mul_pd(va.lift, vb.turned),
                                     _mm_mul_pd(vb.lift, va.turned)));
      const __m128d products = _mm_mul_pd(va.o, vb.turned); // (ux wy, uy (-wx))
      const __m128d a = _mm_add_sd(products, _mm_unpackhi_pd(products, products));
      _mm_store_pd(r.k.a, _mm_unpacklo_pd(a, a));
      _mm_storeu_pd(&c.p[0].x, va.p);
      _mm_storeu_pd(&c.p[1].x, vb.p);
    };
#else
    const double nx = next.x - q.x, ny = next.y - q.y;
    struct ChainVertex {
      Point2 p;
      CornerOffset o;
      std::uint32_t left, real; // real: a point, not a super triangle corner
    };
    const auto chainVertex = [&](std::int32_t id) {
      ChainVertex cv;
      cv.real = static_cast<std::uint32_t>(id >= 3);
      cv.p = P[id];
      cv.o = cornerOffset(cv.p, q);
      cv.left = static_cast<std::uint32_t>(cv.o.x * ny - cv.o.y * nx >= 0.0);
      return cv;
    };
    const auto writeTriangle = [&](Record& r, Corners& c, const ChainVertex& va,
                                   const ChainVertex& vb) {
      r.apex = q;
      r.k = incircleCoefficients(va.o, vb.o);
      c = {{va.p, vb.p}};
    };
#endif
    // Two star triangles a round: the chain vertex computed for one triangle's second
    // corner is the next one's first, kept in place instead of copied (the copies were
    // a fifth of the loop's instructions); the same operations in the same order.
    const auto starTriangle = [&](std::size_t j, const ChainVertex& va,
                                  ChainVertex& vb) {
      const std::uint32_t s = bad[j];
      const Edge& edge = boundary[j];
      const std::int32_t b = boundary[j + 1].first;
      V[3 * s] = edge.first;
      V[3 * s + 1] = b;
      V[3 * s + 2] = k;
      vb = chainVertex(b);
      Record& r = R[s];
      writeTriangle(r, C[s], va, vb);
      r.adj = {edge.second, static_cast<std::int32_t>(16 * bad[j + 1] + 2),
               static_cast<std::int32_t>(16 * previous + 1)};
      // In the wedge: left of or on the ray through pa, right of the one through pb.
      const std::uint32_t in_wedge = va.left & (vb.left ^ 1u);
      start ^= (start ^ s) & (0u - in_wedge); // s where in the wedge, without a branch
      if (edge.second >= 0)
        twinSlot(R, static_cast<std::uint32_t>(edge.second)) =
            static_cast<std::int32_t>(16 * s);
      // Stored last: beside the twins, GCC packed all four into one vector store
      // (movd and unpack instructions, more than four plain stores).
      r.real = static_cast<std::int32_t>(va.real & vb.real);
      previous = s;
    };
    ChainVertex even = chainVertex(boundary[0].first), odd;
    std::size_t j = 0;
    for (; j + 2 <= boundary_count; j += 2) {
      starTriangle(j, even, odd);
      starTriangle(j + 1, odd, even);
    }
    if (j < boundary_count)
      starTriangle(j, even, odd);
    last = start;
    if (bad_.size() <
        triangles + 3) { // the next cavity's arrays (as above: not expected)
      reserveTriangles(v.size() / 3);
      V = v.data();
      R = rec_.data();
      C = corners_.data();
      bad = bad_.data();
      boundary = boundary_.data();
      stack = stack_.data();
    }
  }
  last_ = static_cast<std::int32_t>(last);
  triangles_ = triangles;
}

} // namespace detail
} // namespace pcl_vts
