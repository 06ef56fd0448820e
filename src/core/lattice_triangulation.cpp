// Lattice fast path (lattice_triangulation.h, docs/algorithm.md section 7).
//
// Why the output is the Delaunay triangulation DT of the perturbed point set P:
// 1. A complete cell [x_i, x_i+1] x [y_j, y_j+1] is an exact rectangle: its corners
//    are cocircular and its circumcircle is the circle on its diagonal. No lattice
//    value lies strictly between x_i and x_i+1 (or y_j and y_j+1), so any other
//    lattice point has one coordinate beyond the cell's range and the other at best
//    on its end: it lies strictly outside. Under the perturbation (smallest point
//    lifted most) the lower-left corner A rises above the plane of the other three, so
//    the cell splits along the diagonal that avoids A: triangles (A, B, D) and (B, C,
//    D) with B the lower-right, C the upper-right and D the upper-left corner. Both are
//    DT triangles, found with no predicate call.
// 2. A vertex whose cells are all complete has its whole star in them (on the
//    lattice border: its cells inside are complete, so its neighbours along the
//    border are present and the hull there is the border line). So every other DT
//    triangle has its three vertices in I, the vertices touching an incomplete cell.
//    Its interior lies in the incomplete cells and is connected, so it lies in one
//    8-connected component of them (a piece), whose cells have its vertices as
//    corners.
// 3. Per piece, S = its I plus a ring of lattice points around it, triangulated by
//    the ordinary path. The perturbation compares only the lexicographic order of the
//    four points of a test, the same in S as in P, so every DT triangle with vertices
//    in S is a triangle of DT(S) (its circle is empty in P, hence in S). A triangle of
//    DT(S) whose closed circumdisk holds no point of P \ S is a DT triangle (the points
//    of P \ S lie strictly outside, so the perturbation cannot change their side).
//    Each round keeps the DT(S) triangles with vertices in the piece's I that are not
//    complete-cell triangles; if one of them has a point of P \ S in its closed disk,
//    those points (and their ring) join S and the round is redone. S grows strictly,
//    so the loop ends (at worst with S = P); in the last round every candidate is
//    proven, and every DT triangle of the piece is a candidate: the pieces' triangles
//    are exactly the rest of DT.
// 4. Small fringes (Fringe::solveInOneWindow) skip the rounds. An incomplete cell
//    with three corners gives the triangle of them (its circle is the cell's, by
//    1.). A vertex of I inside the lattice with its four axis neighbours present
//    has every cell complete or missing the opposite corner, so its star is those
//    triangles alone. W = I less those vertices, for every piece at once, is
//    triangulated in one window of the cache blocks' kernel; every other fringe
//    triangle has its vertices in W, so it is a DT(W) triangle, and a DT(W)
//    triangle with its vertices in one piece is a DT triangle when no point of P \ W
//    is inside its circle under the perturbation (the emptiness test of the
//    perturbed set itself). Every kept triangle is proven, so they are all of the
//    fringe exactly when their count closes up; when it falls short (a triangle lost
//    to the super triangle), 3. runs.
// The triangle count is checked against 2n - h - 2 and every halfedge is paired.
#include "lattice_triangulation.h"
#include "local_delaunay.h"
#include "release_memory.h"

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/grid_triangulator.h>
#include <pcl_vts/core/mediatrix_search.h>
#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/predicates.h>
#include <pcl_vts/core/stopwatch.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pcl_vts {
namespace {

// Same bounds as the ordinary path (vts_pipeline.cpp): beyond them it reports the
// error, so the fast path leaves such inputs to it.
constexpr double MAX_ABS_COORDINATE = 1e60;
constexpr double MIN_EXTENT = 1e-80;

/// v.reserve(count) with its pages faulted in at once (release_memory.h): for the big
/// arrays, written in full once the input is known to be a lattice.
template <class T>
void reservePopulated(std::vector<T>& v, std::size_t count)
{
  v.reserve(count);
  detail::populatePages(v.data(), v.data() + v.capacity());
}

/// Distinct values of one coordinate; ids in order of first appearance.
class ValueTable {
 public:
  ValueTable() { rehash(1u << 10); }

  std::uint32_t size() const { return static_cast<std::uint32_t>(values_.size()); }
  double value(std::uint32_t id) const { return values_[id]; }
  const std::vector<double>& values() const { return values_; }

  /// The id of v (-0 and +0 are one value), inserted if new. Inline: the detecting
  /// pass looks up every value of scattered input before it gives up.
  [[gnu::always_inline]] std::uint32_t idOf(double v)
  {
    v += 0.0; // -0 -> +0: equal values get equal bits
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    for (std::size_t h = slotOf(bits);; h = (h + 1) & mask_) {
      const std::uint32_t id = slots_[h];
      if (id == INVALID_ID) {
        slots_[h] = size();
        values_.push_back(v);
        if (2 * values_.size() > slots_.size())
          rehash(2 * slots_.size());
        return size() - 1;
      }
      if (values_[id] == v)
        return id;
    }
  }

 private:
  /// Fibonacci hashing: the top bits of the product depend on every bit of the
  /// value. (Bits 20 and up of it, as before, depend only on the value's low bits,
  /// all zero for small integers and short decimals: such coordinates all fell in one
  /// probe chain, walked at every skipped NODATA cell.)
  std::size_t slotOf(std::uint64_t bits) const
  {
    return static_cast<std::size_t>((bits * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  void rehash(std::size_t count)
  {
    slots_.assign(count, INVALID_ID);
    mask_ = count - 1;
    shift_ = 64;
    for (std::size_t c = count; c > 1; c >>= 1)
      --shift_;
    for (std::uint32_t id = 0; id < size(); ++id) {
      std::uint64_t bits = 0;
      std::memcpy(&bits, &values_[id], sizeof bits);
      std::size_t h = slotOf(bits);
      while (slots_[h] != INVALID_ID)
        h = (h + 1) & mask_;
      slots_[h] = id;
    }
  }

  std::vector<std::uint32_t> slots_;
  std::vector<double> values_;
  std::size_t mask_ = 0;
  int shift_ = 64; ///< 64 - log2(slot count)
};

/// Sorted distinct values and, per first-appearance id, the sorted rank.
void sortValues(const ValueTable& table, std::vector<double>& sorted,
                std::vector<std::uint32_t>& rank)
{
  std::vector<std::uint32_t> order(table.size());
  for (std::uint32_t k = 0; k < table.size(); ++k)
    order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return table.value(a) < table.value(b);
  });
  sorted.resize(order.size());
  rank.resize(order.size());
  for (std::uint32_t k = 0; k < order.size(); ++k) {
    sorted[k] = table.value(order[k]);
    rank[order[k]] = k;
  }
}

/// True when input k beats the current representative s (< k) of a position:
/// mergeDuplicates' rule, ties to the smaller input index.
bool replaces(DuplicateRule rule, double zk, double zs)
{
  switch (rule) {
  case DuplicateRule::LOWEST_Z:
    return zk < zs;
  case DuplicateRule::HIGHEST_Z:
    return zk > zs;
  default:
    return false;
  }
}

/// Lattice positions and the vertex at each (row-major, INVALID_ID when absent).
struct Lattice {
  std::vector<double> xs, ys; ///< sorted distinct coordinates
  std::uint32_t nx = 0, ny = 0;
  std::vector<VertexId> vertex_at; ///< nx * ny
  /// Complete cells (all four corners present; cells are row-major, (nx - 1) * (ny -
  /// 1) of them) before each cell row. A cell's rank in its row is counted while its
  /// row is walked: no per-cell array.
  std::vector<std::size_t> row_start;
  /// The other cells, sorted (cell ids fit 32 bits: positions are below INVALID_ID).
  std::vector<std::uint32_t> incomplete;
  /// Each lattice row's first present position and one past its last (columns):
  /// every position outside them is absent.
  std::vector<std::uint32_t> row_first, row_end;

