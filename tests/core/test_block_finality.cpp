// The cache blocks keep a triangle only when its circumdisk lies inside the loaded
// window (src/core/local_delaunay.h): a wrong "final" would put a triangle into the
// mesh that an unloaded point invalidates, and the oracle tests would only notice if
// some input put a point there. So the two finality tests are checked here directly,
// against the exact circumcircle (CGAL, exact constructions; finalTriangle is the
// tiles' boundCircumdisk of error_bounds.h too): sound on random,
// flat and near-touching triangles at small and UTM magnitudes, and not vacuous.
#include "../../src/core/local_delaunay.h"

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/grid_stage.h>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace {

using pcl_vts::Point2;
using pcl_vts::detail::GridBox;
using pcl_vts::detail::LocalDelaunay;
using Exact = CGAL::Exact_predicates_exact_constructions_kernel;

struct Box {
  double x_lo, x_hi, y_lo, y_hi;
};

/// forEachFinal's margin: 1e-14 of the window's coordinates (its loaded points lie
/// within a cell of it, and the cell is a 32nd of the window here).
double marginOf(const Box& w)
{
  return 1e-14 *
         (std::max(std::fabs(w.x_lo), std::fabs(w.x_hi)) +
          std::max(std::fabs(w.y_lo), std::fabs(w.y_hi)) + 4 * (w.x_hi - w.x_lo) / 32);
}

/// The exact circumdisk lies strictly inside the box (false for collinear corners).
bool diskInside(const Point2& a, const Point2& b, const Point2& c, const Box& w)
{
  const Exact::Point_2 p(a.x, a.y), q(b.x, b.y), r(c.x, c.y);
  if (CGAL::collinear(p, q, r))
    return false;
  const Exact::Point_2 m = CGAL::circumcenter(p, q, r);
  const Exact::FT r2 = CGAL::squared_distance(m, p);
  const auto inside = [&r2](const Exact::FT& gap) { return gap > 0 && gap * gap > r2; };
  return inside(m.x() - w.x_lo) && inside(w.x_hi - m.x()) && inside(m.y() - w.y_lo) &&
         inside(w.y_hi - m.y());
}

struct Counts {
  int final_by_vertices = 0, final_triangle = 0, cases = 0;
};

/// Both tests on one triangle: whatever they accept must be final exactly.
void check(const Point2& a, const Point2& b, const Point2& c, const Box& w, Counts& n)
{
  ++n.cases;
  const bool by_vertices = LocalDelaunay::finalByVertices(a, b, c, w.x_lo, w.x_hi,
                                                          w.y_lo, w.y_hi, marginOf(w));
  const bool by_disk =
      LocalDelaunay::finalTriangle(a, b, c, w.x_lo, w.x_hi, w.y_lo, w.y_hi);
  n.final_by_vertices += by_vertices;
  n.final_triangle += by_disk;
  if (by_vertices || by_disk) {
    ASSERT_TRUE(diskInside(a, b, c, w))
        << std::hexfloat << "(" << a.x << ", " << a.y << ") (" << b.x << ", " << b.y
        << ") (" << c.x << ", " << c.y << ") window [" << w.x_lo << ", " << w.x_hi
        << "] x [" << w.y_lo << ", " << w.y_hi << "], by vertices " << by_vertices
        << ", by disk " << by_disk;
  }
}

/// Windows of 32 cells at three scales, near the origin and at UTM magnitudes.
std::vector<Box> windows()
{
  std::vector<Box> out;
  for (const double cell : {1e-3, 0.7, 250.0})
    for (const Point2 o : {Point2{0.0, 0.0}, Point2{-3.5, 2.25},
                           Point2{512345.67, 4123456.78}, Point2{-7.3e5, 9.9e6}})
      out.push_back({o.x, o.x + 32 * cell, o.y, o.y + 32 * cell});
  return out;
}

TEST(BlockFinality, RandomTrianglesAreFinalOnlyWhenTheirDiskIsInside)
{
  std::mt19937_64 rng(15);
  Counts n;
  for (const Box& w : windows()) {
    std::uniform_real_distribution<double> ux(w.x_lo, w.x_hi), uy(w.y_lo, w.y_hi);
    const double cell = (w.x_hi - w.x_lo) / 32;
    std::normal_distribution<double> near(0.0, 1.5 * cell);
    for (int k = 0; k < 4000; ++k) {
      // Small triangles (a terrain's) anywhere, and large ones.
      const Point2 a{ux(rng), uy(rng)};
      check(a, {a.x + near(rng), a.y + near(rng)}, {a.x + near(rng), a.y + near(rng)},
            w, n);
      check(a, {ux(rng), uy(rng)}, {ux(rng), uy(rng)}, w, n);
    }
  }
  // Not vacuous: most small triangles of a window are proven by the cheap test.
  EXPECT_GT(n.final_by_vertices, n.cases / 4);
  EXPECT_GE(n.final_triangle, n.final_by_vertices);
}

TEST(BlockFinality, NearlyFlatTrianglesAreSound)
{
  std::mt19937_64 rng(16);
  Counts n;
  for (const Box& w : windows()) {
    std::uniform_real_distribution<double> ux(w.x_lo, w.x_hi), uy(w.y_lo, w.y_hi);
    std::uniform_real_distribution<double> t(0.0, 1.0);
    std::uniform_int_distribution<int> ulps(-4, 4);
    for (int k = 0; k < 3000; ++k) {
      // c on segment ab (rounded), then nudged by a few units in the last place:
      // huge circumdisks that a careless bound would call small.
      const Point2 a{ux(rng), uy(rng)}, b{ux(rng), uy(rng)};
      const double s = t(rng);
      Point2 c{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)};
      for (int u = ulps(rng); u != 0; u += u > 0 ? -1 : 1)
        c.y = std::nextafter(c.y, u > 0 ? INFINITY : -INFINITY);
      check(a, b, c, w, n);
    }
  }
  EXPECT_GT(n.cases, 0);
}

