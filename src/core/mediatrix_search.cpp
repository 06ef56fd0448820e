#include <pcl_vts/core/error_bounds.h>
#include <pcl_vts/core/mediatrix_search.h>
#include <pcl_vts/core/predicates.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl_vts {
namespace {

// The edge rectangle is skipped (straight to widening) when larger than this.
constexpr std::size_t MAX_LOCAL_CELLS = 64;
// A best circle covering at most this many cells is scanned directly, no widening.
constexpr std::size_t MAX_DISK_CELLS = 256;
// The guess scans the cells within half a cell of the circumcentre of the equilateral
// apex, m + n / (2 sqrt 3): at most 2 x 2 cells.
constexpr double GUESS_CENTRE = 0.2887;
constexpr std::size_t GUESS_CELLS = 9;
// When those cells are empty (the apex's circle spans a void), the guess scans the
// cells within WIDE_GUESS cells of that centre instead, at most WIDE_CELLS of them: a
// guess's disk is certified directly (settleByGuess), without it the edge rectangle
// is scanned and then the disk's cells outside it.
constexpr double WIDE_GUESS = 2.5;
constexpr std::size_t WIDE_CELLS = 49;
// The guess's circle is settled directly when it covers at most this many cells (as
// many as settleInDiskCells scans): near voids the guess, when there is one, is
// mostly the apex, and its disk alone costs less than the edge rectangle and then
// the disk cells outside it.
constexpr std::size_t QUICK_CELLS = MAX_DISK_CELLS;
// settleAlongEdge scans directly at most this many cells of the disk's row spans.
constexpr std::size_t SPAN_CELLS = 2048;
// settleAlongEdge's first band reaches this many cells beyond the edge's ends.
constexpr std::uint32_t EXTEND_CELLS = 8;
// settleAlongEdge skips an edge away from the border longer than EXTEND_CELLS /
// LONG_INTERIOR cells: on clustered input that is an edge across a void, whose band
// rarely settles it (its circle is a void's size) and whose cost widen pays anyway.
constexpr double LONG_INTERIOR = 0.5;

// widen tests the points of a block of up to 2^DIRECT_LEVEL cells a side directly (one
// range per cell row) when it holds at most DIRECT_POINTS points and no crowded cell:
// cheaper than refining it through the heap, which big circles (edges across voids)
// do for every occupied block their boundary crosses.
constexpr std::uint32_t DIRECT_LEVEL = 4;
constexpr std::uint32_t DIRECT_POINTS = 192;

bool heapGreater(double a, double b)
{
  return a > b;
}

/// Circle centres through a and b are m + t n (n the left normal, |n| = |ab|); a left
/// point p gives t(p) = (|p - m|^2 - |ab|^2 / 4) / (2 (p - m).n), and the Delaunay
/// apex has the smallest t. Compared as fractions: no division. A guess, not a proof:
/// the search certifies whatever it returns.
struct SmallestCentre {
  SmallestCentre(const Point2& pa, const Point2& pb)
      : mx(0.5 * (pa.x + pb.x))
      , my(0.5 * (pa.y + pb.y))
      , nx(pa.y - pb.y)
      , ny(pb.x - pa.x)
      , quarter(0.25 * (nx * nx + ny * ny))
  {}
  /// Takes the points [begin, end) of the grid other than the edge's ends a and b.
  void scan(const Point2* points, std::uint32_t begin, std::uint32_t end, VertexId a,
            VertexId b)
  {
    for (std::uint32_t k = begin; k < end; ++k) {
      const double dx = points[k].x - mx, dy = points[k].y - my;
      const double den = dx * nx + dy * ny;
      const double num = dx * dx + dy * dy - quarter;
      if (den > 0.0 && num * best_den < best_num * den && k != a && k != b) {
        best = k;
        best_num = num;
        best_den = den;
      }
    }
  }
  double mx, my, nx, ny, quarter;
  VertexId best = INVALID_ID;
  double best_num = 1.0, best_den = 0.0; // t = +infinity
};

} // namespace