  std::size_t position(std::uint32_t i, std::uint32_t j) const
  {
    return static_cast<std::size_t>(j) * nx + i;
  }
  std::size_t cell(std::uint32_t i, std::uint32_t j) const
  {
    return static_cast<std::size_t>(j) * (nx - 1) + i;
  }
  bool present(std::size_t p) const { return vertex_at[p] != INVALID_ID; }
  bool complete(std::uint32_t i, std::uint32_t j) const
  {
    const VertexId* low = &vertex_at[position(i, j)];
    const VertexId* high = low + nx;
    return low[0] != INVALID_ID && low[1] != INVALID_ID && high[0] != INVALID_ID &&
           high[1] != INVALID_ID;
  }
  std::size_t cellCount() const { return static_cast<std::size_t>(nx - 1) * (ny - 1); }
  Point2 point(std::size_t p) const { return {xs[p % nx], ys[p / nx]}; }
};

/// A run of input points with one y value (a row, as rasters are read): its first
/// input index, the finite points before it, the y value's id.
struct YRun {
  std::size_t first = 0;
  std::size_t finite_before = 0;
  std::uint32_t y_id = 0;
};
using YRuns = std::vector<YRun>;

/// Pass 1 of readLattice: the distinct x and y values of the finite points, which
/// are counted (finite) and the others (dropped). False, early, when the points are
/// scattered (more lattice positions than LATTICE_FILL_FACTOR per point) or a
/// coordinate is beyond the ordinary path's range. Also, while they stay few (rows in
/// order, as rasters are read), the runs of equal y id: readRows then reads the rows
/// once more and writes the vertices directly. Nothing is written per point.
bool distinctCoordinates(const double* xyz, std::size_t n, ValueTable& xt,
                         ValueTable& yt, std::size_t& finite, std::size_t& dropped,
                         YRuns& y_runs, bool& runs_ok)
{
  y_runs.clear();
  runs_ok = true;
  const std::size_t max_runs = n / 8 + 16; // rows of 8 points or more
  double last_x = std::nan(""), last_y = std::nan("");
  std::uint32_t id_x = 0, id_y = 0;
  const std::size_t limit = LATTICE_FILL_FACTOR * n;
  std::size_t finite_count = 0, dropped_count = 0; // in registers
  // Raster order: the value is usually the last one or the one after it (the tables'
  // values and sizes are held here, reloaded when a value is looked up).
  const double* x_values = xt.values().data();
  const double* y_values = yt.values().data();
  std::uint32_t x_count = xt.size(), y_count = yt.size();
  const auto lookup = [](ValueTable& table, double v, std::uint32_t& id,
                         const double*& values, std::uint32_t& count) {
    id = table.idOf(v);
    values = table.values().data();
    const bool grew = table.size() != count;
    count = table.size();
    return grew;
  };
  // A point whose x and y are values of the tables (the next one or the last one) is
  // finite and within the range (checked when they entered); only its height is
  // tested. Any other goes through `checked`, which tests x and y (after the height)
  // before anything enters the tables (a point with a non-finite coordinate is
  // dropped whole).
  enum Check { OK, DROP, OUT_OF_RANGE };
  const auto checked = [](double x, double y) { // the height is finite
    if (std::fabs(x) <= MAX_ABS_COORDINATE && std::fabs(y) <= MAX_ABS_COORDINATE)
      return OK;
    return std::isfinite(x) && std::isfinite(y) ? OUT_OF_RANGE : DROP;
  };
  constexpr double MAX = std::numeric_limits<double>::max();
  for (std::size_t k = 0; k < n; ++k) {
    const double x = xyz[3 * k], y = xyz[3 * k + 1], h = xyz[3 * k + 2];
    const bool next_x = id_x + 1 < x_count && x_values[id_x + 1] == x;
    // Along a row of a raster: the table's next x value, the row's y, a finite height
    // (what the tests below find), tested together without a branch each; then the
    // points after it likewise, while they go on so.
    if (next_x & (y == last_y) & (std::fabs(h) <= MAX)) {
      ++id_x;
      ++finite_count;
      last_x = x;
      for (const double* p = xyz + 3 * k + 3;
           k + 1 < n && id_x + 1 < x_count &&
           ((x_values[id_x + 1] == p[0]) & (p[1] == last_y) & (std::fabs(p[2]) <= MAX));
           p += 3) {
        ++k;
        ++id_x;
        ++finite_count;
        last_x = p[0];
      }
      continue;
    }
    if (!(std::fabs(h) <= MAX)) {
      ++dropped_count; // h not finite
      continue;
    }
    // Scattered: the positions exceed the limit (the pass stops after about
    // sqrt(8 n) points); tested when a table grows.
    const auto tooMany = [&] {
      return static_cast<std::size_t>(x_count) * static_cast<std::size_t>(y_count) >
             limit;
    };
    if (next_x) {
      ++id_x;
      last_x = x;
    } else if (!(x == last_x)) {
      if (const Check c = checked(x, y); c != OK) {
        if (c == OUT_OF_RANGE)
          return false;
        ++dropped_count;
        continue;
      }
      last_x = x;
      if (lookup(xt, x, id_x, x_values, x_count) && tooMany())
        return false;
    }
    if (!(y == last_y)) {
      const std::uint32_t before = id_y;
      if (id_y + 1 < y_count && y_values[id_y + 1] == y) {
        ++id_y;
      } else {
        if (const Check c = checked(x, y); c != OK) {
          if (c == OUT_OF_RANGE)
            return false;
          ++dropped_count;
          continue;
        }
        if (lookup(yt, y, id_y, y_values, y_count) && tooMany())
          return false;
      }
      last_y = y;
      if (runs_ok && (y_runs.empty() || id_y != before)) {
        if (y_runs.size() < max_runs) {
          y_runs.push_back({k, finite_count, id_y});
        } else { // not in rows
          runs_ok = false;
          YRuns().swap(y_runs);
        }
      }
    }
    ++finite_count;
  }
  finite += finite_count;
  dropped += dropped_count;
  return true;
}

/// Pass 2 of readLattice for input in rows: one run per lattice row (each y value in
/// one run), x increasing strictly along each run. A point's vertex id is then its
/// row's first id plus its place in the run: the vertices (lattice row-major order,
/// as the general pass gives them), vertex_at and the input map are written in one
/// read, rows taken bottom up so that every array grows in order (a row's zeros are
/// in cache when it is written), and no position can hold two points. False, with
/// the arrays left partly written, at the first run whose x does not increase: the
/// general pass then decides.
bool readRows(const double* xyz, std::size_t n, const YRuns& runs, std::size_t finite,
              ValueTable& xt, const std::vector<std::uint32_t>& rank_x,
              const std::vector<std::uint32_t>& rank_y, bool input_map, Lattice& lat,
              VtsResult& result)
{
  std::vector<std::uint32_t> run_of_row(lat.ny);
  for (std::size_t r = 0; r < runs.size(); ++r)
    run_of_row[rank_y[runs[r].y_id]] = static_cast<std::uint32_t>(r);
  std::vector<VertexId>& slot = lat.vertex_at;
  std::vector<std::uint32_t>& source = result.source_index;
  TriangleMesh& mesh = result.mesh;
  std::vector<VertexId>& code = result.input_to_vertex;
  reservePopulated(slot, static_cast<std::size_t>(lat.nx) * lat.ny);
  reservePopulated(source, finite);
  reservePopulated(mesh.xy, finite);
  reservePopulated(mesh.z, finite);
  if (input_map)
    code.assign(n, INVALID_ID);
  const double* xs = lat.xs.data();
  const std::uint32_t nx = lat.nx;
  VertexId next = 0;
  for (std::uint32_t j = 0; j < lat.ny; ++j) {
    const YRun& run = runs[run_of_row[j]];
    const std::size_t end =
        run_of_row[j] + 1 < runs.size() ? runs[run_of_row[j] + 1].first : n;
    const std::size_t count =
        (run_of_row[j] + 1 < runs.size() ? runs[run_of_row[j] + 1].finite_before
                                         : finite) -
        run.finite_before;
    slot.resize(slot.size() + nx, INVALID_ID);
    source.resize(next + count);
    mesh.xy.resize(next + count);
    mesh.z.resize(next + count);
    VertexId* row = slot.data() + lat.position(0, j);
    std::uint32_t* src = source.data();
    Point2* xy = mesh.xy.data();
    double* z = mesh.z.data();
    std::uint32_t allowed = 0; // the smallest x rank the run may take next
    // The run's points; SKIP: some are not finite (dropped by pass 1), MAP: input_map.
    const auto readRun = [&](auto skip, auto map) {
      const double* p = xyz + 3 * run.first;
      for (std::size_t k = run.first; k < end; ++k, p += 3) {
        if constexpr (!decltype(skip)::value) {
          // Two points at the next two x values: the steps below for each, without a
          // test between them.
          while (k + 2 <= end && allowed + 2 <= nx &&
                 ((xs[allowed] == p[0]) & (xs[allowed + 1] == p[3]))) {
            row[allowed] = next;
            row[allowed + 1] = next + 1;
            src[next] = static_cast<std::uint32_t>(k);
            src[next + 1] = static_cast<std::uint32_t>(k + 1);
            std::memcpy(&xy[next], p, sizeof(Point2));
            std::memcpy(&xy[next + 1], p + 3, sizeof(Point2));
            z[next] = p[2];
            z[next + 1] = p[5];
            if (decltype(map)::value) {
              code[k] = next;
              code[k + 1] = next + 1;
            }
            allowed += 2;
            next += 2;
            k += 2;
            p += 6;
          }
          if (k == end)
            break;
        }
        if (decltype(skip)::value &&
            (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])))
          continue;
        std::uint32_t i = allowed;
        if (!(i < nx && xs[i] == p[0])) {
          i = rank_x[xt.idOf(p[0])];
          if (i < allowed)
            return false; // a duplicate, or the row is not in order of x
        }
        allowed = i + 1;
        row[i] = next;
        src[next] = static_cast<std::uint32_t>(k);
        static_assert(sizeof(Point2) == 2 * sizeof(double), "x and y only");
        std::memcpy(&xy[next], p, sizeof(Point2)); // x then y, as in the input
        z[next] = p[2];
        if (decltype(map)::value)
          code[k] = next;
        ++next;
      }
      return true;
    };
    using Yes = std::true_type;
    using No = std::false_type;
    const bool all_finite = count == end - run.first; // nothing to skip
    const bool read = all_finite
                          ? (input_map ? readRun(No(), Yes()) : readRun(No(), No()))
                          : (input_map ? readRun(Yes(), Yes()) : readRun(Yes(), No()));
    if (!read)
      return false;
  }
  return true;
}

/// Reads the input: distinct coordinates, duplicates merged, vertex ids. False when
/// the points do not form a lattice the fast path should take.
bool readLattice(const double* xyz, std::size_t n, const VtsOptions& options,
                 Lattice& lat, VtsResult& result)
{
  Diagnostics& diag = result.diagnostics;
  ValueTable xt, yt;
  std::size_t finite = 0, dropped = 0;
  std::vector<std::uint32_t>& code = result.input_to_vertex;
  YRuns y_runs;
  bool runs_ok = false;
  if (!distinctCoordinates(xyz, n, xt, yt, finite, dropped, y_runs, runs_ok))
    return false;
  const std::size_t positions =
      static_cast<std::size_t>(xt.size()) * static_cast<std::size_t>(yt.size());
  if (finite == 0 || xt.size() < 2 || yt.size() < 2 ||
      positions > LATTICE_FILL_FACTOR * finite || positions >= INVALID_ID)
    return false;
  std::vector<std::uint32_t> rank_x, rank_y;
  sortValues(xt, lat.xs, rank_x);
  sortValues(yt, lat.ys, rank_y);
  lat.nx = xt.size();
  lat.ny = yt.size();
  const double extent =
      std::max(lat.xs.back() - lat.xs.front(), lat.ys.back() - lat.ys.front());
  if (extent < MIN_EXTENT)
    return false;
  const auto done = [&](std::size_t merged) {
    diag.non_finite_dropped = dropped;
    diag.duplicates_merged = merged;
    diag.distinct_points = finite - merged;
    diag.cells = positions;
    diag.cell_size = 0.0;
    diag.lattice_columns = lat.nx;
    diag.lattice_rows = lat.ny;
    return true;
  };
  if (runs_ok && y_runs.size() == lat.ny) { // each row one run
    if (readRows(xyz, n, y_runs, finite, xt, rank_x, rank_y, options.input_map, lat,
                 result))
      return done(0);
    lat.vertex_at.clear();
    result.source_index.clear();
    result.mesh.xy.clear();
    result.mesh.z.clear();
  }
  YRuns().swap(y_runs);

  // Pass 2: the position of every point (in input_to_vertex for now) and the
  // representative input point of every position.
  std::vector<std::uint32_t>& slot = lat.vertex_at;
  reservePopulated(slot, positions);
  slot.assign(positions, INVALID_ID);
  code.assign(n, INVALID_ID);
  std::size_t merged = 0;
  bool zero_replaced = false; // a representative replaced at x or y == 0 (+-0.0)
  const auto place = [&](std::size_t k, std::uint32_t p) {
    std::uint32_t& s = slot[p];
    if (s == INVALID_ID) {
      s = static_cast<std::uint32_t>(k);
    } else {
      ++merged;
      if (replaces(options.duplicate_rule, xyz[3 * k + 2],
                   xyz[3 * static_cast<std::size_t>(s) + 2])) {
        s = static_cast<std::uint32_t>(k);
        zero_replaced = zero_replaced || xyz[3 * k] == 0.0 || xyz[3 * k + 1] == 0.0;
      }
    }
  };
  {
    // Sorted ranks, predicted from the last one (rows may come top down).
    const auto rankOf = [](ValueTable& table, const std::vector<std::uint32_t>& rank,
                           const std::vector<double>& sorted, double v,
                           std::uint32_t& r) {
      if (r + 1 < sorted.size() && sorted[r + 1] == v)
        ++r;
      else if (r > 0 && sorted[r - 1] == v)
        --r;
      else
        r = rank[table.idOf(v)];
    };
    std::uint32_t r_x = 0, r_y = 0;
    double last_x = std::nan(""), last_y = std::nan("");
    for (std::size_t k = 0; k < n; ++k) {
      const double x = xyz[3 * k], y = xyz[3 * k + 1];
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(xyz[3 * k + 2]))
        continue; // dropped by pass 1
      if (!(x == last_x)) {
        last_x = x;
        rankOf(xt, rank_x, lat.xs, x, r_x);
      }
      if (!(y == last_y)) {
        last_y = y;
        rankOf(yt, rank_y, lat.ys, y, r_y);
      }
      code[k] = static_cast<std::uint32_t>(lat.position(r_x, r_y));
      place(k, code[k]);
    }
  }
  // Vertex ids in lattice order, in place, with their positions and heights; then
  // each input's vertex.
  const std::size_t nv = finite - merged;
  std::vector<std::uint32_t>& source = result.source_index;
  TriangleMesh& mesh = result.mesh;
  // Grown row by row (no pass zeroing them first: a row's zeros are in cache when
  // it is written).
  reservePopulated(source, nv);
  reservePopulated(mesh.xy, nv);
  reservePopulated(mesh.z, nv);
  VertexId next = 0;
  for (std::uint32_t j = 0; j < lat.ny; ++j) {
    std::uint32_t* row = &slot[lat.position(0, j)];
    std::size_t count = 0;
    for (std::uint32_t i = 0; i < lat.nx; ++i)
      count += row[i] != INVALID_ID;
    source.resize(next + count);
    mesh.xy.resize(next + count);
    mesh.z.resize(next + count);
    std::uint32_t* src = source.data();
    Point2* xy = mesh.xy.data();
    double* z = mesh.z.data();
    for (std::uint32_t i = 0; i < lat.nx; ++i)
      if (const std::uint32_t s = row[i]; s != INVALID_ID) {
        const double* p = xyz + 3 * static_cast<std::size_t>(s);
        src[next] = s;
        xy[next] = {p[0], p[1]};
        z[next] = p[2];
        row[i] = next++;
      }
  }
  const bool mean_z = options.duplicate_rule == DuplicateRule::MEAN_Z && merged > 0;
  if (!options.input_map && !zero_replaced && !mean_z) {
    std::vector<std::uint32_t>().swap(code); // not wanted, nor needed below
  } else {
    for (std::uint32_t& c : code)
      if (c != INVALID_ID)
        c = slot[c];
  }
  if (zero_replaced) {
    // As mergeDuplicates: a position's XY is its first input point's, whose -0.0 or
    // +0.0 may differ from the representative's (the tiled path rebuilds vertices so).
    std::vector<bool> placed(nv, false);
    for (std::size_t k = 0; k < n; ++k)
      if (const std::uint32_t v = code[k]; v != INVALID_ID && !placed[v]) {
        placed[v] = true;
        mesh.xy[v] = {xyz[3 * k], xyz[3 * k + 1]};
      }
  }

  if (mean_z) {
    // As vertexHeights (vts_pipeline.cpp): sums in input order.
    std::vector<std::uint32_t> count(nv, 0);
    std::fill(mesh.z.begin(), mesh.z.end(), 0.0);
    for (std::size_t k = 0; k < n; ++k)
      if (const VertexId v = result.input_to_vertex[k]; v != INVALID_ID) {
        mesh.z[v] += xyz[3 * k + 2];
        ++count[v];
      }
    for (std::size_t v = 0; v < nv; ++v)
      mesh.z[v] /= static_cast<double>(count[v]);
  }
  return done(merged);
}

