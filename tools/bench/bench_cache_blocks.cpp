// Cache blocks (issue 15): a measured prototype of block-local triangulation with the
// "known space" finality rule of the tiled path, against the core's region growing
// and CGAL on the same points, in one process:
//   bench_cache_blocks DIST N [BLOCK [RING [SEED]]] [--check]
//   DIST: jittered | uniform | clustered | grid (tools/bench/bench_inputs.h)
// The grid stage is the core's (bucket, merge duplicates, subdivide crowded cells).
// Then for every block of BLOCK x BLOCK cells (default 32) with points, the points of
// the block and of a ring of RING cells around it (default 1) are triangulated by
// Bowyer-Watson insertion in snake cell order (walk from the last new triangle, the
// core's exact orient2d and incirclePerturbed, so the same tie-break), inside a finite
// super triangle. A triangle of real points is *final* when a bound on its circumdisk
// lies inside the loaded window shrunk by the grid's slack (sides on the grid border
// are open): no unloaded point can then be inside or on its circle, so it is a triangle
// of the global (perturbed) Delaunay triangulation. It is *kept* by the block holding
// its smallest vertex id, so each is kept once. The triangles not proven are what the
// mediatrix search would still have to grow (near voids, the hull, block corners).
// Prints one JSON line: CPU seconds per stage (CLOCK_THREAD_CPUTIME_ID), ns per
// distinct point, the share of the Delaunay triangles proven. --check compares every
// kept triangle with the core's triangulation (must be one of its triangles, kept once)
// and exits 3 on a mismatch. The integrated version is VtsOptions::cache_blocks
// (src/core/local_delaunay.cpp; bench_triangulation vts against vts-search).
#include "bench_inputs.h"

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/cell_pyramid.h>
#include <pcl_vts/core/cell_subdivision.h>
#include <pcl_vts/core/convex_hull.h>
#include <pcl_vts/core/grid_triangulator.h>
#include <pcl_vts/core/merge_duplicates.h>
#include <pcl_vts/core/predicates.h>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Projection_traits_xy_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

namespace {

using pcl_vts::Point2;
using pcl_vts::Sign;

double threadCpuSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// A disk containing the exact circumdisk of (a, b, c), or false when floating point
/// cannot bound it (flat triangle). The bound of known_space.cpp (boundCircumdisk).
bool boundCircumdisk(const Point2& a, const Point2& b, const Point2& c, Point2& center,
                     double& radius)
{
  const double bx = b.x - a.x, by = b.y - a.y;
  const double cx = c.x - a.x, cy = c.y - a.y;
  const double t1 = bx * cy, t2 = by * cx;
  const double det = 2.0 * (t1 - t2);
  if (!(std::fabs(det) > 1e-6 * (std::fabs(t1) + std::fabs(t2))) || !std::isfinite(det))
    return false;
  const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  const double ux = (cy * b2 - by * c2) / det;
  const double uy = (bx * c2 - cx * b2) / det;
  center = {a.x + ux, a.y + uy};
  const double r = std::sqrt(ux * ux + uy * uy);
  radius = r + 1e-7 * (r + std::sqrt(b2) + std::sqrt(c2)) +
           1e-15 * (std::fabs(a.x) + std::fabs(a.y));
  return std::isfinite(radius);
}

/// Bowyer-Watson Delaunay triangulation of a small point set inside a super triangle,
/// flat arrays reused from block to block. Triangle t: vertices v[3t..3t+2] CCW;
/// halfedge 3t+i goes v[3t+i] -> v[3t+(i+1)%3], adj[3t+i] is its twin or -1.
class LocalDelaunay {
 public:
  std::vector<Point2> p; ///< 0..2: the super triangle; then the points in order
  std::vector<std::int32_t> v, adj;
  std::size_t incircle_tests = 0, walk_steps = 0;