MediatrixSearch::MediatrixSearch(const CellGrid& grid, const CellPyramid& pyramid,
                                 const CellSubdivision& subdivision)
    : grid_(grid)
    , pyramid_(pyramid)
    , sub_(subdivision)
{}

VertexId MediatrixSearch::guessThirdPoint(const Query& q) const
{
  SmallestCentre centre(q.pa, q.pb);
  const double gx = centre.mx + GUESS_CENTRE * centre.nx;
  const double gy = centre.my + GUESS_CENTRE * centre.ny;
  for (const double cells : {0.5, WIDE_GUESS}) {
    const double reach = cells * grid_.cell_size;
    const Window w{grid_.column(gx - reach), grid_.column(gx + reach),
                   grid_.row(gy - reach), grid_.row(gy + reach)};
    if (cellCount(w) > (cells < 1.0 ? GUESS_CELLS : WIDE_CELLS) ||
        windowHasCrowdedCell(w))
      return INVALID_ID;
    for (std::uint32_t j = w.j0; j <= w.j1; ++j) {
      const CellId row = grid_.cellId(0, j);
      centre.scan(grid_.points.data(), grid_.start(row + w.i0),
                  grid_.start(row + w.i1 + 1), q.a, q.b);
    }
    if (centre.best != INVALID_ID)
      break;
  }
  return centre.best;
}

void MediatrixSearch::testRow(std::uint32_t j, std::uint32_t i0, std::uint32_t i1,
                              const Window& skip, Query& q)
{
  const CellId row = grid_.cellId(0, j);
  const auto cells = [&](std::uint32_t first, std::uint32_t last) {
    testRange(grid_.start(row + first), grid_.start(row + last + 1), q);
    stats_.cells_visited += last - first;
  };
  if (j < skip.j0 || j > skip.j1 || skip.i1 < i0 || skip.i0 > i1) {
    cells(i0, i1);
    return;
  }
  if (skip.i0 > i0)
    cells(i0, skip.i0 - 1);
  if (skip.i1 < i1)
    cells(skip.i1 + 1, i1);
}

void MediatrixSearch::testPoints(std::uint32_t begin, std::uint32_t end, Query& q)
{
  stats_.points_tested += end - begin;
  const Point2* points = grid_.points.data();
  for (std::uint32_t k = begin; k < end; ++k) {
    const Point2& p = points[k];
    // Outside the safe disk means strictly outside the exact circle: not a candidate.
    const double dx = p.x - q.reject_cx, dy = p.y - q.reject_cy;
    if (dx * dx + dy * dy > q.reject_r2)
      continue;
    if (k == q.a || k == q.b || k == q.best ||
        orient2d(q.pa, q.pb, p) != Sign::POSITIVE)
      continue;
    if (q.best != INVALID_ID &&
        incirclePerturbed(q.pa, q.pb, grid_.points[q.best], p) != Sign::POSITIVE)
      continue;
    // Each new best's safe disk at once: it holds the open side of every better
    // circle, so the points after it outside it cost one distance test (computed once
    // a phase instead, it left a phase's first cells, a whole edge rectangle when there
    // was no guess, to the orientation and in-circle tests).
    q.best = k;
    q.disk_fresh = false;
    q.refreshDisk(grid_);
  }
}

void MediatrixSearch::Query::refreshDisk(const CellGrid& grid)
{
  if (best != INVALID_ID && !disk_fresh) {
    disk = safeCircumdisk(pa, pb, grid.points[best]);
    disk_fresh = true;
    if (disk.valid) {
      reject_cx = disk.cx;
      reject_cy = disk.cy;
      reject_r2 = disk.radius * disk.radius * (1.0 + SQUARED_DISTANCE_SLACK);
    }
  }
}

