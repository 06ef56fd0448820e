// Cache blocks (issue 15): block-local triangulation with the "known space" finality
// rule of the tiled path, measured alone against the core's region growing and CGAL
// on the same points, in one process:
//   bench_cache_blocks DIST N [BLOCK [RING [SEED]]] [--check]
//   DIST: jittered | uniform | clustered | grid (tools/bench/bench_inputs.h)
// The grid stage is the core's (bucket, merge duplicates, subdivide crowded cells).
// Then for every block of BLOCK x BLOCK cells (default 32) with points, the points of
// the block and of a ring of RING cells around it (default 1) are triangulated by the
// core's Bowyer-Watson (src/core/local_delaunay.h, the code the cache blocks run; the
// prototype this program first held, with its own copy and per-insertion counters,
// is at commit 226cedc). A triangle of real points is *final* when a bound on its
// circumdisk lies inside the loaded window shrunk by the grid's slack (sides on the
// grid border are open): no unloaded point can then be inside or on its circle, so it
// is a triangle of the global (perturbed) Delaunay triangulation. It is *kept* by the
// block holding its smallest vertex id, so each is kept once. The triangles not proven
// are what the mediatrix search would still have to grow (near voids, the hull, block
// corners). Prints one JSON line: CPU seconds per stage (CLOCK_THREAD_CPUTIME_ID), ns
// per distinct point, the share of the Delaunay triangles proven. --check compares
// every kept triangle with the core's triangulation (must be one of its triangles, kept
// once) and exits 3 on a mismatch. The integrated version is VtsOptions::cache_blocks
// (src/core/local_delaunay.cpp; bench_triangulation vts against vts-search).
#include "bench_inputs.h"
#include "local_delaunay.h"

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

double threadCpuSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct BlockResult {
  std::vector<std::array<std::uint32_t, 3>> kept; ///< grid ids, CCW
  /// Twin of each kept halfedge (3 per kept triangle) or INVALID_ID: open, for the
  /// search (its neighbour is not proven) or on the hull.
  std::vector<std::uint32_t> twins;
  std::size_t loaded = 0; ///< points inserted, ring included
  std::size_t open_edges = 0;
  double seconds_insert = 0, seconds_finalize = 0, seconds_link = 0;
};