  void reset(double x0, double y0, double x1, double y1)
  {
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    const double d = std::max(x1 - x0, y1 - y0) + 1.0;
    p.clear();
    p.push_back({cx - 10.0 * d, cy - 10.0 * d});
    p.push_back({cx + 10.0 * d, cy - 10.0 * d});
    p.push_back({cx, cy + 10.0 * d});
    v.assign({0, 1, 2});
    adj.assign({-1, -1, -1});
    if (stamp_.empty())
      stamp_.resize(1);
    stamp_[0] = 0;
    last_ = 0;
  }

  void insert(const Point2& q)
  {
    const auto k = static_cast<std::int32_t>(p.size());
    p.push_back(q);
    if (head_.size() < p.size())
      head_.resize(2 * p.size());
    // Visibility walk from the last new triangle (terminates in a Delaunay mesh); the
    // edge it came in by is not tested again (q is left of it).
    std::int32_t t = last_;
    int entry = -1;
    for (;;) {
      int e = 0;
      for (; e < 3; ++e) {
        if (e == entry)
          continue;
        const Point2& a = p[static_cast<std::size_t>(v[3 * t + e])];
        const Point2& b = p[static_cast<std::size_t>(v[3 * t + (e + 1) % 3])];
        if (pcl_vts::orient2d(a, b, q) == Sign::NEGATIVE)
          break;
      }
      if (e == 3)
        break;
      const std::int32_t o = adj[3 * t + e];
      t = o / 3;
      entry = o % 3;
      ++walk_steps;
    }
    // Cavity: every triangle whose (perturbed) circumcircle holds q, grown from t.
    stamp_counter_ += 2;
    const std::uint32_t bad_mark = stamp_counter_, good_mark = stamp_counter_ + 1;
    bad_.clear();
    boundary_.clear();
    bad_.push_back(t);
    stamp_[static_cast<std::size_t>(t)] = bad_mark;
    for (std::size_t i = 0; i < bad_.size(); ++i) {
      const std::int32_t b = bad_[i];
      for (int e = 0; e < 3; ++e) {
        const std::int32_t h = 3 * b + e;
        const std::int32_t o = adj[static_cast<std::size_t>(h)];
        if (o >= 0) {
          const std::int32_t n = o / 3;
          std::uint32_t& s = stamp_[static_cast<std::size_t>(n)];
          if (s == bad_mark)
            continue;
          if (s != good_mark) {
            ++incircle_tests;
            if (pcl_vts::incirclePerturbed(p[static_cast<std::size_t>(v[3 * n])],
                                           p[static_cast<std::size_t>(v[3 * n + 1])],
                                           p[static_cast<std::size_t>(v[3 * n + 2])],
                                           q) == Sign::POSITIVE) {
              s = bad_mark;
              bad_.push_back(n);
              continue;
            }
            s = good_mark;
          }
        }
        boundary_.push_back({v[static_cast<std::size_t>(h)],
                             v[static_cast<std::size_t>(3 * b + (e + 1) % 3)], o});
      }
    }
    // Star of q over the cavity boundary: reuse the cavity's slots, then append.
    std::int32_t s = 0;
    for (std::size_t j = 0; j < boundary_.size(); ++j) {
      if (j < bad_.size()) {
        s = bad_[j];
      } else {
        s = static_cast<std::int32_t>(v.size() / 3);
        v.resize(v.size() + 3);
        adj.resize(adj.size() + 3);
        stamp_.push_back(0);
      }
      const std::array<std::int32_t, 3>& edge = boundary_[j];
      v[static_cast<std::size_t>(3 * s)] = edge[0];
      v[static_cast<std::size_t>(3 * s + 1)] = edge[1];
      v[static_cast<std::size_t>(3 * s + 2)] = k;
      adj[static_cast<std::size_t>(3 * s)] = edge[2];
      if (edge[2] >= 0)
        adj[static_cast<std::size_t>(edge[2])] = 3 * s;
      head_[static_cast<std::size_t>(edge[0])] = s;
    }
    for (std::size_t j = 0; j < boundary_.size(); ++j) {
      const std::int32_t t1 =
          j < bad_.size()
              ? bad_[j]
              : static_cast<std::int32_t>(v.size() / 3 - (boundary_.size() - j));
      const std::int32_t t2 =
          head_[static_cast<std::size_t>(v[static_cast<std::size_t>(3 * t1 + 1)])];
      adj[static_cast<std::size_t>(3 * t1 + 1)] = 3 * t2 + 2;
      adj[static_cast<std::size_t>(3 * t2 + 2)] = 3 * t1 + 1;
    }
    last_ = s;
  }