MediatrixSearch::Window MediatrixSearch::diskCells(const SafeDisk& disk) const
{
  // Monotone cell lookup: every point of the disk lies in a cell of this range.
  const double reach = disk.radius + grid_.slack;
  return {grid_.column(disk.cx - reach), grid_.column(disk.cx + reach),
          grid_.row(disk.cy - reach), grid_.row(disk.cy + reach)};
}

bool MediatrixSearch::windowHasCrowdedCell(const Window& w) const
{
  if (!sub_.any())
    return false;
  for (std::uint32_t j = w.j0; j <= w.j1; ++j)
    for (std::uint32_t i = w.i0; i <= w.i1; ++i)
      if (sub_.root[grid_.cellId(i, j)] != INVALID_ID)
        return true;
  return false;
}

BlockRect MediatrixSearch::blockBounds(const Block& b) const
{
  if (b.node != INVALID_ID) {
    const SubCell& n = sub_.nodes[b.node];
    return {n.x0 - grid_.slack, n.y0 - grid_.slack, n.x1 + grid_.slack,
            n.y1 + grid_.slack};
  }
  return blockRect(grid_, b.level, b.i, b.j);
}

void MediatrixSearch::widen(Query& q, const Window& done)
{
  const double mx = 0.5 * (q.pa.x + q.pb.x), my = 0.5 * (q.pa.y + q.pb.y);
  const auto cmp = [](const Block& l, const Block& r) {
    return heapGreater(l.key, r.key);
  };
  const auto outsideDisk = [&](const BlockRect& r) {
    const double r2 = q.disk.radius * q.disk.radius * (1.0 + SQUARED_DISTANCE_SLACK);
    return q.best != INVALID_ID && q.disk.valid &&
           r.squaredDistance(q.disk.cx, q.disk.cy) > r2;
  };
  // A block enters the heap unless it lies outside the current safe disk (no point of
  // it can beat the best) or in the closed right half-plane of a->b (certified bound):
  // an edge across a void has a large circle, and most blocks met on its way are
  // dropped here rather than pushed and popped.
  const auto push = [&](Block child) {
    const BlockRect r = blockBounds(child);
    if (outsideDisk(r) || (!mayLieLeft(q.pa, q.pb, {r.x0, r.y0}) &&
                           !mayLieLeft(q.pa, q.pb, {r.x1, r.y0}) &&
                           !mayLieLeft(q.pa, q.pb, {r.x0, r.y1}) &&
                           !mayLieLeft(q.pa, q.pb, {r.x1, r.y1})))
      return;
    child.key = r.squaredDistance(mx, my);
    heap_.push_back(child);
    std::push_heap(heap_.begin(), heap_.end(), cmp);
  };

  heap_.clear();
  q.refreshDisk(grid_);
  const auto top = static_cast<std::uint32_t>(pyramid_.levels.size() - 1);
  push({0.0, top, 0, 0, INVALID_ID});
  VertexId reach_of = INVALID_ID; // the best whose reach2 is known
  double reach2 = 0.0;
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), cmp);
    const Block blk = heap_.back();
    heap_.pop_back();

    q.refreshDisk(grid_);
    if (q.best != INVALID_ID && q.disk.valid) {
      // Blocks come out nearest the edge midpoint first: once one lies beyond every
      // point of the disk, so do all the rest.
      if (reach_of != q.best) {
        const double reach = std::hypot(q.disk.cx - mx, q.disk.cy - my) + q.disk.radius;
        reach2 = reach * reach * (1.0 + SQUARED_DISTANCE_SLACK);
        reach_of = q.best;
      }
      if (blk.key > reach2)
        break;
      // The disk may have shrunk since the block was pushed.
      if (outsideDisk(blockBounds(blk)))
        continue;
    }

    if (blk.node != INVALID_ID) { // inside a crowded cell
      const SubCell& n = sub_.nodes[blk.node];
      if (n.first_child == INVALID_ID)
        testRange(n.begin, n.end, q);
      else
        for (std::uint32_t c = n.first_child; c < n.first_child + 4; ++c)
          if (sub_.nodes[c].end > sub_.nodes[c].begin)
            push({0.0, 0, 0, 0, c});
      continue;
    }
    if (blk.level == 0) {
      const CellId cell = grid_.cellId(blk.i, blk.j);
      if (sub_.any() && sub_.root[cell] != INVALID_ID)
        push({0.0, 0, blk.i, blk.j, sub_.root[cell]});
      else if (!done.contains(blk.i, blk.j))
        testCell(cell, q);
      continue;
    }
    if (blk.level <= DIRECT_LEVEL && testBlockDirectly(blk, q))
      continue;
    forEachOccupiedChild(pyramid_, blk.level, blk.i, blk.j,
                         [&](std::uint32_t ci, std::uint32_t cj) {
                           push({0.0, blk.level - 1, ci, cj, INVALID_ID});
                         });
  }
}