/// The convex hull from the first and last point of every row and column: a
/// superset of the hull boundary (a supporting line through a boundary point makes
/// it extreme in its row, or in its column when the line is horizontal). Andrew's
/// monotone chain as in convexHull (the same vertices from the same start, collinear
/// boundary points kept), without its passes over all the points.
Status latticeHull(Lattice& lat, std::vector<VertexId>& hull)
{
  std::vector<std::uint32_t> low(lat.nx, INVALID_ID), high(lat.nx, INVALID_ID);
  std::vector<std::uint64_t> keys; // (column, row): lexicographic (x, y) order
  const auto key = [](std::uint32_t i, std::uint32_t j) {
    return (static_cast<std::uint64_t>(i) << 32) | j;
  };
  // Each row's first and last point, scanned from its ends (a row holds a point
  // unless it is all NODATA), and each column's lowest and highest, rows scanned from
  // the bottom (the top) over the columns not found yet: not every position is read.
  lat.row_first.assign(lat.ny, lat.nx);
  lat.row_end.assign(lat.ny, 0);
  for (std::uint32_t j = 0; j < lat.ny; ++j) {
    const VertexId* row = &lat.vertex_at[lat.position(0, j)];
    std::uint32_t first = 0, last = lat.nx;
    while (first < lat.nx && row[first] == INVALID_ID)
      ++first;
    if (first == lat.nx)
      continue;
    while (row[last - 1] == INVALID_ID)
      --last;
    lat.row_first[j] = first;
    lat.row_end[j] = last;
    keys.push_back(key(first, j));
    keys.push_back(key(last - 1, j));
  }
  const auto extremes = [&lat](std::vector<std::uint32_t>& found, bool upward) {
    std::vector<std::uint32_t> left(lat.nx); // columns not found yet
    for (std::uint32_t i = 0; i < lat.nx; ++i)
      left[i] = i;
    for (std::uint32_t r = 0; r < lat.ny && !left.empty(); ++r) {
      const std::uint32_t j = upward ? r : lat.ny - 1 - r;
      const VertexId* row = &lat.vertex_at[lat.position(0, j)];
      std::size_t kept = 0;
      for (const std::uint32_t i : left)
        if (row[i] != INVALID_ID)
          found[i] = j;
        else
          left[kept++] = i;
      left.resize(kept);
    }
  };
  extremes(low, true);
  extremes(high, false);
  for (std::uint32_t i = 0; i < lat.nx; ++i)
    if (low[i] != INVALID_ID) {
      keys.push_back(key(i, low[i]));
      keys.push_back(key(i, high[i]));
    }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<Point2> p(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k)
    p[k] = {lat.xs[keys[k] >> 32], lat.ys[keys[k] & 0xffffffffu]};
  bool has_area = false;
  for (std::size_t k = 1; k + 1 < p.size() && !has_area; ++k)
    has_area = orient2d(p.front(), p.back(), p[k]) != Sign::ZERO;
  if (!has_area)
    return Status::error(StatusCode::ALL_COLLINEAR, "collinear"); // not reported
  std::vector<std::uint32_t> chain;
  const auto build = [&](auto first, auto last) {
    const std::size_t base = chain.size();
    for (auto it = first; it != last; ++it) {
      while (chain.size() >= base + 2 &&
             orient2d(p[chain[chain.size() - 2]], p[chain.back()], p[*it]) ==
                 Sign::NEGATIVE)
        chain.pop_back();
      chain.push_back(*it);
    }
    chain.pop_back(); // the last point starts the other chain
  };
  std::vector<std::uint32_t> order(p.size());
  for (std::uint32_t k = 0; k < order.size(); ++k)
    order[k] = k;
  build(order.begin(), order.end());
  build(order.rbegin(), order.rend());
  hull.clear();
  for (const std::uint32_t k : chain)
    hull.push_back(lat.vertex_at[lat.position(static_cast<std::uint32_t>(keys[k] >> 32),
                                              static_cast<std::uint32_t>(keys[k]))]);
  return Status::success();
}

/// Every position of the lattice row holds a point: vertex ids grow by one along a
/// row's present positions (lattice row-major order), so its ends are nx - 1 apart
/// exactly when none is missing.
bool fullRow(const VertexId* row, std::uint32_t nx)
{
  return row[0] != INVALID_ID && row[nx - 1] != INVALID_ID &&
         row[nx - 1] - row[0] == nx - 1;
}

/// The complete cells' row offsets, the incomplete cells. One thread lists them
/// straight into lat.incomplete, reserved for every cell (only the pages written are
/// faulted in): no copies of a growing list (on zSW3.asc's 35 k incomplete cells the
/// list's regrowth and the copy of the per-thread lists faulted in about 190 pages);
/// several list theirs per chunk, joined in row order.
void rankCompleteCells(Lattice& lat, unsigned threads)
{
  const std::uint32_t cx = lat.nx - 1, cy = lat.ny - 1;
  lat.row_start.assign(static_cast<std::size_t>(cy) + 1, 0);
  const unsigned parts = std::max(1u, threads);
  std::vector<std::vector<std::uint32_t>> incomplete(parts > 1 ? parts : 0);
  if (parts == 1)
    lat.incomplete.reserve(lat.cellCount());
  parallelChunks(threads, cy, [&](std::size_t begin, std::size_t end, unsigned t) {
    std::vector<std::uint32_t>& list = parts == 1 ? lat.incomplete : incomplete[t];
    for (auto j = static_cast<std::uint32_t>(begin); j < end; ++j) {
      const VertexId* below = &lat.vertex_at[lat.position(0, j)];
      const VertexId* above = below + lat.nx;
      std::uint32_t count = 0;
      if (fullRow(below, lat.nx) && fullRow(above, lat.nx)) {
        lat.row_start[j + 1] = cx; // every cell complete
        continue;
      }
      const auto row = static_cast<std::uint32_t>(lat.cell(0, j));
      std::uint32_t i = 0;
#if defined(__SSE2__)
      // Four cells at a time: a lane is set where a corner is missing.
      static constexpr std::uint8_t SET_BITS[16] = {0, 1, 1, 2, 1, 2, 2, 3,
                                                    1, 2, 2, 3, 2, 3, 3, 4};
      const __m128i absent = _mm_set1_epi32(-1);
      const auto missing = [&absent](const VertexId* q) {
        return _mm_cmpeq_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(q)),
                               absent);
      };
      for (; i + 4 <= cx; i += 4) {
        const __m128i m =
            _mm_or_si128(_mm_or_si128(missing(below + i), missing(below + i + 1)),
                         _mm_or_si128(missing(above + i), missing(above + i + 1)));
        auto bits = static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(m)));
        count += 4u - SET_BITS[bits];
        for (; bits != 0; bits &= bits - 1)
          list.push_back(row + i + static_cast<std::uint32_t>(__builtin_ctz(bits)));
      }
#endif
      for (; i < cx; ++i)
        if (below[i] != INVALID_ID && below[i + 1] != INVALID_ID &&
            above[i] != INVALID_ID && above[i + 1] != INVALID_ID)
          ++count;
        else
          list.push_back(row + i);
      lat.row_start[j + 1] = count;
    }
  });
  for (std::uint32_t j = 0; j < cy; ++j)
    lat.row_start[j + 1] += lat.row_start[j];
  for (const std::vector<std::uint32_t>& part : incomplete) // chunks in row order
    lat.incomplete.insert(lat.incomplete.end(), part.begin(), part.end());
}

/// The first triangle of each cell of cell row r in the output (complete cells are
/// numbered in row-major order, two triangles each), INVALID_ID for an incomplete
/// cell and for every cell of a row beyond the lattice (r = -1 or r = cy): idx[i + 1]
/// for cell i, idx[0] and idx[cx + 1] INVALID_ID. A row beyond the lattice (NONE) or
/// with every cell complete (FULL: cell i's first triangle is first + 2 i) is not
/// listed.
struct CellRow {
  enum Kind { NONE, FULL, PARTIAL };
  Kind kind = NONE;
  HalfedgeId first = 0; ///< the row's first triangle
  std::vector<HalfedgeId> idx;
  /// PARTIAL: the row's incomplete cells in lat.incomplete, the row's first cell id.
  const std::uint32_t *incomplete_begin = nullptr, *incomplete_end = nullptr;
  std::size_t cell0 = 0;

  void index(const Lattice& lat, std::int64_t r)
  {
    kind = NONE;
    if (r < 0 || r >= static_cast<std::int64_t>(lat.ny) - 1)
      return;
    const auto j = static_cast<std::uint32_t>(r);
    const std::uint32_t cx = lat.nx - 1;
    first = static_cast<HalfedgeId>(2 * lat.row_start[j]);
    if (lat.row_start[j + 1] - lat.row_start[j] == cx) {
      kind = FULL;
      return;
    }
    kind = PARTIAL;
    idx.resize(static_cast<std::size_t>(cx) + 2);
    idx[0] = idx[static_cast<std::size_t>(cx) + 1] = INVALID_ID;
    // From the row's incomplete cells (lat.incomplete, sorted): the complete cells
    // between them count up.
    const std::size_t row = lat.cell(0, j);
    auto it = std::lower_bound(lat.incomplete.begin(), lat.incomplete.end(), row);
    HalfedgeId t = first;
    HalfedgeId* out = idx.data() + 1;
    std::uint32_t i = 0;
    cell0 = row;
    incomplete_begin = lat.incomplete.data() + (it - lat.incomplete.begin());
    for (; it != lat.incomplete.end() && *it < row + cx; ++it) {
      const auto gap = static_cast<std::uint32_t>(*it - row);
      for (; i < gap; ++i, t += 2)
        out[i] = t;
      out[i++] = INVALID_ID;
    }
    for (; i < cx; ++i, t += 2)
      out[i] = t;
    incomplete_end = lat.incomplete.data() + (it - lat.incomplete.begin());
  }
};