TEST(BlockFinality, DisksTouchingTheWindowAreNotFinal)
{
  // Corners on a circle whose disk reaches a side of the window within a small gap,
  // either way: the tests may accept only disks truly inside.
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> angle(0.0, 2 * M_PI), unit(0.0, 1.0);
  Counts n;
  int inside_by_a_millionth = 0, accepted_of_those = 0;
  for (const Box& w : windows()) {
    const double width = w.x_hi - w.x_lo;
    for (int k = 0; k < 6000; ++k) {
      const double r = width * (0.02 + 0.2 * unit(rng));
      // Gaps of a millionth of the radius, of a billionth, and of a few units in the
      // last place of the coordinates (where only the rounding allowance decides).
      const double ulp =
          std::nextafter(std::max(std::fabs(w.x_hi), std::fabs(w.y_hi)) +
                             std::max(std::fabs(w.x_lo), std::fabs(w.y_lo)),
                         INFINITY) -
          (std::max(std::fabs(w.x_hi), std::fabs(w.y_hi)) +
           std::max(std::fabs(w.x_lo), std::fabs(w.y_lo)));
      const double scale = k % 3 == 0 ? 1e-6 * r : k % 3 == 1 ? 1e-9 * r : 16 * ulp;
      const double gap = scale * (2 * unit(rng) - 1);
      const int side = k % 4;
      const double along = w.y_lo + r + (width - 2 * r) * unit(rng);
      const double across_lo = w.x_lo + r + gap, across_hi = w.x_hi - r - gap;
      Point2 m = side == 0   ? Point2{across_lo, along}
                 : side == 1 ? Point2{across_hi, along}
                 : side == 2 ? Point2{along - w.y_lo + w.x_lo, w.y_lo + r + gap}
                             : Point2{along - w.y_lo + w.x_lo, w.y_hi - r - gap};
      Point2 p[3];
      for (Point2& q : p) {
        const double phi = angle(rng);
        q = {m.x + r * std::cos(phi), m.y + r * std::sin(phi)};
      }
      const int before = n.final_triangle;
      check(p[0], p[1], p[2], w, n);
      if (gap > 1e-7 * r && diskInside(p[0], p[1], p[2], w)) {
        ++inside_by_a_millionth;
        accepted_of_those += n.final_triangle > before;
      }
    }
  }
  // The allowance is a few 1e-7 of the radius: disks inside by more are mostly kept.
  EXPECT_GT(inside_by_a_millionth, 0);
  EXPECT_GT(accepted_of_those, inside_by_a_millionth / 2);
}