bool MediatrixSearch::testBlockDirectly(const Block& blk, Query& q)
{
  const std::uint32_t span = 1u << blk.level;
  const std::uint32_t i0 = blk.i * span, j0 = blk.j * span;
  const std::uint32_t i1 = std::min(i0 + span, grid_.nx) - 1;
  const std::uint32_t j1 = std::min(j0 + span, grid_.ny) - 1;
  if (windowHasCrowdedCell({i0, i1, j0, j1}))
    return false;
  std::uint32_t points = 0;
  for (std::uint32_t j = j0; j <= j1; ++j) {
    const CellId row = grid_.cellId(0, j);
    points += grid_.start(row + i1 + 1) - grid_.start(row + i0);
  }
  if (points > DIRECT_POINTS)
    return false;
  for (std::uint32_t j = j0; j <= j1; ++j) {
    const CellId row = grid_.cellId(0, j);
    testRange(grid_.start(row + i0), grid_.start(row + i1 + 1), q);
    stats_.cells_visited += i1 - i0;
  }
  return true;
}

bool MediatrixSearch::settleByGuess(Query& q)
{
  // A floating-point guess of the apex, certified exactly on the cells of its safe
  // disk. Any valid left candidate may start the exact tests; a good one makes the
  // disk tight, so nearly every other point is rejected by one distance test.
  const VertexId guess = guessThirdPoint(q);
  if (guess == INVALID_ID ||
      orient2d(q.pa, q.pb, grid_.points[guess]) != Sign::POSITIVE)
    return false;
  q.best = guess;
  q.refreshDisk(grid_);
  if (!q.disk.valid)
    return false;
  const Window r = diskCells(q.disk);
  if (cellCount(r) > QUICK_CELLS || windowHasCrowdedCell(r))
    return false;
  // The cells of a window row are contiguous in the grid: one range per row.
  for (std::uint32_t j = r.j0; j <= r.j1; ++j) {
    const CellId row = grid_.cellId(0, j);
    testRange(grid_.start(row + r.i0), grid_.start(row + r.i1 + 1), q);
    stats_.cells_visited += r.i1 - r.i0;
  }
  return true;
}

MediatrixSearch::Window MediatrixSearch::edgeRectangle(const Query& q) const
{
  const std::uint32_t ia = grid_.column(q.pa.x), ib = grid_.column(q.pb.x);
  const std::uint32_t ja = grid_.row(q.pa.y), jb = grid_.row(q.pb.y);
  const Window w{std::min(ia, ib) > 0 ? std::min(ia, ib) - 1 : 0,
                 std::min(std::max(ia, ib) + 1, grid_.nx - 1),
                 std::min(ja, jb) > 0 ? std::min(ja, jb) - 1 : 0,
                 std::min(std::max(ja, jb) + 1, grid_.ny - 1)};
  if (cellCount(w) > MAX_LOCAL_CELLS || windowHasCrowdedCell(w))
    return Window{1, 0, 1, 0};
  return w;
}