/// Emits the run [i0, i1) of complete cells of a cell row (the cells beside it
/// incomplete or beyond the lattice): their corners are present, so the vertex ids
/// (low0 and high0 at column i0), the triangles (first: cell i0's first) and the
/// twins inside the run are arithmetic in i; the twins below and above likewise when
/// that row is FULL, none when it is beyond the lattice, looked up otherwise. The
/// same values and open halfedges as a loop over the cells (not in the same order).
template <CellRow::Kind BELOW, CellRow::Kind ABOVE>
void emitRun(std::uint32_t i0, std::uint32_t i1, VertexId low0, VertexId high0,
             HalfedgeId first, const CellRow& below, const CellRow& above,
             VertexId* tri, HalfedgeId* twin, std::vector<HalfedgeId>& open)
{
  const HalfedgeId* b = BELOW == CellRow::PARTIAL ? below.idx.data() + 1 : nullptr;
  const HalfedgeId* a = ABOVE == CellRow::PARTIAL ? above.idx.data() + 1 : nullptr;
  const HalfedgeId below_e = 3 * below.first + 4, above_e = 3 * above.first;
  // The twins across the rows below and above.
  const auto down = [&](std::uint32_t i) -> HalfedgeId {
    if constexpr (BELOW == CellRow::FULL)
      return below_e + 6 * i;
    else if constexpr (BELOW == CellRow::PARTIAL)
      return b[i] != INVALID_ID ? 3 * b[i] + 4 : INVALID_ID;
    else
      return INVALID_ID;
  };
  const auto up = [&](std::uint32_t i) -> HalfedgeId {
    if constexpr (ABOVE == CellRow::FULL)
      return above_e + 6 * i;
    else if constexpr (ABOVE == CellRow::PARTIAL)
      return a[i] != INVALID_ID ? 3 * a[i] : INVALID_ID;
    else
      return INVALID_ID;
  };
  HalfedgeId e0 = 3 * first;
  VertexId* v = tri + e0;
  HalfedgeId* h = twin + e0;
  VertexId lo = low0, hi = high0;
  std::uint32_t i = i0;
#if defined(__SSE2__)
  // Two cells at a time: their twelve vertex ids and twelve twins in three vectors
  // each, every lane counting up (by 2 and 12 a pair), the twins across the rows
  // below and above written over theirs unless that row is FULL.
  if (i1 - i0 >= 2) {
    const auto lanes = [](std::uint32_t w, std::uint32_t x, std::uint32_t y,
                          std::uint32_t z) {
      return _mm_setr_epi32(static_cast<int>(w), static_cast<int>(x),
                            static_cast<int>(y), static_cast<int>(z));
    };
    __m128i t0 = lanes(lo, lo + 1, hi, lo + 1), t1 = lanes(hi + 1, hi, lo + 1, lo + 2),
            t2 = lanes(hi + 1, lo + 2, hi + 2, hi + 1);
    // The twins across a FULL row count up in their lanes too.
    const HalfedgeId d0 = BELOW == CellRow::FULL ? below_e + 6 * i : 0,
                     u0 = ABOVE == CellRow::FULL ? above_e + 6 * i : 0;
    __m128i h0 = lanes(d0, e0 + 5, e0 - 3, e0 + 8),
            h1 = lanes(u0, e0 + 1, BELOW == CellRow::FULL ? d0 + 6 : 0, e0 + 11),
            h2 = lanes(e0 + 3, e0 + 14, ABOVE == CellRow::FULL ? u0 + 6 : 0, e0 + 7);
    const __m128i two = _mm_set1_epi32(2), twelve = _mm_set1_epi32(12);
    for (; i + 2 <= i1; i += 2, v += 12, h += 12) {
      _mm_storeu_si128(reinterpret_cast<__m128i*>(v), t0);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(v + 4), t1);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(v + 8), t2);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(h), h0);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(h + 4), h1);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(h + 8), h2);
      if constexpr (BELOW != CellRow::FULL) {
        h[0] = down(i);
        h[6] = down(i + 1);
      }
      if constexpr (ABOVE != CellRow::FULL) {
        h[4] = up(i);
        h[10] = up(i + 1);
      }
      t0 = _mm_add_epi32(t0, two);
      t1 = _mm_add_epi32(t1, two);
      t2 = _mm_add_epi32(t2, two);
      h0 = _mm_add_epi32(h0, twelve);
      h1 = _mm_add_epi32(h1, twelve);
      h2 = _mm_add_epi32(h2, twelve);
    }
    e0 += 6 * (i - i0);
    lo += i - i0;
    hi += i - i0;
  }
#endif
  for (; i < i1; ++i, e0 += 6, v += 6, h += 6, ++lo, ++hi) {
    v[0] = lo;
    v[1] = lo + 1;
    v[2] = hi;
    v[3] = lo + 1;
    v[4] = hi + 1;
    v[5] = hi;
    h[0] = down(i);
    h[1] = e0 + 5;
    h[2] = e0 - 3;
    h[3] = e0 + 8;
    h[4] = up(i);
    h[5] = e0 + 1;
  }
  // The run's ends face incomplete cells or the border; the open halfedges below and
  // above: every cell's beyond the lattice, the incomplete cells' of a PARTIAL row
  // (their order in `open` does not matter: pairHalfedges pairs them by vertex pair).
  const HalfedgeId start = 3 * first, last = start + 6 * (i1 - i0 - 1);
  twin[start + 2] = INVALID_ID;
  twin[last + 3] = INVALID_ID;
  open.push_back(start + 2);
  open.push_back(last + 3);
  const auto openFacing = [&](const CellRow& row, HalfedgeId k) {
    if (row.kind == CellRow::NONE) {
      for (std::uint32_t c = i0; c < i1; ++c)
        open.push_back(start + 6 * (c - i0) + k);
      return;
    }
    for (const std::uint32_t* it =
             std::lower_bound(row.incomplete_begin, row.incomplete_end, row.cell0 + i0);
         it != row.incomplete_end && *it < row.cell0 + i1; ++it)
      open.push_back(start + 6 * static_cast<HalfedgeId>(*it - row.cell0 - i0) + k);
  };
  if constexpr (BELOW != CellRow::FULL)
    openFacing(below, 0);
  if constexpr (ABOVE != CellRow::FULL)
    openFacing(above, 4);
}

/// emitRun for the kinds of the rows below and above. A PARTIAL row whose cells
/// beside the run are all complete counts up there as a FULL row does: its cells'
/// first triangles idx[i] are idx[i0] + 2 (i - i0), those of a FULL row whose first
/// triangle is idx[i0] - 2 i0 (modulo 2^32: only the run's values are formed), and
/// it has no open halfedge facing the run.
void emitRunOf(std::uint32_t i0, std::uint32_t i1, VertexId low0, VertexId high0,
               HalfedgeId first, const CellRow& below, const CellRow& above,
               VertexId* tri, HalfedgeId* twin, std::vector<HalfedgeId>& open)
{
  const auto completeBeside = [i0, i1](const CellRow& row, CellRow& full) {
    if (row.kind != CellRow::PARTIAL)
      return false;
    const HalfedgeId* c = row.idx.data() + 1;
    if (c[i0] == INVALID_ID || c[i1 - 1] == INVALID_ID ||
        c[i1 - 1] - c[i0] != 2 * (i1 - 1 - i0))
      return false; // an incomplete cell beside the run: idx skips it
    full.kind = CellRow::FULL;
    full.first = c[i0] - 2 * i0;
    return true;
  };
  CellRow below_full, above_full;
  const CellRow& b = completeBeside(below, below_full) ? below_full : below;
  const CellRow& a = completeBeside(above, above_full) ? above_full : above;
  using K = CellRow;
  using Emit = void (*)(std::uint32_t, std::uint32_t, VertexId, VertexId, HalfedgeId,
                        const CellRow&, const CellRow&, VertexId*, HalfedgeId*,
                        std::vector<HalfedgeId>&);
  static constexpr Emit EMIT[3][3] = {
      {emitRun<K::NONE, K::NONE>, emitRun<K::NONE, K::FULL>,
       emitRun<K::NONE, K::PARTIAL>},
      {emitRun<K::FULL, K::NONE>, emitRun<K::FULL, K::FULL>,
       emitRun<K::FULL, K::PARTIAL>},
      {emitRun<K::PARTIAL, K::NONE>, emitRun<K::PARTIAL, K::FULL>,
       emitRun<K::PARTIAL, K::PARTIAL>}};
  EMIT[b.kind][a.kind](i0, i1, low0, high0, first, b, a, tri, twin, open);
}