 private:
  std::vector<std::uint32_t> stamp_;
  std::uint32_t stamp_counter_ = 0;
  std::vector<std::int32_t> head_, bad_;
  std::vector<std::array<std::int32_t, 3>> boundary_;
  std::int32_t last_ = 0;
};

struct BlockResult {
  std::vector<std::array<std::uint32_t, 3>> kept; ///< grid ids, CCW
  /// Twin of each kept halfedge (3 per kept triangle) or INVALID_ID: open, for the
  /// search (its neighbour is not proven) or on the hull.
  std::vector<std::uint32_t> twins;
  std::size_t loaded = 0; ///< points inserted, ring included
  std::size_t open_edges = 0;
  double seconds_gather = 0, seconds_insert = 0, seconds_finalize = 0, seconds_link = 0;
  std::size_t incircle_tests = 0, walk_steps = 0;
};

/// The block-local stage over the whole grid.
void triangulateBlocks(const pcl_vts::CellGrid& grid, std::uint32_t block,
                       std::uint32_t ring, BlockResult& out)
{
  LocalDelaunay dt;
  std::vector<std::int64_t> kept_as; // per local triangle: its kept index, or -1
  /// Kept halfedges whose twin is not kept by the same block: (smaller vertex, larger
  /// vertex, halfedge), paired across blocks by one sort at the end.
  std::vector<std::array<std::uint32_t, 3>> border;
  std::vector<std::uint32_t> ids;
  std::vector<std::uint8_t> core;
  const double c = grid.cell_size;
  for (std::uint32_t bj = 0; bj * block < grid.ny; ++bj)
    for (std::uint32_t bi = 0; bi * block < grid.nx; ++bi) {
      double t0 = threadCpuSeconds();
      const std::uint32_t ci0 = bi * block, ci1 = std::min(grid.nx, ci0 + block);
      const std::uint32_t cj0 = bj * block, cj1 = std::min(grid.ny, cj0 + block);
      std::uint32_t own = 0;
      for (std::uint32_t j = cj0; j < cj1; ++j)
        own += grid.cell_start[grid.cellId(ci1 - 1, j) + 1] -
               grid.cell_start[grid.cellId(ci0, j)];
      if (own == 0)
        continue; // no point of its own
      const std::uint32_t wi0 = ci0 > ring ? ci0 - ring : 0,
                          wi1 = std::min(grid.nx, ci1 + ring);
      const std::uint32_t wj0 = cj0 > ring ? cj0 - ring : 0,
                          wj1 = std::min(grid.ny, cj1 + ring);
      // The window's known space: open on the grid border, else its nominal side
      // moved inwards by the slack (a point of an unloaded cell may be that close).
      const double x_lo = wi0 == 0 ? -HUGE_VAL : grid.origin_x + wi0 * c + grid.slack;
      const double x_hi =
          wi1 == grid.nx ? HUGE_VAL : grid.origin_x + wi1 * c - grid.slack;
      const double y_lo = wj0 == 0 ? -HUGE_VAL : grid.origin_y + wj0 * c + grid.slack;
      const double y_hi =
          wj1 == grid.ny ? HUGE_VAL : grid.origin_y + wj1 * c - grid.slack;
      dt.reset(grid.origin_x + wi0 * c, grid.origin_y + wj0 * c,
               grid.origin_x + wi1 * c, grid.origin_y + wj1 * c);
      ids.assign(3, pcl_vts::INVALID_ID);
      core.assign(3, 0);
      // Three rounds, snake order over the cell rows in each: cells at even multiples
      // of 4 from the window corner, then of 2, then the rest. Inserting in one sweep
      // puts every point on the frontier of the mesh, where the thin triangles to the
      // super triangle make large cavities; the coarse rounds fill the window first.
      for (std::uint32_t stride = 4; stride >= 1; stride /= 2)
        for (std::uint32_t j = wj0; j < wj1; ++j) {
          const bool forward = ((j - wj0) & 1u) == 0;
          for (std::uint32_t m = 0; m < wi1 - wi0; ++m) {
            const std::uint32_t i = forward ? wi0 + m : wi1 - 1 - m;
            const std::uint32_t di = i - wi0, dj = j - wj0;
            if (di % stride != 0 || dj % stride != 0 ||
                (stride < 4 && di % (2 * stride) == 0 && dj % (2 * stride) == 0))
              continue;
            const std::uint8_t in_core = i >= ci0 && i < ci1 && j >= cj0 && j < cj1;
            const pcl_vts::CellId cell = grid.cellId(i, j);
            for (std::uint32_t k = grid.cell_start[cell]; k < grid.cell_start[cell + 1];
                 ++k) {
              ids.push_back(k);
              core.push_back(in_core);
            }
          }
        }
      double t1 = threadCpuSeconds();
      out.seconds_gather += t1 - t0;
      for (std::size_t k = 3; k < ids.size(); ++k)
        dt.insert(grid.points[ids[k]]);
      out.loaded += ids.size() - 3;
      t0 = threadCpuSeconds();
      out.seconds_insert += t0 - t1;
      kept_as.assign(dt.v.size() / 3, -1);
      for (std::size_t t = 0; t < dt.v.size() / 3; ++t) {
        const auto a = static_cast<std::size_t>(dt.v[3 * t]),
                   b = static_cast<std::size_t>(dt.v[3 * t + 1]),
                   d = static_cast<std::size_t>(dt.v[3 * t + 2]);
        if (a < 3 || b < 3 || d < 3)
          continue;
        const std::size_t owner =
            ids[a] < ids[b] ? (ids[a] < ids[d] ? a : d) : (ids[b] < ids[d] ? b : d);
        if (core[owner] == 0)
          continue;
        Point2 center{};
        double r = 0;
        if (!boundCircumdisk(dt.p[a], dt.p[b], dt.p[d], center, r))
          continue;
        if (center.x - r > x_lo && center.x + r < x_hi && center.y - r > y_lo &&
            center.y + r < y_hi) {
          kept_as[t] = static_cast<std::int64_t>(out.kept.size());
          out.kept.push_back({ids[a], ids[b], ids[d]});
        }
      }
      t1 = threadCpuSeconds();
      out.seconds_finalize += t1 - t0;
      // Adjacency: inside the block from the local mesh, across blocks by the sort.
      out.twins.resize(3 * out.kept.size());
      for (std::size_t t = 0; t < kept_as.size(); ++t) {
        if (kept_as[t] < 0)
          continue;
        const auto g = static_cast<std::uint32_t>(kept_as[t]);
        for (std::uint32_t e = 0; e < 3; ++e) {
          const std::int32_t o = dt.adj[3 * t + e];
          if (o >= 0 && kept_as[static_cast<std::size_t>(o / 3)] >= 0) {
            out.twins[3 * g + e] = 3 * static_cast<std::uint32_t>(
                                           kept_as[static_cast<std::size_t>(o / 3)]) +
                                   static_cast<std::uint32_t>(o % 3);
          } else {
            out.twins[3 * g + e] = pcl_vts::INVALID_ID;
            const std::uint32_t u = out.kept[g][e], w = out.kept[g][(e + 1) % 3];
            border.push_back({std::min(u, w), std::max(u, w), 3 * g + e});
          }
        }
      }
      t0 = threadCpuSeconds();
      out.seconds_link += t0 - t1;
      out.incircle_tests += dt.incircle_tests;
      out.walk_steps += dt.walk_steps;
      dt.incircle_tests = dt.walk_steps = 0;
    }
  const double t0 = threadCpuSeconds();
  std::sort(border.begin(), border.end());
  for (std::size_t k = 0; k < border.size(); ++k) {
    if (k + 1 < border.size() && border[k][0] == border[k + 1][0] &&
        border[k][1] == border[k + 1][1]) {
      out.twins[border[k][2]] = border[k + 1][2];
      out.twins[border[k + 1][2]] = border[k][2];
      ++k;
    } else {
      ++out.open_edges;
    }
  }
  out.seconds_link += threadCpuSeconds() - t0;
}

std::array<std::uint32_t, 3> canonical(std::array<std::uint32_t, 3> t)
{
  while (t[0] > t[1] || t[0] > t[2])
    std::rotate(t.begin(), t.begin() + 1, t.end());
  return t;
}

} // namespace