/// The block-local stage over the whole grid, with the core's LocalDelaunay (the one
/// VtsOptions::cache_blocks runs inside the strips), timed per step.
void triangulateBlocks(const pcl_vts::CellGrid& grid, std::uint32_t block,
                       std::uint32_t ring, BlockResult& out)
{
  pcl_vts::detail::LocalDelaunay dt;
  std::vector<std::int64_t> kept_as; // per local triangle: its kept index, or -1
  /// Kept halfedges whose twin is not kept by the same block: (smaller vertex, larger
  /// vertex, halfedge), paired across blocks by one sort at the end.
  std::vector<std::array<std::uint32_t, 3>> border;
  for (std::uint32_t bj = 0; bj * block < grid.ny; ++bj)
    for (std::uint32_t bi = 0; bi * block < grid.nx; ++bi) {
      const pcl_vts::detail::CellWindow core{
          bi * block, std::min(grid.nx, bi * block + block), bj * block,
          std::min(grid.ny, bj * block + block)};
      std::uint32_t own = 0;
      for (std::uint32_t j = core.j0; j < core.j1; ++j)
        own += grid.cell_start[grid.cellId(core.i1 - 1, j) + 1] -
               grid.cell_start[grid.cellId(core.i0, j)];
      if (own == 0)
        continue; // no point of its own
      const pcl_vts::detail::CellWindow window{
          core.i0 > ring ? core.i0 - ring : 0, std::min(grid.nx, core.i1 + ring),
          core.j0 > ring ? core.j0 - ring : 0, std::min(grid.ny, core.j1 + ring)};
      double t0 = threadCpuSeconds();
      if (!dt.triangulate(grid, window, core))
        continue; // nothing proven: the search grows it all
      out.loaded += dt.ids.size() - 3;
      double t1 = threadCpuSeconds();
      out.seconds_insert += t1 - t0;
      // Kept by the block holding the smallest vertex id, so once.
      kept_as.assign(dt.v.size() / 3, -1);
      dt.forEachFinal(grid, window, [&](std::size_t t) {
        const auto a = static_cast<std::size_t>(dt.v[3 * t]),
                   b = static_cast<std::size_t>(dt.v[3 * t + 1]),
                   d = static_cast<std::size_t>(dt.v[3 * t + 2]);
        const std::size_t owner = dt.ids[a] < dt.ids[b]
                                      ? (dt.ids[a] < dt.ids[d] ? a : d)
                                      : (dt.ids[b] < dt.ids[d] ? b : d);
        if (dt.in_core[owner] == 0)
          return;
        kept_as[t] = static_cast<std::int64_t>(out.kept.size());
        out.kept.push_back({dt.ids[a], dt.ids[b], dt.ids[d]});
      });
      t0 = threadCpuSeconds();
      out.seconds_finalize += t0 - t1;
      // Adjacency: inside the block from the local mesh, across blocks by the sort.
      out.twins.resize(3 * out.kept.size());
      for (std::size_t t = 0; t < kept_as.size(); ++t) {
        if (kept_as[t] < 0)
          continue;
        const auto g = static_cast<std::uint32_t>(kept_as[t]);
        for (std::uint32_t e = 0; e < 3; ++e) {
          const std::int32_t o = dt.twin(t, e);
          const std::uint32_t o_t =
              o >= 0 ? pcl_vts::detail::LocalDelaunay::twinTriangle(o) : 0;
          if (o >= 0 && kept_as[o_t] >= 0) {
            out.twins[3 * g + e] = 3 * static_cast<std::uint32_t>(kept_as[o_t]) +
                                   pcl_vts::detail::LocalDelaunay::twinEdge(o);
          } else {
            out.twins[3 * g + e] = pcl_vts::INVALID_ID;
            const std::uint32_t u = out.kept[g][e], w = out.kept[g][(e + 1) % 3];
            border.push_back({std::min(u, w), std::max(u, w), 3 * g + e});
          }
        }
      }
      out.seconds_link += threadCpuSeconds() - t0;
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
                 "usage: %s jittered|uniform|clustered|grid|raster N [BLOCK [RING "
                 "[SEED]]] [--check]\n",
                 argv[0]);
    return 1;
  }
  const auto requested = static_cast<std::size_t>(std::atof(args[1].c_str()));
  const auto block =
      static_cast<std::uint32_t>(args.size() > 2 ? std::atoi(args[2].c_str()) : 32);
  const auto ring =
      static_cast<std::uint32_t>(args.size() > 3 ? std::atoi(args[3].c_str()) : 1);
  const auto seed =
      static_cast<unsigned>(args.size() > 4 ? std::atoi(args[4].c_str()) : 1);
  if (requested < 3 || block < 1) {
    std::fprintf(stderr, "bench_cache_blocks: need N >= 3 and BLOCK >= 1\n");
    return 1;
  }
  const std::vector<double> xyz = pcl_vts::bench::generate(args[0], requested, seed);
  const std::size_t n = xyz.size() / 3; // raster: fewer (its NODATA cells)
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
      "\"insert_ns\":%.1f,\"finalize_ns\":%.1f,\"link_ns\":%.1f,"
      "\"open_edges_per_point\":%.4f,"
      "\"insert_ns_per_loaded\":%.1f,\"loaded_per_point\":%.3f,"
      "\"proven_share\":%.4f,"
      "\"cgal_faces\":%zu,\"dt_triangles\":%zu,\"checked\":%s,\"mismatches\":%zu}\n",
      args[0].c_str(), n, distinct, block, ring, seconds_cgal * per, seconds_grid * per,
      seconds_vts * per, seconds_blocks * per, blocks.seconds_insert * per,
      blocks.seconds_finalize * per, blocks.seconds_link * per,
      static_cast<double>(blocks.open_edges) / static_cast<double>(distinct),
      1e9 * blocks.seconds_insert / static_cast<double>(blocks.loaded),
      static_cast<double>(blocks.loaded) / static_cast<double>(distinct),
      static_cast<double>(blocks.kept.size()) / static_cast<double>(dt_triangles),
      cgal_faces, dt_triangles, check ? "true" : "false", mismatches);
  return code;
}