/// The triangles of every complete cell in row-major order (the first
/// 2 * row_start.back() triangles), with the twins among them; the halfedges facing
/// an incomplete cell (or the border) are INVALID_ID and listed in `open`. One
/// thread appends (no pass zeroing the arrays first) and hands vertex_at's pages
/// back as it goes (lat.vertex_at is empty afterwards, whatever the thread count);
/// several write their rows into arrays sized once.
void emitCompleteCells(Lattice& lat, unsigned threads, std::vector<VertexId>& triangles,
                       std::vector<HalfedgeId>& halfedges,
                       std::vector<HalfedgeId>& open, std::size_t capacity)
{
  // Rows [begin, end): each cell's six halfedges written in place, the open ones
  // listed. Complete cell (i, j) has triangles (A, B, D) and (B, C, D), A lower
  // left, B lower right, C upper right, D upper left. A->B faces the cell below (its
  // C->D, halfedge 4), D->A the cell on the left (its B->C, halfedge 3), B->C the
  // cell on the right (its D->A, halfedge 2), C->D the cell above (its A->B,
  // halfedge 0); B-D is shared. Each cell's first triangle in the rows below, at and
  // above the row is looked up in three rolling CellRows (sentinels at both ends: no
  // bounds work per cell), only below and above: emitRun writes each run of complete
  // cells with the vertices and the twins inside it counted up. Row j's halfedges are
  // [6 row_start[j], 6 row_start[j + 1]): one thread grows the arrays row by row (no
  // pass zeroing them first: the zeros of a row are in cache when it is written), with
  // their pages faulted in a chunk ahead (populateAhead) and the lattice rows no longer
  // read handed back (releasePages: the peak holds the cells' arrays, not vertex_at
  // too).
  const auto emitRows = [&lat, &triangles,
                         &halfedges](std::size_t begin, std::size_t end,
                                     std::vector<HalfedgeId>& my_open, bool grow) {
    const std::uint32_t cx = lat.nx - 1;
    CellRow below, at, above;
    below.index(lat, static_cast<std::int64_t>(begin) - 1);
    at.index(lat, static_cast<std::int64_t>(begin));
    const void* populated_triangles = nullptr; // populateAhead's marks
    const void* populated_halfedges = nullptr;
    const void* released = lat.vertex_at.data();
    constexpr std::ptrdiff_t RELEASE_STEP = std::ptrdiff_t{1} << 18; // bytes at a time
    for (auto j = static_cast<std::uint32_t>(begin); j < end; ++j) {
      above.index(lat, static_cast<std::int64_t>(j) + 1);
      const std::size_t size = 6 * lat.row_start[j + 1];
      if (grow && size > triangles.size()) {
        detail::populateAhead(triangles, size - triangles.size(), populated_triangles);
        detail::populateAhead(halfedges, size - halfedges.size(), populated_halfedges);
        triangles.resize(size);
        halfedges.resize(size);
      }
      const VertexId* low = &lat.vertex_at[lat.position(0, j)];
      const VertexId* high = low + lat.nx;
      VertexId* tri = triangles.data();
      HalfedgeId* twin = halfedges.data();
      if (at.kind == CellRow::FULL) {
        emitRunOf(0, cx, low[0], high[0], at.first, below, above, tri, twin, my_open);
      } else {
        // The runs of complete cells (idx[cx + 1], past the last cell, is INVALID_ID).
        const HalfedgeId* c = at.idx.data() + 1;
        for (std::uint32_t i = 0; i < cx;) {
          if (c[i] == INVALID_ID) {
            ++i;
            continue;
          }
          std::uint32_t i1 = i + 1;
          while (c[i1] != INVALID_ID)
            ++i1;
          emitRunOf(i, i1, low[i], high[i], c[i], below, above, tri, twin, my_open);
          i = i1;
        }
      }
      if (grow) { // lattice rows up to j are read no more
        const void* done = lat.vertex_at.data() + lat.position(0, j + 1);
        if (static_cast<const char*>(done) - static_cast<const char*>(released) >=
            RELEASE_STEP)
          released = detail::releasePagesUpTo(released, done);
      }
      std::swap(below, at);
      std::swap(at, above);
    }
  };
  const std::size_t rows = lat.ny - 1;
  if (threads <= 1) {
    triangles.reserve(capacity); // the fringe's triangles follow
    halfedges.reserve(capacity);
    emitRows(0, rows, open, true);
    std::vector<VertexId>().swap(lat.vertex_at);
    return;
  }
  reservePopulated(triangles, capacity);
  reservePopulated(halfedges, capacity);
  triangles.resize(6 * lat.row_start.back());
  halfedges.resize(triangles.size());
  std::vector<std::vector<HalfedgeId>> open_per_chunk(threads);
  parallelChunks(threads, rows, [&](std::size_t begin, std::size_t end, unsigned t) {
    emitRows(begin, end, open_per_chunk[t], false);
  });
  for (const std::vector<HalfedgeId>& part : open_per_chunk)
    open.insert(open.end(), part.begin(), part.end());
  std::vector<VertexId>().swap(lat.vertex_at);
}

/// Lattice rows per block of Fringe::emptyOutsideWindow's skip test.
constexpr std::uint32_t ROW_BLOCK = 16;

class Fringe {
 public:
  Fringe(const Lattice& lat, const TriangleMesh& mesh, const VtsOptions& options,
         unsigned threads)
      : lat_(lat)
      , mesh_(mesh)
      , options_(options)
      , threads_(threads)
  {}

  /// The DT triangles that are not complete-cell triangles, CCW vertex triples;
  /// INTERNAL_ERROR when the ordinary path fails on a piece (triangulateLattice then
  /// checks that the count closes up). `expected`: how many there are (2n - h - 2
  /// less the complete cells' triangles): the one-window pass below must reach it.
  Status triangulate(std::vector<std::array<VertexId, 3>>& found, Diagnostics& diag,
                     std::size_t expected);

 private:
  /// One component of the incomplete cells with its S, triangulated on its own.
  struct Piece {
    std::uint32_t label = 0;
    std::vector<std::size_t> own;   ///< its positions in I, sorted
    std::vector<std::size_t> s;     ///< positions in S_C, sorted
    std::vector<std::size_t> added; ///< positions added by the rounds, sorted
    std::vector<std::array<VertexId, 3>> found;
    std::size_t rounds = 0;
    std::size_t points = 0; ///< in S in the last round
    std::size_t cells = 0;  ///< incomplete cells in it
    SearchStats stats;
    Status status;
  };

  void labelPieces(std::vector<Piece>& pieces);
  /// The piece of an I position, INVALID_ID for any other position.
  std::uint32_t labelOf(std::size_t p) const
  {
    const auto it = std::lower_bound(i_.begin(), i_.end(), p);
    return it != i_.end() && *it == p
               ? label_[static_cast<std::size_t>(it - i_.begin())]
               : INVALID_ID;
  }
  void solve(Piece& piece) const;
  /// Every piece but the gaps at once: DT(W) in one LocalDelaunay window (no grid
  /// stage, pyramid or search per piece, no rounds), its triangles proven one by one
  /// by emptyOutsideWindow. False when the window could not be triangulated.
  bool solveInOneWindow(std::vector<Piece>& pieces, double widening);
  /// No point of P \ W inside the circle of the CCW lattice triangle p under the
  /// perturbation (incirclePerturbed).
  bool emptyOutsideWindow(const std::array<std::size_t, 3>& p) const;
  /// A piece that is one missing position with its eight neighbours present (a
  /// NODATA cell or a dropout): its six triangles without a search; false otherwise.
  bool solveGap(Piece& piece) const;
  /// One round with S = the piece's I, by testing every triple (small pieces); false
  /// when a candidate fails its disk check (the rounds then start over with the ring).
  bool solveSmall(Piece& piece) const;
  static bool inPiece(const Piece& piece, std::size_t p)
  {
    return std::binary_search(piece.s.begin(), piece.s.end(), p) ||
           std::binary_search(piece.added.begin(), piece.added.end(), p);
  }
  /// The points found in candidates' disks join the piece's S with their ring.
  void grow(Piece& piece, const std::vector<std::size_t>& inside) const;
  /// The present positions within lattice_ring steps of p (p included), appended.
  void ring(std::size_t p, std::vector<std::size_t>& out) const;
  bool isCellTriangle(const std::array<std::size_t, 3>& p) const;
  /// The three positions are corners of one cell.
  bool isOneCell(const std::array<std::size_t, 3>& p) const;
  /// Present position (i, j) is in I (a corner of an incomplete cell).
  bool inI(std::uint32_t i, std::uint32_t j) const;
  /// Present position (i, j) is in W, solveInOneWindow's points: I less the corners
  /// inside the lattice whose four axis neighbours are present. Each cell of such a
  /// corner is complete or misses the opposite corner, so its star is the cells'
  /// triangles and the three-corner triangles with their right angle at it.
  bool inWindow(std::uint32_t i, std::uint32_t j) const;
  /// Present positions outside the piece in the closed circumdisk of the CCW
  /// triangle p, appended to inside.
  void pointsInDisk(const Piece& piece, const std::array<std::size_t, 3>& p,
                    std::vector<std::size_t>& inside) const;

  const Lattice& lat_;
  const TriangleMesh& mesh_;
  const VtsOptions& options_;
  unsigned threads_;
  std::vector<std::size_t> i_;       ///< positions in I, sorted
  std::vector<std::uint32_t> label_; ///< the piece of each i_
  std::size_t window_points_ = 0;    ///< I of the pieces solveInOneWindow solved
  /// Per lattice row, the columns [first, end) holding its points of P \ W; per
  /// block of ROW_BLOCK rows, the least x of them and the greatest (lo > hi when
  /// there are none): emptyOutsideWindow skips rows and blocks.
  std::vector<std::uint32_t> inner_first_, inner_end_;
  std::vector<double> block_lo_, block_hi_;
};

void Fringe::ring(std::size_t p, std::vector<std::size_t>& out) const
{
  const std::uint32_t r = options_.lattice_ring;
  const auto i = static_cast<std::uint32_t>(p % lat_.nx),
             j = static_cast<std::uint32_t>(p / lat_.nx);
  const std::uint32_t i0 = i > r ? i - r : 0, j0 = j > r ? j - r : 0;
  const std::uint32_t i1 = std::min(lat_.nx - 1, i + std::min(r, lat_.nx)),
                      j1 = std::min(lat_.ny - 1, j + std::min(r, lat_.ny));
  for (std::uint32_t jj = j0; jj <= j1; ++jj)
    for (std::uint32_t ii = i0; ii <= i1; ++ii)
      if (const std::size_t q = lat_.position(ii, jj); lat_.present(q))
        out.push_back(q);
}

void Fringe::labelPieces(std::vector<Piece>& pieces)
{
  // Pieces: the 8-connected components of the incomplete cells (sharing an edge or
  // a corner). A fringe triangle's interior lies in the incomplete cells (the
  // complete ones are covered by their own triangles) and is connected, so it lies
  // in one component, and its vertices are corners of that component's cells. I is
  // the set of their present corners: the vertices with an incomplete cell (on the
  // lattice border, cells beyond it do not count: the border vertex's cells inside
  // being complete, its neighbours along the border are present, every point lies
  // on the inner side of the border line, and those cells cover the hull around it).
  const std::vector<std::uint32_t>& cells = lat_.incomplete;
  const std::uint32_t cx = lat_.nx - 1, cy = lat_.ny - 1;
  // The components from the runs of incomplete cells along each row: two runs in
  // consecutive rows touch (by an edge or a corner) when their column ranges,
  // widened by one, overlap; a union-find over the runs joins them. Labels are given
  // in order of each component's first run, i.e. of its smallest cell, as a flood
  // fill seeded in cell order numbers them.
  struct Run {
    std::uint32_t i0, i1, j; ///< columns [i0, i1) of cell row j
  };
  std::vector<Run> runs;
  // The first run of each cell row (cy + 1 entries: the corners below are listed
  // row by row from them).
  std::vector<std::size_t> row_runs(static_cast<std::size_t>(cy) + 1, 0);
  for (const std::uint32_t c : cells) {
    const auto i = static_cast<std::uint32_t>(c % cx),
               j = static_cast<std::uint32_t>(c / cx);
    if (runs.empty() || runs.back().j != j || runs.back().i1 != i) {
      runs.push_back({i, i + 1, j});
      ++row_runs[j + 1];
    } else {
      ++runs.back().i1;
    }
  }
  for (std::uint32_t j = 0; j < cy; ++j)
    row_runs[j + 1] += row_runs[j];
  std::vector<std::uint32_t> parent(runs.size());
  for (std::size_t r = 0; r < runs.size(); ++r)
    parent[r] = static_cast<std::uint32_t>(r);
  const auto find = [&parent](std::uint32_t r) {
    while (parent[r] != r)
      r = parent[r] = parent[parent[r]];
    return r;
  };
  for (std::size_t a = 0, b = 0; a < runs.size(); ++a) {
    // b: the first run of row j + 1 that may touch run a (runs are in cell order).
    const std::uint32_t j = runs[a].j;
    while (b < runs.size() &&
           (runs[b].j <= j || (runs[b].j == j + 1 && runs[b].i1 < runs[a].i0)))
      ++b;
    for (std::size_t c = b;
         c < runs.size() && runs[c].j == j + 1 && runs[c].i0 <= runs[a].i1; ++c) {
      const std::uint32_t x = find(static_cast<std::uint32_t>(a)),
                          y = find(static_cast<std::uint32_t>(c));
      if (x != y)
        parent[std::max(x, y)] = std::min(x, y);
    }
  }
  std::vector<std::uint32_t> label_of(runs.size(), INVALID_ID), run_label(runs.size());
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const std::uint32_t root = find(static_cast<std::uint32_t>(r));
    if (label_of[root] == INVALID_ID) {
      label_of[root] = static_cast<std::uint32_t>(pieces.size());
      pieces.emplace_back();
      pieces.back().label = label_of[root];
    }
    run_label[r] = label_of[root];
    pieces[run_label[r]].cells += runs[r].i1 - runs[r].i0;
  }
  // I in position order without a sort: the present corners on lattice row j are the
  // top corners of the runs of cell row j - 1 and the bottom corners of those of row
  // j (run [i0, i1) has corners i0 to i1), each list in order of i; merged, equal
  // positions once. A corner's cells all lie in one piece (they share it).
  for (std::uint32_t j = 0; j <= cy; ++j) {
    std::array<std::size_t, 2> at = {j > 0 ? row_runs[j - 1] : 0,
                                     j < cy ? row_runs[j] : 0};
    const std::array<std::size_t, 2> end = {j > 0 ? row_runs[j] : 0,
                                            j < cy ? row_runs[j + 1] : 0};
    const std::size_t row = lat_.position(0, j);
    std::uint32_t next = 0; // the smallest corner not listed yet
    for (;;) {
      const bool first = at[0] < end[0], second = at[1] < end[1];
      if (!first && !second)
        break;
      const unsigned from =
          first && (!second || runs[at[0]].i0 <= runs[at[1]].i0) ? 0 : 1;
      const Run& run = runs[at[from]];
      const std::uint32_t label = run_label[at[from]];
      ++at[from];
      for (std::uint32_t i = std::max(next, run.i0); i <= run.i1; ++i)
        if (lat_.present(row + i)) {
          i_.push_back(row + i);
          label_.push_back(label);
          pieces[label].own.push_back(row + i); // in order
        }
      next = std::max(next, run.i1 + 1);
    }
  }
}