int main(int argc, char** argv)
{
  std::vector<std::string> args;
  bool check = false;
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--check") == 0)
      check = true;
    else
      args.emplace_back(argv[k]);
  }
  if (args.size() < 2) {
    std::fprintf(stderr,
                 "usage: %s jittered|uniform|clustered|grid N [BLOCK [RING "
                 "[SEED]]] [--check]\n",
                 argv[0]);
    return 1;
  }
  const auto n = static_cast<std::size_t>(std::atof(args[1].c_str()));
  const auto block =
      static_cast<std::uint32_t>(args.size() > 2 ? std::atoi(args[2].c_str()) : 32);
  const auto ring =
      static_cast<std::uint32_t>(args.size() > 3 ? std::atoi(args[3].c_str()) : 1);
  const auto seed =
      static_cast<unsigned>(args.size() > 4 ? std::atoi(args[4].c_str()) : 1);
  if (n < 3 || block < 1) {
    std::fprintf(stderr, "bench_cache_blocks: need N >= 3 and BLOCK >= 1\n");
    return 1;
  }
  const std::vector<double> xyz = pcl_vts::bench::generate(args[0], n, seed);
  std::vector<Point2> xy(n);
  for (std::size_t k = 0; k < n; ++k)
    xy[k] = {xyz[3 * k], xyz[3 * k + 1]};

  // CGAL on the same points (range insertion, its spatial sort included).
  // The traits bench_triangulation uses.
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Traits = CGAL::Projection_traits_xy_3<Kernel>;
  std::vector<Traits::Point_2> cgal_points;
  cgal_points.reserve(n);
  for (std::size_t k = 0; k < n; ++k)
    cgal_points.emplace_back(xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]);
  double t0 = threadCpuSeconds();
  std::size_t cgal_faces = 0;
  {
    const CGAL::Delaunay_triangulation_2<Traits> cgal(cgal_points.begin(),
                                                      cgal_points.end());
    cgal_faces = cgal.number_of_faces();
  }
  const double seconds_cgal = threadCpuSeconds() - t0;
  std::vector<Traits::Point_2>().swap(cgal_points);

  // The core's grid stage (as vts_pipeline.cpp, one thread).
  t0 = threadCpuSeconds();
  pcl_vts::CellGrid grid;
  std::vector<std::uint32_t> order;
  if (pcl_vts::Status s = pcl_vts::buildCellGrid(xy, 0.0, grid, order, 1); !s.ok()) {
    std::fprintf(stderr, "%s\n", s.toString().c_str());
    return 2;
  }
  std::vector<double> z(order.size(), 0.0);
  std::vector<std::uint32_t> source(order);
  std::vector<pcl_vts::VertexId> slot_to_vertex;
  pcl_vts::mergeDuplicates(grid, pcl_vts::DuplicateRule::LOWEST_Z, z, source,
                           slot_to_vertex);
  pcl_vts::CellSubdivision subdivision;
  std::vector<std::uint32_t> old_slot;
  pcl_vts::subdivideCrowdedCells(grid, subdivision, old_slot);
  pcl_vts::CellPyramid pyramid;
  pcl_vts::buildCellPyramid(grid, pyramid);
  const double seconds_grid = threadCpuSeconds() - t0;
  const std::size_t distinct = grid.points.size();

  // The core's triangulation (hull + region growing).
  t0 = threadCpuSeconds();
  std::vector<pcl_vts::VertexId> hull;
  const std::vector<pcl_vts::VertexId> candidates = pcl_vts::gridHullCandidates(grid);
  if (pcl_vts::Status s = pcl_vts::convexHull(grid.points, hull, &candidates);
      !s.ok()) {
    std::fprintf(stderr, "%s\n", s.toString().c_str());
    return 2;
  }
  std::vector<pcl_vts::VertexId> triangles;
  std::vector<pcl_vts::HalfedgeId> halfedges;
  pcl_vts::SearchStats stats;
  if (pcl_vts::Status s = pcl_vts::triangulateGrid(grid, pyramid, subdivision, hull,
                                                   triangles, halfedges, stats, 1);
      !s.ok()) {
    std::fprintf(stderr, "%s\n", s.toString().c_str());
    return 2;
  }
  const double seconds_vts = threadCpuSeconds() - t0;
  const std::size_t dt_triangles = triangles.size() / 3;

  // The block-local stage.
  BlockResult blocks;
  t0 = threadCpuSeconds();
  triangulateBlocks(grid, block, ring, blocks);
  const double seconds_blocks = threadCpuSeconds() - t0;

  int code = 0;
  std::size_t mismatches = 0;
  if (check) {
    std::vector<std::array<std::uint32_t, 3>> all(dt_triangles), kept(blocks.kept);
    for (std::size_t t = 0; t < dt_triangles; ++t)
      all[t] =
          canonical({triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]});
    for (auto& t : kept)
      t = canonical(t);
    std::sort(all.begin(), all.end());
    std::sort(kept.begin(), kept.end());
    for (std::size_t k = 0; k < kept.size(); ++k)
      if ((k > 0 && kept[k] == kept[k - 1]) ||
          !std::binary_search(all.begin(), all.end(), kept[k]))
        ++mismatches;
    // The links: twins are mutual and reverse the edge.
    for (std::size_t h = 0; h < blocks.twins.size(); ++h) {
      const std::uint32_t o = blocks.twins[h];
      if (o == pcl_vts::INVALID_ID)
        continue;
      const auto& t = blocks.kept[h / 3];
      const auto& u = blocks.kept[o / 3];
      if (blocks.twins[o] != h || t[h % 3] != u[(o + 1) % 3] ||
          t[(h + 1) % 3] != u[o % 3])
        ++mismatches;
    }
    code = mismatches == 0 ? 0 : 3;
  }
  const double per = 1e9 / static_cast<double>(distinct);
  std::printf(
      "{\"dist\":\"%s\",\"n\":%zu,\"distinct\":%zu,\"block\":%u,\"ring\":%u,"
      "\"cgal_ns\":%.1f,\"grid_ns\":%.1f,\"vts_ns\":%.1f,\"blocks_ns\":%.1f,"
      "\"gather_ns\":%.1f,\"insert_ns\":%.1f,\"finalize_ns\":%.1f,\"link_ns\":%.1f,"
      "\"open_edges_per_point\":%.4f,"
      "\"insert_ns_per_loaded\":%.1f,\"loaded_per_point\":%.3f,"
      "\"incircle_per_loaded\":%.2f,\"walk_per_loaded\":%.2f,\"proven_share\":%.4f,"
      "\"cgal_faces\":%zu,\"dt_triangles\":%zu,\"checked\":%s,\"mismatches\":%zu}\n",
      args[0].c_str(), n, distinct, block, ring, seconds_cgal * per, seconds_grid * per,
      seconds_vts * per, seconds_blocks * per, blocks.seconds_gather * per,
      blocks.seconds_insert * per, blocks.seconds_finalize * per,
      blocks.seconds_link * per,
      static_cast<double>(blocks.open_edges) / static_cast<double>(distinct),
      1e9 * blocks.seconds_insert / static_cast<double>(blocks.loaded),
      static_cast<double>(blocks.loaded) / static_cast<double>(distinct),
      static_cast<double>(blocks.incircle_tests) / static_cast<double>(blocks.loaded),
      static_cast<double>(blocks.walk_steps) / static_cast<double>(blocks.loaded),
      static_cast<double>(blocks.kept.size()) / static_cast<double>(dt_triangles),
      cgal_faces, dt_triangles, check ? "true" : "false", mismatches);
  return code;
}