bool MediatrixSearch::settleInRectangle(Query& q, const Window& w)
{
  // Nearest circumcentre first: the guess if any, else the cell where the mediatrix
  // enters the open side (half an edge length from the midpoint).
  std::uint32_t fi = w.i1 + 1, fj = w.j1 + 1; // no foot cell tested yet
  if (q.best == INVALID_ID) {
    const double fx = 0.5 * (q.pa.x + q.pb.x) - 0.5 * (q.pb.y - q.pa.y);
    const double fy = 0.5 * (q.pa.y + q.pb.y) + 0.5 * (q.pb.x - q.pa.x);
    fi = std::clamp(grid_.column(fx), w.i0, w.i1);
    fj = std::clamp(grid_.row(fy), w.j0, w.j1);
    testCell(grid_.cellId(fi, fj), q);
  }
  const Window foot{fi, fi, fj, fj};
  q.refreshDisk(grid_);
  // Usually the apex is known now and its circle spans only a few of the window's
  // cells: visit just those. Later candidates lie inside this circle and so do their
  // circles' open sides, so the cells stay sufficient.
  if (q.best != INVALID_ID && q.disk.valid) {
    const Window r = diskCells(q.disk);
    if (r.i0 >= w.i0 && r.i1 <= w.i1 && r.j0 >= w.j0 && r.j1 <= w.j1) {
      for (std::uint32_t j = r.j0; j <= r.j1; ++j)
        testRow(j, r.i0, r.i1, foot, q);
      return true;
    }
  }
  for (std::uint32_t j = w.j0; j <= w.j1; ++j)
    testRow(j, w.i0, w.i1, foot, q);
  return false;
}

bool MediatrixSearch::settleInDiskCells(Query& q, const Window& done)
{
  q.refreshDisk(grid_);
  if (q.best == INVALID_ID || !q.disk.valid)
    return false;
  // The circle spills out of the rectangle: its cells, when few, still cover it.
  const Window r = diskCells(q.disk);
  if (cellCount(r) > MAX_DISK_CELLS || windowHasCrowdedCell(r))
    return false;
  for (std::uint32_t j = r.j0; j <= r.j1; ++j)
    testRow(j, r.i0, r.i1, done, q);
  return true;
}

bool MediatrixSearch::settleAlongEdge(Query& q)
{
  // The band along the edge and EXTEND_CELLS beyond its ends first; then, near the
  // grid's border, four edge lengths beyond them (flat apexes along the hull often lie
  // far beyond the segment).
  if (sub_.any())
    return false;
  const double near = static_cast<double>(EXTEND_CELLS) * grid_.cell_size /
                      std::sqrt((q.pb.x - q.pa.x) * (q.pb.x - q.pa.x) +
                                (q.pb.y - q.pa.y) * (q.pb.y - q.pa.y));
  const auto inside = [&](const Point2& p) {
    const std::uint32_t i = grid_.column(p.x), j = grid_.row(p.y);
    return i >= EXTEND_CELLS && j >= EXTEND_CELLS && i + EXTEND_CELLS < grid_.nx &&
           j + EXTEND_CELLS < grid_.ny;
  };
  const bool interior = inside(q.pa) && inside(q.pb);
  if (interior && near < LONG_INTERIOR)
    return false;
  if (settleInBand(q, near))
    return true;
  // The long band only near the grid's border, where the flat hull triangles are
  // (inside, a failed near band is mostly an edge across a void: nothing to find).
  if (interior)
    return false;
  return settleInBand(q, near + 4.0);
}