bool Fringe::isOneCell(const std::array<std::size_t, 3>& p) const
{
  const auto i = [this](std::size_t q) {
    return static_cast<std::uint32_t>(q % lat_.nx);
  };
  const auto j = [this](std::size_t q) {
    return static_cast<std::uint32_t>(q / lat_.nx);
  };
  const std::uint32_t i0 = std::min({i(p[0]), i(p[1]), i(p[2])}),
                      i1 = std::max({i(p[0]), i(p[1]), i(p[2])}),
                      j0 = std::min({j(p[0]), j(p[1]), j(p[2])}),
                      j1 = std::max({j(p[0]), j(p[1]), j(p[2])});
  return i1 == i0 + 1 && j1 == j0 + 1;
}

bool Fringe::inWindow(std::uint32_t i, std::uint32_t j) const
{
  if (i == 0 || j == 0 || i + 1 == lat_.nx || j + 1 == lat_.ny)
    return inI(i, j);
  // Inside the lattice: in I, unless its four axis neighbours are present (then each
  // of its cells is complete or has it as the corner opposite the missing one).
  const std::size_t p = lat_.position(i, j);
  return !lat_.present(p - 1) || !lat_.present(p + 1) || !lat_.present(p - lat_.nx) ||
         !lat_.present(p + lat_.nx);
}

bool Fringe::inI(std::uint32_t i, std::uint32_t j) const
{
  // Present, with an absent position among its eight neighbours inside the lattice:
  // each of them shares a cell with it.
  const std::uint32_t i0 = i > 0 ? i - 1 : 0, i1 = std::min(lat_.nx - 1, i + 1);
  const std::uint32_t j0 = j > 0 ? j - 1 : 0, j1 = std::min(lat_.ny - 1, j + 1);
  for (std::uint32_t jj = j0; jj <= j1; ++jj)
    for (std::uint32_t ii = i0; ii <= i1; ++ii)
      if (!lat_.present(lat_.position(ii, jj)))
        return true;
  return false;
}

bool Fringe::isCellTriangle(const std::array<std::size_t, 3>& p) const
{
  std::uint32_t i0 = INVALID_ID, i1 = 0, j0 = INVALID_ID, j1 = 0;
  for (const std::size_t q : p) {
    const auto i = static_cast<std::uint32_t>(q % lat_.nx),
               j = static_cast<std::uint32_t>(q / lat_.nx);
    i0 = std::min(i0, i);
    i1 = std::max(i1, i);
    j0 = std::min(j0, j);
    j1 = std::max(j1, j);
  }
  // Three corners of one complete cell: one of the cell's two triangles (emitted with
  // the cells), or, when the fourth corner is not in S (ring 0), a triangle with that
  // corner on its circle, not Delaunay in P. Either way not a fringe triangle.
  return i1 == i0 + 1 && j1 == j0 + 1 && lat_.complete(i0, j0);
}

/// The indices [first, last) of the sorted values within [low, high].
std::pair<std::uint32_t, std::uint32_t> indicesWithin(const std::vector<double>& sorted,
                                                      double low, double high)
{
  const auto first = std::lower_bound(sorted.begin(), sorted.end(), low);
  const auto last = std::upper_bound(first, sorted.end(), high);
  return {static_cast<std::uint32_t>(first - sorted.begin()),
          static_cast<std::uint32_t>(last - sorted.begin())};
}

void Fringe::pointsInDisk(const Piece& piece, const std::array<std::size_t, 3>& p,
                          std::vector<std::size_t>& inside) const
{
  const Point2 a = lat_.point(p[0]), b = lat_.point(p[1]), c = lat_.point(p[2]);
  const SafeDisk disk = safeCircumdisk(a, b, c);
  std::uint32_t j0 = 0, j1 = lat_.ny; // rows [j0, j1)
  double reach = 0.0;
  if (disk.valid) {
    // Widened once more for the rounding of the row and column bounds below.
    reach =
        disk.radius * (1.0 + 1e-9) + 1e-12 * (std::fabs(disk.cx) + std::fabs(disk.cy));
    std::tie(j0, j1) = indicesWithin(lat_.ys, disk.cy - reach, disk.cy + reach);
  }
  for (std::uint32_t j = j0; j < j1; ++j) {
    // Only the row's present span: disks of triangles across large NODATA areas
    // reach far beyond it.
    std::uint32_t i0 = lat_.row_first[j], i1 = lat_.row_end[j];
    if (i0 >= i1)
      continue;
    if (disk.valid) {
      const double dy = lat_.ys[j] - disk.cy;
      const double h2 = reach * reach - dy * dy;
      if (h2 < 0.0)
        continue;
      const double h = std::sqrt(h2);
      if (lat_.xs[i0] > disk.cx + h || lat_.xs[i1 - 1] < disk.cx - h)
        continue;
      const auto within = indicesWithin(lat_.xs, disk.cx - h, disk.cx + h);
      i0 = std::max(i0, within.first);
      i1 = std::min(i1, within.second);
    }
    const std::size_t row = lat_.position(0, j);
    for (std::uint32_t i = i0; i < i1; ++i)
      if (lat_.present(row + i) && !inPiece(piece, row + i) &&
          incircle(a, b, c, {lat_.xs[i], lat_.ys[j]}) != Sign::NEGATIVE)
        inside.push_back(row + i);
  }
}

/// Pieces this small go through solveSmall first.
constexpr std::size_t SMALL_PIECE = 12;

bool Fringe::solveSmall(Piece& piece) const
{
  // The triangles of DT(I) are the triples whose circle is empty under the
  // perturbation: it decides every test (no three of them collinear with the fourth
  // off the line can tie), so this is the same set the ordinary path would return.
  const std::vector<std::size_t>& s = piece.own;
  std::vector<Point2> q(s.size());
  for (std::size_t k = 0; k < s.size(); ++k)
    q[k] = lat_.point(s[k]);
  std::vector<std::size_t> inside;
  piece.rounds = 1;
  for (std::size_t a = 0; a < s.size(); ++a)
    for (std::size_t b = a + 1; b < s.size(); ++b)
      for (std::size_t c = b + 1; c < s.size(); ++c) {
        const Sign o = orient2d(q[a], q[b], q[c]);
        if (o == Sign::ZERO)
          continue;
        const std::size_t c2 = o == Sign::POSITIVE ? c : b,
                          b2 = o == Sign::POSITIVE ? b : c;
        bool empty = true;
        for (std::size_t d = 0; d < s.size() && empty; ++d)
          empty = d == a || d == b2 || d == c2 ||
                  incirclePerturbed(q[a], q[b2], q[c2], q[d]) == Sign::NEGATIVE;
        const std::array<std::size_t, 3> p = {s[a], s[b2], s[c2]};
        if (!empty || isCellTriangle(p))
          continue;
        pointsInDisk(piece, p, inside);
        if (!inside.empty())
          return false;
        piece.found.push_back(
            {lat_.vertex_at[p[0]], lat_.vertex_at[p[1]], lat_.vertex_at[p[2]]});
      }
  return true;
}

bool Fringe::solveGap(Piece& piece) const
{
  // The piece is the 2 x 2 cells around a missing position m, its I the eight
  // neighbours of m (own is sorted: the row below, the two beside m, the row above).
  const std::vector<std::size_t>& o = piece.own;
  if (piece.cells != 4 || o.size() != 8)
    return false;
  const std::size_t nx = lat_.nx, p = o[0];
  if (p % nx + 2 >= nx || o[1] != p + 1 || o[2] != p + 2 || o[3] != p + nx ||
      o[4] != p + nx + 2 || o[5] != p + 2 * nx || o[6] != p + 2 * nx + 1 ||
      o[7] != p + 2 * nx + 2)
    return false;
  // The corner triangle of each of the four cells (its three present corners) has
  // the cell's circumcircle, the circle on the cell's diagonal: as for a complete
  // cell, every other lattice point lies strictly outside it, and m is missing, so it
  // is a Delaunay triangle of P. What they leave of the cells is the convex
  // quadrilateral (W, S, E, N) of m's neighbours along the axes; the Delaunay
  // triangles covering it have their vertices in it, so they are one of its two
  // splits, the one the perturbed in-circle test picks.
  const VertexId sw = lat_.vertex_at[o[0]], s = lat_.vertex_at[o[1]],
                 se = lat_.vertex_at[o[2]], w = lat_.vertex_at[o[3]],
                 e = lat_.vertex_at[o[4]], nw = lat_.vertex_at[o[5]],
                 n = lat_.vertex_at[o[6]], ne = lat_.vertex_at[o[7]];
  piece.found.push_back({sw, s, w});
  piece.found.push_back({s, se, e});
  piece.found.push_back({e, ne, n});
  piece.found.push_back({w, n, nw});
  if (incirclePerturbed(lat_.point(o[3]), lat_.point(o[1]), lat_.point(o[4]),
                        lat_.point(o[6])) == Sign::NEGATIVE) {
    piece.found.push_back({w, s, e}); // N outside the circle of (W, S, E)
    piece.found.push_back({w, e, n});
  } else {
    piece.found.push_back({w, s, n});
    piece.found.push_back({s, e, n});
  }
  piece.rounds = 1;
  piece.points = o.size();
  return true;
}