/// The exact circumdisk meets no point of the closed rectangle [x0, x1] x [y0, y1]
/// (true when it is empty).
bool diskMisses(const Exact::Point_2& m, const Exact::FT& r2, double x0, double x1,
                double y0, double y1)
{
  if (!(x0 <= x1 && y0 <= y1))
    return true;
  const Exact::FT cx = m.x() < x0 ? Exact::FT(x0) : m.x() > x1 ? Exact::FT(x1) : m.x();
  const Exact::FT cy = m.y() < y0 ? Exact::FT(y0) : m.y() > y1 ? Exact::FT(y1) : m.y();
  return CGAL::squared_distance(m, Exact::Point_2(cx, cy)) > r2;
}

TEST(BlockFinality, DisksOverTheGridOutsideTheWindowAreNotFinal)
{
  // Windows on a side or corner of the grid (infinite there), triangles near that
  // border, many flat ones along it (a hull's): finalInGrid may accept only disks
  // whose exact circle meets none of the grid's box outside the window, and does
  // accept some that finalTriangle refuses (those reaching out of the grid).
  std::mt19937_64 rng(18);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int cases = 0, accepted = 0, beyond_final_triangle = 0;
  for (const Box& b : windows()) {
    const double cell = (b.x_hi - b.x_lo) / 32;
    // The grid: 4 x 3 windows wide, the window at its lower left, lower middle or
    // left middle.
    for (int place = 0; place < 3; ++place) {
      const double shift_x = place == 1 ? 32 * cell : 0.0;
      const double shift_y = place == 2 ? 32 * cell : 0.0;
      const double gx_lo = b.x_lo - shift_x, gx_hi = gx_lo + 128 * cell;
      const double gy_lo = b.y_lo - shift_y, gy_hi = gy_lo + 96 * cell;
      const double inf = INFINITY;
      const Box w{place == 1 ? b.x_lo : -inf, b.x_hi, place == 2 ? b.y_lo : -inf,
                  b.y_hi};
      for (int k = 0; k < 3000; ++k) {
        // Corners near the grid's lower side (within a cell or two of it) or its left
        // side, some exactly on it, some a few ulps off a line.
        const bool bottom = place != 2 && (place == 1 || k % 2 == 0);
        Point2 p[3];
        for (Point2& q : p) {
          const double along = unit(rng) * 32 * cell;
          const double off = k % 5 == 0 ? 0.0 : unit(rng) * 2 * cell;
          q = bottom ? Point2{b.x_lo + along, gy_lo + off}
                     : Point2{gx_lo + off, b.y_lo + along};
        }
        if (k % 7 == 0)
          p[2].y = std::nextafter(p[2].y, INFINITY);
        ++cases;
        const bool in_grid =
            LocalDelaunay::finalInGrid(p[0], p[1], p[2], w.x_lo, w.x_hi, w.y_lo, w.y_hi,
                                       gx_lo, gx_hi, gy_lo, gy_hi);
        if (!in_grid)
          continue;
        ++accepted;
        beyond_final_triangle += !LocalDelaunay::finalTriangle(p[0], p[1], p[2], w.x_lo,
                                                               w.x_hi, w.y_lo, w.y_hi);
        const Exact::Point_2 e0(p[0].x, p[0].y), e1(p[1].x, p[1].y), e2(p[2].x, p[2].y);
        ASSERT_FALSE(CGAL::collinear(e0, e1, e2));
        const Exact::Point_2 m = CGAL::circumcenter(e0, e1, e2);
        const Exact::FT r2 = CGAL::squared_distance(m, e0);
        ASSERT_TRUE(diskMisses(m, r2, w.x_hi, gx_hi, gy_lo, gy_hi) &&
                    diskMisses(m, r2, gx_lo, w.x_lo, gy_lo, gy_hi) &&
                    diskMisses(m, r2, gx_lo, gx_hi, w.y_hi, gy_hi) &&
                    diskMisses(m, r2, gx_lo, gx_hi, gy_lo, w.y_lo))
            << std::hexfloat << "(" << p[0].x << ", " << p[0].y << ") (" << p[1].x
            << ", " << p[1].y << ") (" << p[2].x << ", " << p[2].y << ") place "
            << place;
      }
    }
  }
  // Not vacuous: some triangles pass, some of them only this way.
  EXPECT_GT(accepted, cases / 10);
  EXPECT_GT(beyond_final_triangle, 0);
}

} // namespace