bool MediatrixSearch::settleInBand(Query& q, double e)
{
  // The band: per row j, the cells within one cell of the part of the line through
  // a and b from e edge lengths before a to e after b whose y lies within a cell of
  // rows j - 1 .. j + 1. A point within c - 2 slack of the segment lies in the band
  // (its nearest segment point z is in the rows around its own, and its column within
  // one of z's).
  const double c = grid_.cell_size;
  const double ex = q.pb.x - q.pa.x, ey = q.pb.y - q.pa.y;
  if (!(e < 64.0))
    return false;
  const double ya = q.pa.y - e * ey, yb = q.pb.y + e * ey;
  const std::uint32_t jlo = grid_.row(std::min(ya, yb) - c);
  const std::uint32_t jhi = grid_.row(std::max(ya, yb) + c);
  if ((static_cast<std::size_t>(jhi - jlo) + 1) * 3 > SPAN_CELLS)
    return false;
  band_.clear();
  std::size_t cells = 0;
  for (std::uint32_t j = jlo; j <= jhi; ++j) {
    const double ylo = grid_.origin_y + (j - 1.0) * c;
    const double yhi = grid_.origin_y + (j + 2.0) * c;
    double s0 = -e, s1 = 1.0 + e;
    if (ey != 0.0) {
      const double u = (ylo - q.pa.y) / ey, w = (yhi - q.pa.y) / ey;
      s0 = std::max(s0, std::min(u, w) - 1e-9);
      s1 = std::min(s1, std::max(u, w) + 1e-9);
      if (s0 > s1)
        continue;
    } else if (q.pa.y < ylo || q.pa.y > yhi) {
      continue;
    }
    const double xa = q.pa.x + s0 * ex, xb = q.pa.x + s1 * ex;
    const Window span{grid_.column(std::min(xa, xb) - c),
                      grid_.column(std::max(xa, xb) + c), j, j};
    cells += span.i1 - span.i0 + 1;
    if (cells > SPAN_CELLS)
      return false;
    band_.push_back(span);
  }
  // The guess: the smallest circumcentre offset (as in guessThirdPoint) in the band.
  SmallestCentre centre(q.pa, q.pb);
  for (const Window& span : band_) {
    const CellId row = grid_.cellId(0, span.j0);
    centre.scan(grid_.points.data(), grid_.start(row + span.i0),
                grid_.start(row + span.i1 + 1), q.a, q.b);
  }
  const VertexId guess = centre.best;
  if (guess != INVALID_ID && guess != q.best &&
      orient2d(q.pa, q.pb, grid_.points[guess]) == Sign::POSITIVE &&
      (q.best == INVALID_ID ||
       incirclePerturbed(q.pa, q.pb, grid_.points[q.best], grid_.points[guess]) ==
           Sign::POSITIVE)) {
    q.best = guess;
    q.disk_fresh = false;
  }
  if (q.best == INVALID_ID)
    return false;
  q.refreshDisk(grid_);
  // When the angle at the apex p is obtuse (certified), the circle's centre is right
  // of a->b and the part left of it is the minor segment: every better candidate lies
  // in it, within its height s of the segment, and s <= d / (4 ta tb) (d: p's distance
  // to the line, ta and tb = 1 - ta: where p projects along a->b and back from b, each
  // computed from its own end so that both keep their relative accuracy). When that
  // is under a cell the band holds it. The margins (relative 1e-6, absolute 1e-9 of
  // the edge and the grid slack) are far beyond the rounding of these few operations.
  const auto minorSegmentInBand = [&] {
    const Point2 p = grid_.points[q.best];
    const double apx = p.x - q.pa.x, apy = p.y - q.pa.y;
    const double bpx = p.x - q.pb.x, bpy = p.y - q.pb.y;
    const double dot = apx * bpx + apy * bpy;
    const double l2 = ex * ex + ey * ey;
    if (!(dot < -1e-14 * (std::fabs(apx * bpx) + std::fabs(apy * bpy))) ||
        !(l2 > 1e-12 * c * c))
      return false;
    const double ta = (ex * apx + ey * apy) / l2;
    const double tb = -(ex * bpx + ey * bpy) / l2;
    const double cross = std::fabs(ex * apy - ey * apx) +
                         1e-14 * (std::fabs(ex * apy) + std::fabs(ey * apx));
    const double length = std::sqrt(l2);
    const double height = cross / length / (4.0 * ta * tb);
    const double reach = height * (1.0 + 1e-6) + 1e-9 * length + 4.0 * grid_.slack;
    return ta > 0.0 && tb > 0.0 && reach + 2.0 * grid_.slack <= c;
  };
  const auto testBand = [&] {
    for (const Window& span : band_) {
      const CellId row = grid_.cellId(0, span.j0);
      testRange(grid_.start(row + span.i0), grid_.start(row + span.i1 + 1), q);
      stats_.cells_visited += span.i1 - span.i0;
    }
  };
  if (!q.disk.valid) { // too flat for a safe disk: the band or nothing
    if (!minorSegmentInBand())
      return false;
    testBand();
    return true;
  }
  {
    // A thin minor segment is also certified on the band when the band has fewer
    // cells than the disk's bounding box (a flat triangle's disk spans the grid).
    const SafeDisk& d = q.disk;
    const double reach = d.radius + grid_.slack;
    const std::size_t box =
        (static_cast<std::size_t>(grid_.row(d.cy + reach) - grid_.row(d.cy - reach)) +
         1) *
        (static_cast<std::size_t>(grid_.column(d.cx + reach) -
                                  grid_.column(d.cx - reach)) +
         1);
    if (cells < box && minorSegmentInBand()) {
      testBand();
      return true;
    }
  }
  // Certify on the safe disk: a point of it in row j has its y in the row's band
  // [y0, y1] (the row widened by the slack), so its x within the disk's chord over the
  // band (half-width from the band's y nearest the centre), so its column within that
  // chord's columns widened by the slack. The squares carry the usual relative slack,
  // far beyond their rounding.
  const SafeDisk& d = q.disk;
  const double r2 = d.radius * d.radius * (1.0 + SQUARED_DISTANCE_SLACK);
  const std::uint32_t r0 = grid_.row(d.cy - d.radius - grid_.slack);
  const std::uint32_t r1 = grid_.row(d.cy + d.radius + grid_.slack);
  spans_.clear();
  cells = 0;
  for (std::uint32_t j = r0; j <= r1; ++j) {
    const BlockRect rect = blockRect(grid_, 0, 0, j);
    const double gap = std::max({0.0, rect.y0 - d.cy, d.cy - rect.y1});
    const double h2 = r2 - gap * gap * (1.0 - SQUARED_DISTANCE_SLACK);
    if (h2 < 0.0)
      continue;
    const double half = std::sqrt(h2) * (1.0 + SQUARED_DISTANCE_SLACK) + grid_.slack;
    const Window span{grid_.column(d.cx - half), grid_.column(d.cx + half), j, j};
    cells += span.i1 - span.i0 + 1;
    if (cells > SPAN_CELLS)
      return false;
    spans_.push_back(span);
  }
  for (const Window& span : spans_) {
    const CellId row = grid_.cellId(0, span.j0);
    testRange(grid_.start(row + span.i0), grid_.start(row + span.i1 + 1), q);
    stats_.cells_visited += span.i1 - span.i0;
  }
  return true;
}

VertexId MediatrixSearch::findThirdPoint(VertexId a, VertexId b)
{
  Query q;
  q.a = a;
  q.b = b;
  q.pa = grid_.points[a];
  q.pb = grid_.points[b];
  // Quick guess; else the rectangle supported by the edge (the cells spanned by a and
  // b, dilated by one; empty when too large or crowded), then the cells of the best
  // circle found; else widen over the pyramid.
  if (settleByGuess(q)) {
    ++stats_.local;
    return q.best;
  }
  const Window w = edgeRectangle(q);
  if (w.i0 <= w.i1 && (settleInRectangle(q, w) || settleInDiskCells(q, w))) {
    ++stats_.local;
    return q.best;
  }
  if (settleAlongEdge(q)) {
    ++stats_.local;
    return q.best;
  }
  ++stats_.widened;
  widen(q, w);
  return q.best;
}

} // namespace pcl_vts