void Fringe::solve(Piece& piece) const
{
  if (solveGap(piece))
    return;
  if (piece.own.size() <= SMALL_PIECE) {
    // pointsInDisk counts the ring as outside here: the piece's S is its I alone.
    Piece alone;
    alone.label = piece.label;
    alone.s = piece.own;
    alone.own = piece.own;
    if (solveSmall(alone)) {
      piece.found = std::move(alone.found);
      piece.rounds = 1;
      piece.points = piece.own.size();
      return;
    }
  }
  // S of the piece: its I and their ring.
  for (const std::size_t p : piece.own)
    ring(p, piece.s);
  std::sort(piece.s.begin(), piece.s.end());
  piece.s.erase(std::unique(piece.s.begin(), piece.s.end()), piece.s.end());
  VtsOptions inner; // the ordinary path on the piece
  inner.lattice = false;
  inner.threads = 1;
  inner.check_output = options_.check_output;
  std::vector<double> xyz;
  std::vector<std::size_t> inside;
  for (;;) {
    ++piece.rounds;
    xyz.clear();
    std::vector<std::size_t> all;
    all.reserve(piece.s.size() + piece.added.size());
    std::merge(piece.s.begin(), piece.s.end(), piece.added.begin(), piece.added.end(),
               std::back_inserter(all));
    piece.points = all.size();
    for (const std::size_t p : all) {
      const Point2 q = mesh_.xy[lat_.vertex_at[p]];
      xyz.insert(xyz.end(), {q.x, q.y, 0.0});
    }
    VtsResult sub;
    const Status s = runVtsPipeline(xyz.data(), all.size(), inner, sub);
    if (s.code == StatusCode::ALL_COLLINEAR || s.code == StatusCode::TOO_FEW_POINTS) {
      piece.found.clear(); // no triangle has its three vertices in the piece
      return;
    }
    if (!s.ok()) {
      piece.status = Status::error(StatusCode::INTERNAL_ERROR,
                                   "lattice fast path: the triangulation of " +
                                       std::to_string(all.size()) +
                                       " fringe points failed: " + s.toString());
      return;
    }
    piece.stats.local += sub.diagnostics.local_searches;
    piece.stats.widened += sub.diagnostics.widened_searches;
    piece.stats.cells_visited += sub.diagnostics.cells_visited;
    piece.stats.points_tested += sub.diagnostics.points_tested;
    piece.found.clear();
    inside.clear();
    const std::vector<VertexId>& tri = sub.mesh.triangles;
    for (std::size_t t = 0; t < tri.size(); t += 3) {
      const std::array<std::size_t, 3> p = {all[sub.source_index[tri[t]]],
                                            all[sub.source_index[tri[t + 1]]],
                                            all[sub.source_index[tri[t + 2]]]};
      if (labelOf(p[0]) != piece.label || labelOf(p[1]) != piece.label ||
          labelOf(p[2]) != piece.label || isCellTriangle(p))
        continue; // another piece's, or not a candidate
      const std::size_t before = inside.size();
      pointsInDisk(piece, p, inside);
      if (inside.size() == before)
        piece.found.push_back(
            {lat_.vertex_at[p[0]], lat_.vertex_at[p[1]], lat_.vertex_at[p[2]]});
    }
    if (inside.empty())
      return;
    grow(piece, inside); // this round's tests all saw the same piece
  }
}

void Fringe::grow(Piece& piece, const std::vector<std::size_t>& inside) const
{
  std::vector<std::size_t> joining;
  for (const std::size_t q : inside)
    ring(q, joining);
  for (const std::size_t q : joining)
    if (!inPiece(piece, q))
      piece.added.push_back(q);
  std::sort(piece.added.begin(), piece.added.end());
  piece.added.erase(std::unique(piece.added.begin(), piece.added.end()),
                    piece.added.end());
}

/// Fringes with more points than this in I go piece by piece (parallel, one ordinary
/// triangulation each) instead of through one window: the window's gain is the
/// small files' fixed costs; beyond, it saves no time (raster 1e7, 140k points in I:
/// CPU 0.585-0.590 s piece by piece, 0.564-0.602 s in one window) and its arrays
/// (about 200 bytes a point of W) raised the peak by 0.9 bytes a raster point.
constexpr std::size_t ONE_WINDOW_MAX_POINTS = std::size_t{1} << 16;
/// solveInOneWindow's cell: this many times the points' extent (its super triangle
/// ten times that away), then, when a triangle of DT(W) was lost to the super
/// triangle (its circle reaches a corner: flat triangles along the hull; 1 of 228 on
/// west_bijou_gully at 1, none on the test rasters at 2), the second. The wider the
/// cell, the weaker the semi-static filters (raster 1e6: 26 M instructions in the
/// window at 1, 27 M at 2, 42 M at 64).
constexpr std::array<double, 2> WINDOW_WIDENING = {2.0, 64.0};

bool Fringe::emptyOutsideWindow(const std::array<std::size_t, 3>& p) const
{
  const Point2 a = lat_.point(p[0]), b = lat_.point(p[1]), c = lat_.point(p[2]);
  const SafeDisk disk = safeCircumdisk(a, b, c);
  // Widened once more for the rounding of the row and column bounds below.
  const double reach = disk.valid
                           ? disk.radius * (1.0 + 1e-9) +
                                 1e-12 * (std::fabs(disk.cx) + std::fabs(disk.cy))
                           : 0.0;
  // A point of P \ W of row j inside the circle.
  const auto inside = [&](std::uint32_t j) {
    std::uint32_t i0 = inner_first_[j], i1 = inner_end_[j];
    if (i0 >= i1)
      return false;
    if (disk.valid) {
      const double dy = lat_.ys[j] - disk.cy;
      const double h2 = reach * reach - dy * dy;
      // The row's span of P \ W too far from the centre (no square root).
      const double dx =
          std::max({0.0, lat_.xs[i0] - disk.cx, disk.cx - lat_.xs[i1 - 1]});
      if (h2 < 0.0 || dx * dx > h2)
        return false;
      const double h = std::sqrt(h2);
      const auto within = indicesWithin(lat_.xs, disk.cx - h, disk.cx + h);
      i0 = std::max(i0, within.first);
      i1 = std::min(i1, within.second);
    }
    const std::size_t row = lat_.position(0, j);
    for (std::uint32_t i = i0; i < i1; ++i)
      if (lat_.present(row + i) && !inWindow(i, j) &&
          incirclePerturbed(a, b, c, {lat_.xs[i], lat_.ys[j]}) == Sign::POSITIVE)
        return true;
    return false;
  };
  if (!disk.valid) { // a flat triangle: every row
    for (std::uint32_t j = 0; j < lat_.ny; ++j)
      if (inside(j))
        return false;
    return true;
  }
  const auto [j0, j1] = indicesWithin(lat_.ys, disk.cy - reach, disk.cy + reach);
  if (j0 >= j1)
    return true;
  // Blocks of ROW_BLOCK rows from the centre's outward (a triangle across complete
  // cells, not a Delaunay triangle, usually has a point near its circle's centre),
  // each skipped when the x range of its rows' spans of P \ W misses the disk over
  // its y range (large disks over NODATA: most of their rows).
  const auto centre = static_cast<std::uint32_t>(
      std::lower_bound(lat_.ys.begin() + j0, lat_.ys.begin() + j1, disk.cy) -
      lat_.ys.begin());
  const std::uint32_t first = j0 / ROW_BLOCK, last = (j1 - 1) / ROW_BLOCK,
                      mid = std::min(centre, j1 - 1) / ROW_BLOCK;
  for (std::uint32_t step = 0; step <= std::max(mid - first, last - mid); ++step)
    for (unsigned side = 0; side < 2; ++side) {
      if (side == 0 ? step > mid - first : (step == 0 || step > last - mid))
        continue;
      const std::uint32_t block = side == 0 ? mid - step : mid + step;
      const std::uint32_t r0 = std::max(j0, block * ROW_BLOCK),
                          r1 = std::min(j1, block * ROW_BLOCK + ROW_BLOCK);
      const double dy =
          std::max({0.0, lat_.ys[r0] - disk.cy, disk.cy - lat_.ys[r1 - 1]});
      const double dx =
          std::max({0.0, block_lo_[block] - disk.cx, disk.cx - block_hi_[block]});
      const double h2 = reach * reach - dy * dy;
      if (h2 < 0.0 || dx * dx > h2)
        continue;
      for (std::uint32_t j = r0; j < r1; ++j)
        if (inside(j))
          return false;
    }
  return true;
}