TEST(BlockFinality, GridBoxOfPointsIsThePointsBoundingBox)
{
  // finalInGrid's box from the border rows and columns only (GridBox::ofPoints) must
  // be the least and greatest coordinates of all the grid's points, on grids from
  // the grid stage (compact cell starts, crowded cells) and buildCellGrid: uniform
  // and clustered points at UTM offsets and around zero, lattices with points on the
  // cells' sides, cell sizes that leave part of a cell past the last point.
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int grids = 0;
  for (int shape = 0; shape < 4; ++shape)
    for (const double x0 : {0.0, -3.7, 512345.25})
      for (const double cell : {0.0, 0.37, 1.0, 2.5}) {
        const std::size_t n = 3000 + 997 * static_cast<std::size_t>(shape);
        std::vector<double> xyz(3 * n);
        std::vector<Point2> pts(n);
        for (std::size_t k = 0; k < n; ++k) {
          double x = unit(rng) * 40.0, y = unit(rng) * 25.0;
          if (shape == 1) { // clustered: most points in a corner, a few far out
            x = k % 10 == 0 ? x : x * 0.05;
            y = k % 10 == 0 ? y : y * 0.05;
          } else if (shape == 2) { // a lattice, points on the cells' sides
            x = std::floor(x);
            y = std::floor(y) * 0.5;
          } else if (shape == 3) { // a thin band, many points per cell
            y *= 0.01;
          }
          pts[k] = {x0 + x, 0.5 * x0 + y};
          xyz[3 * k] = pts[k].x;
          xyz[3 * k + 1] = pts[k].y;
          xyz[3 * k + 2] = 0.0;
        }
        double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
        for (const Point2& p : pts) {
          x_lo = std::min(x_lo, p.x);
          x_hi = std::max(x_hi, p.x);
          y_lo = std::min(y_lo, p.y);
          y_hi = std::max(y_hi, p.y);
        }
        pcl_vts::GridStage stage;
        std::vector<pcl_vts::VertexId> map;
        pcl_vts::Diagnostics diag;
        ASSERT_TRUE(pcl_vts::buildGridStage(xyz.data(), n, cell,
                                            pcl_vts::DuplicateRule::LOWEST_Z, 1, stage,
                                            map, diag)
                        .ok());
        pcl_vts::CellGrid plain;
        std::vector<std::uint32_t> order;
        ASSERT_TRUE(pcl_vts::buildCellGrid(pts, cell, plain, order).ok());
        for (const pcl_vts::CellGrid* grid : {&stage.grid, &plain}) {
          const GridBox box = GridBox::ofPoints(*grid);
          const GridBox cells = GridBox::ofCells(*grid);
          EXPECT_EQ(box.x_lo, x_lo) << shape << " " << x0 << " " << cell;
          EXPECT_EQ(box.x_hi, x_hi) << shape << " " << x0 << " " << cell;
          EXPECT_EQ(box.y_lo, y_lo) << shape << " " << x0 << " " << cell;
          EXPECT_EQ(box.y_hi, y_hi) << shape << " " << x0 << " " << cell;
          EXPECT_TRUE(box.x_lo >= cells.x_lo && box.x_hi <= cells.x_hi &&
                      box.y_lo >= cells.y_lo && box.y_hi <= cells.y_hi);
          ++grids;
        }
      }
  EXPECT_EQ(grids, 96);
}