bool Fringe::solveInOneWindow(std::vector<Piece>& pieces, double widening)
{
  if (i_.size() < 3 || i_.size() > ONE_WINDOW_MAX_POINTS)
    return false;
  // W: I less the corners whose four axis neighbours are present (inWindow), by
  // their indices in i_.
  std::vector<std::uint32_t> w;
  std::vector<Point2> xy;
  w.reserve(i_.size());
  xy.reserve(i_.size());
  for (std::size_t k = 0; k < i_.size(); ++k) {
    const auto i = static_cast<std::uint32_t>(i_[k] % lat_.nx),
               j = static_cast<std::uint32_t>(i_[k] / lat_.nx);
    if (inWindow(i, j)) {
      w.push_back(static_cast<std::uint32_t>(k));
      xy.push_back(lat_.point(i_[k]));
    }
  }
  if (w.size() < 3)
    return false;
  CellGrid cells;
  std::vector<std::uint32_t> cell_order;
  if (!buildCellGrid(xy, 0.0, cells, cell_order, 1).ok())
    return false;
  // One cell far wider than the points (the super triangle far away: fewer DT(W)
  // triangles lost to it), its points in the cache blocks' order of the cells
  // above: multiples of 4, of 2, then the rest, rows in snake order.
  CellGrid grid;
  std::vector<std::uint32_t> order;
  order.reserve(xy.size());
  grid.points.reserve(xy.size());
  for (std::uint32_t stride = 4; stride >= 1; stride /= 2)
    for (std::uint32_t j = 0; j < cells.ny; ++j)
      for (std::uint32_t m = 0; m < cells.nx; ++m) {
        const std::uint32_t i = (j & 1u) == 0 ? m : cells.nx - 1 - m;
        if (i % stride != 0 || j % stride != 0 ||
            (stride < 4 && i % (2 * stride) == 0 && j % (2 * stride) == 0))
          continue;
        const CellId c = cells.cellId(i, j);
        for (std::uint32_t k = cells.start(c); k < cells.start(c + 1); ++k) {
          order.push_back(cell_order[k]);
          grid.points.push_back(cells.points[k]);
        }
      }
  const double extent =
      std::max(static_cast<double>(cells.nx), static_cast<double>(cells.ny)) *
      cells.cell_size;
  grid.cell_size = widening * extent;
  grid.inv_cell_size = 1.0 / grid.cell_size;
  grid.origin_x = cells.origin_x - 0.5 * (grid.cell_size - extent);
  grid.origin_y = cells.origin_y - 0.5 * (grid.cell_size - extent);
  grid.nx = grid.ny = 1;
  grid.cell_start = {0, static_cast<std::uint32_t>(grid.points.size())};
  detail::LocalDelaunay window;
  const detail::CellWindow all = {0, 1, 0, 1};
  if (!window.triangulate(grid, all, all))
    return false;
  // Each row's span of P \ W (the points emptyOutsideWindow looks for), from its ends
  // inward, and the blocks' x ranges of them.
  inner_first_.assign(lat_.ny, 0);
  inner_end_.assign(lat_.ny, 0);
  const std::uint32_t blocks = (lat_.ny + ROW_BLOCK - 1) / ROW_BLOCK;
  block_lo_.assign(blocks, std::numeric_limits<double>::infinity());
  block_hi_.assign(blocks, -std::numeric_limits<double>::infinity());
  for (std::uint32_t j = 0; j < lat_.ny; ++j) {
    const std::size_t row = lat_.position(0, j);
    const auto outside = [&](std::uint32_t i) {
      return lat_.present(row + i) && !inWindow(i, j);
    };
    std::uint32_t first = lat_.row_first[j], end = lat_.row_end[j];
    while (first < end && !outside(first))
      ++first;
    while (end > first && !outside(end - 1))
      --end;
    inner_first_[j] = first;
    inner_end_[j] = end;
    if (first < end) {
      block_lo_[j / ROW_BLOCK] = std::min(block_lo_[j / ROW_BLOCK], lat_.xs[first]);
      block_hi_[j / ROW_BLOCK] = std::max(block_hi_[j / ROW_BLOCK], lat_.xs[end - 1]);
    }
  }
  // Every fringe triangle of DT(P) but the three-corner ones has its vertices in one
  // piece's W, so it is a triangle of DT(W) (its circle is empty in P, hence in W).
  // Every triangle of real points here is one of DT(W) (its circle is empty of W and
  // of the super triangle); it is one of DT(P) when no point of P \ W is inside its
  // circle under the perturbation (the points of W are not): kept then, unless its
  // vertices are in different pieces (then it is not) or in one cell (a cell
  // triangle, or a three-corner one, emitted below). A DT(W) triangle lost to the
  // super triangle leaves the count short: triangulate() checks it.
  const std::int32_t* v = window.v.data();
  for (std::size_t t = 0; t < window.triangleCount(); ++t) {
    if (v[3 * t] < 3 || v[3 * t + 1] < 3 || v[3 * t + 2] < 3)
      continue; // a super triangle corner
    std::array<std::size_t, 3> k{};
    for (unsigned m = 0; m < 3; ++m)
      k[m] = w[order[window.ids[static_cast<std::size_t>(v[3 * t + m])]]];
    const std::uint32_t label = label_[k[0]];
    const std::array<std::size_t, 3> p = {i_[k[0]], i_[k[1]], i_[k[2]]};
    // Three corners of one cell: a cell triangle or one emitted below.
    if (label_[k[1]] != label || label_[k[2]] != label || pieces[label].rounds != 0 ||
        isOneCell(p) || !emptyOutsideWindow(p))
      continue;
    pieces[label].found.push_back(
        {lat_.vertex_at[p[0]], lat_.vertex_at[p[1]], lat_.vertex_at[p[2]]});
  }
  // The incomplete cells with three corners: their circle (the cell's) holds no
  // other lattice point (section 7, 1.), so the triangle of those corners is a
  // fringe triangle, CCW in the cell's corner order. Each is found once from its
  // corners in I: from its lower left one, or from its lower right one when the
  // lower left is missing.
  const auto threeCorners = [&](std::size_t a) {
    const std::array<std::size_t, 4> corner = {a, a + 1, a + 1 + lat_.nx, a + lat_.nx};
    std::array<VertexId, 4> id{};
    unsigned present = 0;
    for (unsigned m = 0; m < 4; ++m) {
      id[m] = lat_.vertex_at[corner[m]];
      present += id[m] != INVALID_ID ? 1 : 0;
    }
    if (present != 3)
      return;
    const unsigned missing = id[0] == INVALID_ID   ? 0
                             : id[1] == INVALID_ID ? 1
                             : id[2] == INVALID_ID ? 2
                                                   : 3;
    Piece& piece = pieces[labelOf(corner[(missing + 1) % 4])];
    if (piece.rounds == 0)
      piece.found.push_back(
          {id[(missing + 1) % 4], id[(missing + 2) % 4], id[(missing + 3) % 4]});
  };
  for (const std::size_t q : i_) {
    const auto i = static_cast<std::uint32_t>(q % lat_.nx),
               j = static_cast<std::uint32_t>(q / lat_.nx);
    if (j + 1 == lat_.ny)
      continue;
    if (i + 1 < lat_.nx)
      threeCorners(q);
    if (i > 0 && !lat_.present(q - 1))
      threeCorners(q - 1);
  }
  window_points_ = 0;
  for (Piece& piece : pieces)
    if (piece.rounds == 0) {
      piece.rounds = 1;
      piece.points = 0; // counted in window_points_
      window_points_ += piece.own.size();
    }
  return true;
}

Status Fringe::triangulate(std::vector<std::array<VertexId, 3>>& found,
                           Diagnostics& diag, std::size_t expected)
{
  std::vector<Piece> pieces;
  labelPieces(pieces);
  if (pieces.empty())
    return Status::success(); // every vertex has its star in complete cells
  // Small fringes: the gaps alone, the rest in one window; any piece it leaves (and
  // every piece when the count does not close up) goes through solve().
  bool one_window = false;
  if (options_.lattice_one_window && i_.size() <= ONE_WINDOW_MAX_POINTS) {
    for (Piece& piece : pieces)
      solveGap(piece);
    for (const double widening : WINDOW_WIDENING) {
      one_window = solveInOneWindow(pieces, widening);
      std::size_t count = 0;
      for (const Piece& piece : pieces)
        count += piece.found.size();
      if (one_window && count > expected) // each of them is proven: a bug
        return Status::error(StatusCode::INTERNAL_ERROR,
                             "lattice fast path: " + std::to_string(count) +
                                 " fringe triangles proven, " +
                                 std::to_string(expected) + " expected");
      if (one_window && count == expected)
        break;
      for (Piece& piece : pieces) // the window's pieces again
        if (piece.points == 0) {
          piece.found.clear();
          piece.rounds = 0;
        }
      one_window = false;
    }
  }
  // Pieces are independent: any thread order gives the same pieces' results.
  parallelChunks(threads_, pieces.size(),
                 [&](std::size_t begin, std::size_t end, unsigned) {
                   for (std::size_t k = begin; k < end; ++k)
                     if (pieces[k].rounds == 0)
                       solve(pieces[k]);
                 });
  for (Piece& piece : pieces) {
    if (!piece.status.ok())
      return piece.status;
    found.insert(found.end(), piece.found.begin(), piece.found.end());
    diag.local_searches += piece.stats.local;
    diag.widened_searches += piece.stats.widened;
    diag.cells_visited += piece.stats.cells_visited;
    diag.points_tested += piece.stats.points_tested;
    diag.lattice_fringe_points += piece.points;
    diag.lattice_fringe_rounds = std::max(diag.lattice_fringe_rounds, piece.rounds);
  }
  if (one_window) {
    diag.lattice_fringe_points += window_points_;
    for (const Piece& piece : pieces)
      diag.lattice_fringe_window += piece.points == 0 ? piece.found.size() : 0;
  }
  diag.lattice_fringe_pieces = pieces.size();
  return Status::success();
}

/// Pairs the open halfedges of the complete cells and the fringe's halfedges by
/// vertex pair; unpaired ones are hull edges (INVALID_ID, as they are on entry). An
/// open-addressing table of the vertex pairs: the second halfedge of a pair finds
/// the first; a third one, or two in the same direction, is not manifold.
Status pairHalfedges(const std::vector<VertexId>& triangles,
                     std::vector<HalfedgeId>& halfedges,
                     const std::vector<HalfedgeId>& open, std::size_t fringe_first)
{
  const std::size_t count = open.size() + (triangles.size() - 3 * fringe_first);
  std::size_t slots = 16;
  int shift = 60;
  while (slots < 2 * count) {
    slots *= 2;
    --shift;
  }
  struct Slot {
    std::uint64_t key; ///< (min vertex, max vertex) + 1; 0: empty
    HalfedgeId e;      ///< INVALID_ID once paired
  };
  std::vector<Slot> table(slots, Slot{0, INVALID_ID});
  const auto fail = [&](HalfedgeId e) {
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "lattice fast path: edge " + std::to_string(triangles[e]) +
                             "-" + std::to_string(triangles[nextHalfedge(e)]) +
                             " is not manifold");
  };
  const auto add = [&](HalfedgeId e) {
    const VertexId u = triangles[e], v = triangles[nextHalfedge(e)];
    // The key of (INVALID_ID, INVALID_ID) would wrap to 0; vertex ids are smaller.
    const std::uint64_t key =
        ((static_cast<std::uint64_t>(std::min(u, v)) << 32) | std::max(u, v)) + 1;
    for (auto h = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift);;
         h = (h + 1) & (slots - 1)) {
      Slot& slot = table[h];
      if (slot.key == 0) {
        slot = {key, e};
        return true;
      }
      if (slot.key == key) {
        if (slot.e == INVALID_ID || triangles[slot.e] == u)
          return false; // a third halfedge, or two the same way
        halfedges[slot.e] = e;
        halfedges[e] = slot.e;
        slot.e = INVALID_ID;
        return true;
      }
    }
  };
  for (const HalfedgeId e : open)
    if (!add(e))
      return fail(e);
  for (std::size_t e = 3 * fringe_first; e < triangles.size(); ++e)
    if (!add(static_cast<HalfedgeId>(e)))
      return fail(static_cast<HalfedgeId>(e));
  return Status::success();
}

} // namespace

Status triangulateLattice(const double* xyz, std::size_t n, const VtsOptions& options,
                          VtsResult& result, bool& handled)
{
  handled = false;
  Diagnostics& diag = result.diagnostics;
  Stopwatch watch;
  Lattice lat;
  VtsResult attempt;
  attempt.diagnostics = diag;
  if (!readLattice(xyz, n, options, lat, attempt))
    return Status::success();
  const unsigned threads = options.threads > 0 ? options.threads : allCores();
  rankCompleteCells(lat, threads);
  attempt.diagnostics.seconds_grid = watch.seconds();
  watch.restart();
  std::vector<VertexId> hull;
  if (!latticeHull(lat, hull).ok())
    return Status::success(); // all collinear: the ordinary path says so
  attempt.diagnostics.seconds_hull = watch.seconds();
  handled = true;
  result = std::move(attempt);
  result.hull = std::move(hull);
  diag.hull_vertices = result.hull.size();
  const std::size_t nv = result.mesh.vertexCount();
  if (Status s = checkTriangleCapacity(nv, result.hull.size()); !s.ok()) {
    result.mesh = TriangleMesh{};
    return s;
  }

  watch.restart();
  const std::size_t total = 2 * nv - result.hull.size() - 2;
  const std::size_t cell_triangles = 2 * lat.row_start.back();
  TriangleMesh& mesh = result.mesh;
  std::vector<HalfedgeId> open;
  std::vector<std::array<VertexId, 3>> fringe;
  {
    // Fringe first: its peak memory (the ordinary path on S) comes before the big
    // arrays exist.
    Fringe f(lat, mesh, options, threads);
    if (Status s = f.triangulate(fringe, diag, total - cell_triangles); !s.ok()) {
      result.mesh = TriangleMesh{};
      return s;
    }
  }
  if (cell_triangles + fringe.size() != total) {
    // Not expected (section 7 proves every fringe triangle lies in one piece): the
    // ordinary path decides. The tests check that this never happens.
    result = VtsResult{};
    result.diagnostics.points_in = n;
    handled = false;
    return Status::success();
  }
  emitCompleteCells(lat, threads, mesh.triangles, mesh.halfedges, open, 3 * total);
  // Fringe triangles in a canonical order: smallest vertex first, then sorted; their
  // twins come from pairHalfedges.
  for (std::array<VertexId, 3>& t : fringe)
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  std::sort(fringe.begin(), fringe.end());
  for (const std::array<VertexId, 3>& t : fringe)
    mesh.triangles.insert(mesh.triangles.end(), t.begin(), t.end());
  mesh.halfedges.resize(3 * total, INVALID_ID);
  if (Status s = pairHalfedges(mesh.triangles, mesh.halfedges, open, cell_triangles);
      !s.ok()) {
    result.mesh = TriangleMesh{};
    return s;
  }
  diag.triangles = mesh.triangleCount();
  diag.seconds_triangulate = watch.seconds();
  return Status::success();
}

} // namespace pcl_vts
