#include "grid_internals.h"
#include "release_memory.h"
#include "uninit_allocator.h"

#include <pcl_vts/core/grid_stage.h>
#include <pcl_vts/core/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bitset>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <type_traits>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pcl_vts {
namespace {

// Beyond this magnitude the search's floating-point disk bounds would overflow.
constexpr double MAX_ABS_COORDINATE = 1e60;
// Below this extent cell sizes and circle bounds would underflow.
constexpr double MIN_EXTENT = 1e-80;
// A band closes once it holds this many points or its next row would take it over
// this many cells: its points (24 bytes each, twice) and its cell counters stay in
// a core's cache while it is sorted. Any value gives the same grid.
constexpr std::size_t BAND_POINTS = 1u << 15;
constexpr std::size_t BAND_CELLS = 1u << 15;

/// CellGrid::column and row (the same rule, CellGrid::clampIndex) on local copies of
/// the grid's geometry: a loop that stores 32-bit counts would otherwise reload nx and
/// ny (such stores may alias them) and convert them to double again at each point.
struct CellLookup {
  double origin_x, origin_y, inv, columns, rows;
  std::uint32_t nx, ny;
  explicit CellLookup(const CellGrid& grid)
      : origin_x(grid.origin_x)
      , origin_y(grid.origin_y)
      , inv(grid.inv_cell_size)
      , columns(static_cast<double>(grid.nx))
      , rows(static_cast<double>(grid.ny))
      , nx(grid.nx)
      , ny(grid.ny)
  {}
  std::uint32_t column(double x) const
  {
    return CellGrid::clampIndex((x - origin_x) * inv, columns, nx);
  }
  std::uint32_t row(double y) const
  {
    return CellGrid::clampIndex((y - origin_y) * inv, rows, ny);
  }
  /// The cell of p in a band starting at row r0: (row(p.y) - r0) * nx + column(p.x).
  /// With SSE2 x and y in two lanes, the same difference and product, then clamped
  /// as max(t, 0) and min(t, n - 1) before the truncation: clampIndex's index for
  /// every t (NaN included: maxpd gives 0), without its two branches. The grid holds
  /// at most 2^30 cells, so every index fits cvttpd2dq's 32-bit lanes.
  std::uint32_t bandCell(const Point2& p, std::uint32_t r0) const
  {
#if defined(__SSE2__)
    const __m128d t =
        _mm_mul_pd(_mm_sub_pd(_mm_set_pd(p.y, p.x), _mm_set_pd(origin_y, origin_x)),
                   _mm_set1_pd(inv));
    const __m128d clamped = _mm_min_pd(_mm_max_pd(t, _mm_setzero_pd()),
                                       _mm_set_pd(rows - 1.0, columns - 1.0));
    const __m128i ij = _mm_cvttpd_epi32(clamped);
    const auto i = static_cast<std::uint32_t>(_mm_cvtsi128_si32(ij));
    const auto j = static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm_srli_si128(ij, 4)));
    return (j - r0) * nx + i;
#else
    return (row(p.y) - r0) * nx + column(p.x);
#endif
  }
};

/// The finite points: xyz itself, or a compacted copy when some were dropped.
struct Input {
  const double* xyz;
  const std::uint32_t* source; ///< input index per point; nullptr: the identity
  std::size_t count;
  double x(std::size_t k) const { return xyz[3 * k]; }
  double y(std::size_t k) const { return xyz[3 * k + 1]; }
  Point2 point(std::size_t k) const { return {xyz[3 * k], xyz[3 * k + 1]}; }
  std::uint32_t sourceOf(std::size_t k) const
  {
    return source != nullptr ? source[k] : static_cast<std::uint32_t>(k);
  }
};

/// The points and input indices staged in the grid's own slots by the band scatter
/// (GridBuilder::sortBand's records, Input's interface).
struct StagedSlots {
  const Point2* points;
  const std::uint32_t* source;
  Point2 point(std::size_t k) const { return points[k]; }
  std::uint32_t sourceOf(std::size_t k) const { return source[k]; }
};

/// One chunk's share of the first pass.
struct Scan {
  double xmin = std::numeric_limits<double>::infinity();
  double ymin = xmin, xmax = -xmin, ymax = -xmin;
  std::size_t finite = 0;
  std::size_t out_of_range = std::numeric_limits<std::size_t>::max(); ///< first one
};

/// The first pass over points [begin, end) of xyz, one by one.
Scan scanPoints(const double* xyz, std::size_t begin, std::size_t end)
{
  Scan s;
  for (std::size_t k = begin; k < end; ++k) {
    const double x = xyz[3 * k], y = xyz[3 * k + 1], h = xyz[3 * k + 2];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(h))
      continue;
    if (std::fabs(x) > MAX_ABS_COORDINATE || std::fabs(y) > MAX_ABS_COORDINATE) {
      s.out_of_range = k;
      break;
    }
    ++s.finite;
    s.xmin = std::min(s.xmin, x);
    s.xmax = std::max(s.xmax, x);
    s.ymin = std::min(s.ymin, y);
    s.ymax = std::max(s.ymax, y);
  }
  return s;
}

/// scanPoints without a branch a point: x and y in the two lanes of one register, the
/// bounds by minpd(p, low) = (p < low ? p : low), std::min(low, p)'s rule (a tie
/// keeps the first value met), maxpd likewise; a point with a non-finite coordinate or
/// |x| or |y| beyond MAX_ABS_COORDINATE only noted. When one was met the points are
/// scanned again one by one (scanPoints): the same Scan in every case.
Scan scanFinitePoints(const double* xyz, std::size_t begin, std::size_t end)
{
#if defined(__SSE2__)
  const double inf = std::numeric_limits<double>::infinity();
  __m128d low = _mm_set1_pd(inf), high = _mm_set1_pd(-inf);
  const __m128d magnitude =
      _mm_castsi128_pd(_mm_set1_epi64x(std::numeric_limits<std::int64_t>::max()));
  const __m128d limit = _mm_set1_pd(MAX_ABS_COORDINATE);
  __m128d beyond = _mm_setzero_pd();  // a lane all ones once |x| or |y| failed
  __m128d heights = _mm_setzero_pd(); // the sum of h - h: NaN once h is not finite
  for (std::size_t k = begin; k < end; ++k) {
    const __m128d p = _mm_loadu_pd(xyz + 3 * k);
    const __m128d h = _mm_load_sd(xyz + 3 * k + 2);
    low = _mm_min_pd(p, low);
    high = _mm_max_pd(p, high);
    beyond = _mm_or_pd(beyond, _mm_cmpnle_pd(_mm_and_pd(p, magnitude), limit));
    heights = _mm_add_sd(heights, _mm_sub_sd(h, h));
  }
  beyond = _mm_or_pd(beyond, _mm_cmpunord_pd(heights, heights)); // its high lane 0
  if (_mm_movemask_pd(beyond) != 0)
    return scanPoints(xyz, begin, end);
  Scan s;
  s.finite = end - begin;
  s.xmin = _mm_cvtsd_f64(low);
  s.ymin = _mm_cvtsd_f64(_mm_unpackhi_pd(low, low));
  s.xmax = _mm_cvtsd_f64(high);
  s.ymax = _mm_cvtsd_f64(_mm_unpackhi_pd(high, high));
  return s;
#else
  return scanPoints(xyz, begin, end);
#endif
}

/// Cells of up to this many points are sorted by insertion.
constexpr std::uint32_t INSERTION_SORT_MAX = 16;
static_assert(INSERTION_SORT_MAX <= CROWDED_CELL_POINTS, "no quadtree below it");

/// Sorts slots [first, last) of (points, record) lexicographically, ties by record
/// (records are in input order inside a band): buildCellGrid's order inside a cell.
void sortCell(Point2* points, std::uint32_t* source, std::uint32_t first,
              std::uint32_t last, std::vector<std::pair<Point2, std::uint32_t>>& tmp)
{
  const auto less = [](const Point2& p, std::uint32_t o, const Point2& q,
                       std::uint32_t oq) {
    return lexLess(p, q) || (p == q && o < oq);
  };
  if (last - first > INSERTION_SORT_MAX) {
    tmp.clear();
    for (std::uint32_t k = first; k < last; ++k)
      tmp.emplace_back(points[k], source[k]);
    std::sort(tmp.begin(), tmp.end(), [&](const auto& a, const auto& b) {
      return less(a.first, a.second, b.first, b.second);
    });
    for (std::uint32_t k = first; k < last; ++k) {
      points[k] = tmp[k - first].first;
      source[k] = tmp[k - first].second;
    }
    return;
  }
  for (std::uint32_t k = first + 1; k < last; ++k) {
    const Point2 p = points[k];
    const std::uint32_t o = source[k];
    std::uint32_t m = k;
    for (; m > first && less(p, o, points[m - 1], source[m - 1]); --m) {
      points[m] = points[m - 1];
      source[m] = source[m - 1];
    }
    points[m] = p;
    source[m] = o;
  }
}

/// sortCell for a cell of at most INSERTION_SORT_MAX points whose records ascend: an
/// insertion sort by XY alone (stable, so equal XY keep their records' order, as
/// sortCell's ties do). Returns whether two points have equal XY.
bool sortSmallCell(Point2* points, std::uint32_t* records, std::uint32_t first,
                   std::uint32_t last)
{
  for (std::uint32_t k = first + 1; k < last; ++k) {
    const Point2 p = points[k];
    const std::uint32_t o = records[k];
    std::uint32_t m = k;
    for (; m > first && lexLess(p, points[m - 1]); --m) {
      points[m] = points[m - 1];
      records[m] = records[m - 1];
    }
    points[m] = p;
    records[m] = o;
  }
  bool equal = false;
  for (std::uint32_t k = first + 1; k < last; ++k)
    equal |= points[k] == points[k - 1];
  return equal;
}

/// sortSmallCell for a cell of exactly S points (3 or 4): each point's place from
/// its comparisons with the others, without a branch, instead of the insertion's
/// shifts. Point j goes before point i (j < i, records ascending) when it is
/// lexicographically smaller or equal (the stable order), else after it; the places
/// are the counts of the points before each one, a permutation since this order is
/// total.
template <std::uint32_t S>
bool rankSmallCell(Point2* points, std::uint32_t* records, std::uint32_t first)
{
  Point2 p[S];
  std::uint32_t record[S];
  std::uint32_t place[S] = {};
  for (std::uint32_t i = 0; i < S; ++i) {
    p[i] = points[first + i];
    record[i] = records[first + i];
  }
  bool equal = false;
  for (std::uint32_t i = 1; i < S; ++i)
    for (std::uint32_t j = 0; j < i; ++j) {
      // As integers (GCC branches on the bools' | and &).
      const int same_x = static_cast<int>(p[j].x == p[i].x);
      const int before = static_cast<int>(p[j].x < p[i].x) |
                         (same_x & static_cast<int>(p[j].y <= p[i].y));
      equal |= (same_x & static_cast<int>(p[j].y == p[i].y)) != 0;
      place[i] += static_cast<std::uint32_t>(before);
      place[j] += static_cast<std::uint32_t>(1 - before);
    }
  for (std::uint32_t i = 0; i < S; ++i) {
    points[first + place[i]] = p[i];
    records[first + place[i]] = record[i];
  }
  return equal;
}

/// The band partition: bands of consecutive rows.
struct Bands {
  std::vector<std::uint32_t> first_row; ///< per band, then ny
  std::vector<std::uint32_t> of_row;    ///< band of each row
  std::vector<std::uint32_t> start;     ///< first slot per band, then the count
  std::size_t count() const { return first_row.size() - 1; }
};

/// What one band hands back.
struct BandResult {
  std::uint32_t distinct = 0;
  std::uint32_t occupied = 0; ///< its cells that hold a point
  std::vector<SubCell> nodes; ///< its quadtrees; first_child into this vector
  std::vector<std::pair<CellId, std::uint32_t>> roots; ///< crowded cell, its root
  /// Each point of a run of equal XY: its input index and its vertex (a slot of the
  /// band's range until finish() shifts it).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> merged;
};

/// Per-thread buffers of the band pass. A band's records are its slots of the grid's
/// arrays before the sort (the points and sources the scatter put there), numbered
/// from the band's first slot.
struct BandScratch {
  std::vector<std::uint32_t> count;
  // Resized without a fill: every record's entries are written before they are read.
  std::vector<std::uint32_t, detail::UninitAllocator<std::uint32_t>>
      cell; ///< per record: its cell
  std::vector<std::uint32_t, detail::UninitAllocator<std::uint32_t>>
      sources; ///< its input index
  std::vector<Point2, detail::UninitAllocator<Point2>>
      points; ///< the band's points sorted by cell
  std::vector<std::uint32_t, detail::UninitAllocator<std::uint32_t>>
      records; ///< and their records
  std::vector<std::pair<Point2, std::uint32_t>> sort;
  std::vector<std::uint32_t> slots, moved_sources, new_id;
  std::vector<Point2> moved;
};

/// Whether a sample of the points (every SAMPLE_STRIDE-th) says that the automatic
/// cell size `size` stays (refinedCellSize), so that the band sort may count the
/// occupied cells: the share of cells of SAMPLE_STRIDE times the area that hold a
/// sampled point estimates the share of cells of `size` that hold a point. A wrong
/// guess costs time (a second grid, or the count first), never a different grid.
bool sampleKeepsCellSize(const Input& in, double xmin, double ymin, double width,
                         double height, double size)
{
  constexpr std::size_t SAMPLE_STRIDE = 64;
  constexpr unsigned SAMPLE_SHIFT = 3; // 8 x 8 cells a sample cell
  const std::size_t cx = detail::occupancyColumns(width, size);
  const std::size_t cy = detail::occupancyColumns(height, size);
  const std::size_t sx = (cx >> SAMPLE_SHIFT) + 1, sy = (cy >> SAMPLE_SHIFT) + 1;
  std::vector<std::uint64_t> bits((sx * sy + 63) / 64, 0);
  std::size_t occupied = 0;
  const double inv = 1.0 / size;
  for (std::size_t k = 0; k < in.count; k += SAMPLE_STRIDE) {
    const std::size_t i =
        std::min(static_cast<std::size_t>((in.x(k) - xmin) * inv), cx - 1);
    const std::size_t j =
        std::min(static_cast<std::size_t>((in.y(k) - ymin) * inv), cy - 1);
    const std::size_t c = (j >> SAMPLE_SHIFT) * sx + (i >> SAMPLE_SHIFT);
    const std::uint64_t bit = std::uint64_t{1} << (c & 63);
    occupied += (bits[c >> 6] & bit) == 0 ? 1 : 0;
    bits[c >> 6] |= bit;
  }
  // The size stays while the occupied cells hold at most 2 * DEFAULT_POINTS_PER_CELL
  // points on average; guess so below 1.4 times that (a wrong "stays" costs more).
  const double cells = static_cast<double>(cx) * static_cast<double>(cy);
  const double expected =
      cells * static_cast<double>(occupied) / static_cast<double>(sx * sy);
  return static_cast<double>(in.count) <=
         expected * 2.0 * DEFAULT_POINTS_PER_CELL / 1.4;
}

class GridBuilder {
 public:
  GridBuilder(const double* xyz, DuplicateRule rule, unsigned threads, GridStage& stage,
              std::vector<VertexId>* input_to_vertex)
      : xyz_(xyz)
      , rule_(rule)
      , threads_(threads)
      , grid_(stage.grid)
      , stage_(stage)
      , input_to_vertex_(input_to_vertex)
  {}

  /// Counting sort by band (stable), then each band by cell.
  /// \param inputs the input's point count (input_to_vertex's size)
  /// \param rows points per row per chunk of usefulThreads(threads, in.count)
  ///        chunks, when the occupancy count already made them on this grid; else
  ///        empty
  /// \return the cells that hold a point
  std::size_t run(const Input& in, std::size_t inputs, std::vector<std::uint32_t> rows);

 private:
  void makeBands(const Input& in, unsigned chunks, std::vector<std::uint32_t>& rows,
                 std::vector<std::uint32_t>& chunk_offsets);
  /// \param staged the band's records from its first slot on (point(k), sourceOf(k)
  ///        for slot k): StagedSlots, or the Input itself when it is the only band
  template <typename Staged>
  void sortBand(std::size_t b, BandScratch& scratch, const Staged& staged);
  /// Folds the runs of equal XY of sorted slots [begin, end) of (points, records)
  /// into the grid's slots [out, ...): the new out. sources: the input index of each
  /// record; assign(record, v) for each record of a run of two or more: its record
  /// goes to vertex v.
  template <typename Assign>
  std::uint32_t mergeCell(const Point2* points, const std::uint32_t* records,
                          const std::uint32_t* sources, std::uint32_t begin,
                          std::uint32_t end, std::uint32_t out,
                          const Assign& assign) const;
  /// \param inputs the input's point count
  void finish(std::size_t inputs);

  const double* xyz_; ///< the input, for the heights of duplicates
  DuplicateRule rule_;
  unsigned threads_;
  CellGrid& grid_;
  GridStage& stage_;
  std::vector<VertexId>* input_to_vertex_; ///< nullptr: not built
  Bands bands_;
  unsigned workers_ = 1; ///< threads of the band sort
  std::vector<BandResult> results_;
};

void GridBuilder::makeBands(const Input& in, unsigned chunks,
                            std::vector<std::uint32_t>& rows,
                            std::vector<std::uint32_t>& chunk_offsets)
{
  const std::uint32_t ny = grid_.ny;
  Bands& bands = bands_;
  if (rows.empty() && in.count < BAND_POINTS &&
      std::size_t{grid_.nx} * ny <= BAND_CELLS) {
    // One band (it closes at neither limit below) whatever the rows hold: no count
    // (run() sorts it straight from the input, without the offsets).
    bands.of_row.assign(ny, 0);
    bands.first_row = {0, ny};
    bands.start = {0, static_cast<std::uint32_t>(in.count)};
    chunk_offsets.clear();
    return;
  }
  if (rows.empty()) { // points per row, per chunk
    rows.assign(static_cast<std::size_t>(chunks) * ny, 0);
    parallelChunks(chunks, in.count,
                   [&](std::size_t begin, std::size_t end, unsigned t) {
                     std::uint32_t* count = &rows[static_cast<std::size_t>(t) * ny];
                     const CellLookup lookup(grid_);
                     for (std::size_t k = begin; k < end; ++k)
                       ++count[lookup.row(in.y(k))];
                   });
  }
  // Greedy bands of consecutive rows.
  bands.of_row.resize(ny);
  bands.first_row.assign(1, 0);
  bands.start.assign(1, 0);
  std::size_t points = 0, total = 0;
  const std::size_t nx = grid_.nx;
  for (std::uint32_t r = 0; r < ny; ++r) {
    bands.of_row[r] = static_cast<std::uint32_t>(bands.first_row.size() - 1);
    for (unsigned t = 0; t < chunks; ++t)
      points += rows[static_cast<std::size_t>(t) * ny + r];
    const std::size_t band_rows = r + 1 - bands.first_row.back();
    if (r + 1 < ny && (points >= BAND_POINTS || (band_rows + 1) * nx > BAND_CELLS)) {
      bands.first_row.push_back(r + 1);
      total += points;
      bands.start.push_back(static_cast<std::uint32_t>(total));
      points = 0;
    }
  }
  bands.first_row.push_back(ny);
  bands.start.push_back(static_cast<std::uint32_t>(total + points));
  // Where each chunk's points of each band go: bands in order, chunks in order
  // inside a band, so that the scatter is stable.
  const std::size_t count = bands.count();
  chunk_offsets.assign(static_cast<std::size_t>(chunks) * count, 0);
  for (unsigned t = 0; t < chunks; ++t)
    for (std::uint32_t r = 0; r < ny; ++r)
      chunk_offsets[t * count + bands.of_row[r]] +=
          rows[static_cast<std::size_t>(t) * ny + r];
  for (std::size_t b = 0; b < count; ++b) {
    std::uint32_t at = bands.start[b];
    for (unsigned t = 0; t < chunks; ++t) {
      const std::uint32_t here = chunk_offsets[t * count + b];
      chunk_offsets[t * count + b] = at;
      at += here;
    }
  }
}

std::size_t GridBuilder::run(const Input& in, std::size_t inputs,
                             std::vector<std::uint32_t> rows)
{
  const std::size_t m = in.count;
  const unsigned chunks = usefulThreads(threads_, m);
  std::vector<std::uint32_t> offsets;
  makeBands(in, chunks, rows, offsets);
  std::vector<std::uint32_t>().swap(rows);
  const std::size_t band_count = bands_.count();
  // The output arrays, zero-filled (page faults and all) by up to two threads at
  // once: the points on one, the sources and cells on the other. The scatter below
  // stages each point and its input index in the slots of its band in the points and
  // the sources themselves: no other copy of the input (one band is sorted from the
  // input itself: no scatter). Each array faulted in a
  // chunk ahead of its fill (fillPopulated) instead of a trap per page.
  const unsigned fillers = std::min(chunks, 2u);
  runTeam(fillers, [&](unsigned w) {
    if (w == 0)
      detail::fillPopulated(grid_.points, m);
    if (w == fillers - 1) {
      detail::fillPopulated(stage_.source, m);
      detail::fillPopulated(grid_.cell_start, grid_.cellCount() + 1);
    }
  });
  results_.assign(band_count, BandResult{});
  startCellPyramid(grid_.nx, grid_.ny, stage_.pyramid); // the band sort marks cells
  if (band_count == 1) {
    // One band: its records are the input's points in order (what the scatter below
    // would stage, chunks in order), sorted straight from the input.
    workers_ = 1;
    BandScratch scratch;
    sortBand(0, scratch, in);
  } else {
    Point2* staged = grid_.points.data();
    std::uint32_t* staged_source = stage_.source.data();
    parallelChunks(chunks, m, [&](std::size_t begin, std::size_t end, unsigned t) {
      std::uint32_t* at = &offsets[t * band_count];
      const std::uint32_t* band_of_row = bands_.of_row.data();
      const CellLookup lookup(grid_);
      for (std::size_t k = begin; k < end; ++k) {
        const double x = in.x(k), y = in.y(k);
        const std::uint32_t record = at[band_of_row[lookup.row(y)]]++;
        staged[record] = {x, y};
        staged_source[record] = in.sourceOf(k);
      }
    });
    const unsigned workers =
        static_cast<unsigned>(std::min<std::size_t>(chunks, band_count));
    workers_ = workers;
    std::atomic<std::size_t> next{0};
    runTeam(workers, [&](unsigned) {
      BandScratch scratch;
      for (std::size_t b = next++; b < band_count; b = next++)
        sortBand(b, scratch, StagedSlots{staged, staged_source});
    });
  }
  std::size_t occupied = 0;
  for (const BandResult& result : results_)
    occupied += result.occupied;
  finish(inputs);
  return occupied;
}

template <typename Assign>
std::uint32_t GridBuilder::mergeCell(const Point2* points, const std::uint32_t* records,
                                     const std::uint32_t* sources, std::uint32_t begin,
                                     std::uint32_t end, std::uint32_t out,
                                     const Assign& assign) const
{
  Point2* grid_points = grid_.points.data();
  std::uint32_t* source = stage_.source.data();
  const auto z = [&](std::uint32_t k) {
    return xyz_[3 * std::size_t{sources[records[k]]} + 2];
  };
  const bool by_z =
      rule_ == DuplicateRule::LOWEST_Z || rule_ == DuplicateRule::HIGHEST_Z;
  const bool lowest = rule_ == DuplicateRule::LOWEST_Z;
  const bool map = input_to_vertex_ != nullptr;
  for (std::uint32_t k = begin; k < end;) {
    const Point2 p = points[k];
    std::uint32_t run_end = k + 1;
    // The representative, as mergeDuplicates picks it: the best z, ties to the
    // smaller input index. Records ascend along a run (they are in input order inside
    // a band, and the sort is stable): a tie keeps the earlier point, and without a z
    // rule the first point is the one.
    std::uint32_t best = k;
    if (run_end < end && points[run_end] == p) {
      double best_z = by_z ? z(k) : 0.0;
      for (; run_end < end && points[run_end] == p; ++run_end)
        if (by_z) {
          const double h = z(run_end);
          if (lowest ? h < best_z : h > best_z) {
            best = run_end;
            best_z = h;
          }
        }
      if (map)
        for (std::uint32_t q = k; q < run_end; ++q)
          assign(records[q], out);
    }
    grid_points[out] = p;
    source[out] = sources[records[best]];
    ++out;
    k = run_end;
  }
  return out;
}

template <typename Staged>
void GridBuilder::sortBand(std::size_t b, BandScratch& scratch, const Staged& staged)
{
  const std::uint32_t bs = bands_.start[b], be = bands_.start[b + 1];
  const std::uint32_t r0 = bands_.first_row[b];
  const std::size_t nx = grid_.nx;
  const std::size_t cells = (bands_.first_row[b + 1] - r0) * nx;
  const std::size_t c0 = r0 * nx;
  // Counting sort of the band's records (numbered from bs) by cell, stable, into the
  // thread's buffers (reused band after band, so they stay in cache); the records'
  // cells and sources are read first, as the grid's slots [bs, ...) are overwritten
  // below.
  const std::uint32_t n = be - bs;
  std::vector<std::uint32_t>& count = scratch.count;
  count.assign(cells + 1, 0);
  // Sorted from the input (the one band), the points go by cell straight into the
  // grid's own slots: nothing is staged there, and the cells below write each slot at
  // or before the ones they read (out <= begin), so no scratch copy is needed.
  constexpr bool in_place = std::is_same_v<Staged, Input>;
  if (scratch.cell.size() < n) {
    scratch.cell.resize(n);
    scratch.sources.resize(n);
    if (!in_place)
      scratch.points.resize(n);
    scratch.records.resize(n);
  }
  Point2* grid_points = grid_.points.data();
  std::uint32_t* source = stage_.source.data();
  std::uint32_t* cell = scratch.cell.data();
  std::uint32_t* sources = scratch.sources.data();
  const CellLookup lookup(grid_);
  for (std::uint32_t r = 0; r < n; ++r) {
    const Point2 p = staged.point(bs + r);
    cell[r] = lookup.bandCell(p, r0);
    sources[r] = staged.sourceOf(bs + r);
    ++count[cell[r] + 1];
  }
  // The cells' starts as if no point were merged (clustered input has several empty
  // cells a point: only the occupied ones are visited below).
  std::uint32_t* cell_start = grid_.cell_start.data() + c0;
  for (std::size_t c = 0; c < cells; ++c) {
    cell_start[c] = bs + count[c];
    count[c + 1] += count[c];
  }
  Point2* points = in_place ? grid_.points.data() + bs : scratch.points.data();
  std::uint32_t* slot = scratch.records.data();
  for (std::uint32_t r = 0; r < n; ++r) {
    const std::uint32_t at = count[cell[r]]++;
    points[at] = staged.point(bs + r);
    slot[at] = r;
  }
  // count[c] is now cell c's end. Each occupied cell, in order: sort, merge equal XY
  // into the grid's slots [out, ...) (written in order), subdivide when crowded. The
  // points of a merged run go to result.merged with their vertex (finish() builds
  // input_to_vertex from them); vertex ids are slots of the band's own range for now
  // (finish() shifts them down). Once
  // points were merged (out behind the sorted position), the starts of the cells up
  // to the next occupied one are rewritten.
  BandResult& result = results_[b];
  std::vector<std::pair<std::uint32_t, std::uint32_t>>& merged = result.merged;
  const bool map = input_to_vertex_ != nullptr;
  const auto vertex = [&merged, sources, map](std::uint32_t record, std::uint32_t v) {
    if (map)
      merged.emplace_back(sources[record], v);
  };
  // Each occupied cell also sets its bit of the pyramid's level 0 (the band's rows
  // are whole words of it: no word is shared with another band).
  CellPyramid::Level& level0 = stage_.pyramid.levels[0];
  // The staged points and sources of the band this thread likely sorts next (the
  // workers take the bands in turn) fetched a line a cell while this band's cells
  // are sorted, instead of read from memory when that band starts.
  const std::size_t ahead_band = std::min(b + workers_, bands_.count());
  const std::uint32_t ahead_first = bands_.start[ahead_band];
  const Point2* ahead = grid_points + ahead_first;
  const Point2* ahead_end =
      grid_points + bands_.start[std::min(ahead_band + 1, bands_.count())];
  constexpr std::ptrdiff_t POINTS_A_LINE = 64 / sizeof(Point2);
  std::uint32_t out = bs;
  std::size_t unset = 0;               // the first cell whose start may still be off
  std::size_t row = r0, row_first = 0; // the row of the cell met last, its first cell
  std::size_t c = 0;
  for (std::uint32_t begin = 0, end = 0; begin < n; begin = end, ++c) {
    while (count[c] == begin) // an empty cell (count[c] is its end)
      ++c;
    end = count[c];
    if (ahead < ahead_end) {
      const std::ptrdiff_t k = ahead - grid_points;
      __builtin_prefetch(ahead);
      if (((k - ahead_first) & (4 * POINTS_A_LINE - 1)) == 0) // 16 sources a line
        __builtin_prefetch(source + k);
      ahead += POINTS_A_LINE;
    }
    if (out != bs + begin)
      std::fill(cell_start + unset, cell_start + c + 1, out);
    unset = c + 1;
    for (; c >= row_first + nx; row_first += nx)
      ++row;
    const std::size_t column = c - row_first;
    level0.occupied[row * level0.row_words + (column >> 6)] |= std::uint64_t{1}
                                                               << (column & 63u);
    ++result.occupied;
    if (end - begin == 1) {
      grid_points[out] = points[begin];
      source[out] = sources[slot[begin]];
      ++out;
    } else if (end - begin == 2) { // sortSmallCell and mergeCell for two points
      const Point2 p = points[begin], q = points[begin + 1];
      const std::uint32_t rp = slot[begin], rq = slot[begin + 1]; // rp < rq
      if (p == q) {
        // mergeCell's representative: q only when its z is strictly better (a tie
        // goes to the smaller record, p's).
        std::uint32_t best = rp;
        if (rule_ == DuplicateRule::LOWEST_Z || rule_ == DuplicateRule::HIGHEST_Z) {
          const double zp = xyz_[3 * std::size_t{sources[rp]} + 2];
          const double zq = xyz_[3 * std::size_t{sources[rq]} + 2];
          if (rule_ == DuplicateRule::LOWEST_Z ? zq < zp : zq > zp)
            best = rq;
        }
        vertex(rp, out);
        vertex(rq, out);
        grid_points[out] = p;
        source[out] = sources[best];
        ++out;
      } else {
        const bool swap = lexLess(q, p);
        grid_points[out] = swap ? q : p;
        source[out] = sources[swap ? rq : rp];
        grid_points[out + 1] = swap ? p : q;
        source[out + 1] = sources[swap ? rp : rq];
        out += 2;
      }
    } else if (end - begin <= INSERTION_SORT_MAX) { // no quadtree
      const std::uint32_t size = end - begin;
      const bool equal = size == 3   ? rankSmallCell<3>(points, slot, begin)
                         : size == 4 ? rankSmallCell<4>(points, slot, begin)
                                     : sortSmallCell(points, slot, begin, end);
      if (equal) {
        out = mergeCell(points, slot, sources, begin, end, out, vertex);
      } else {
        for (std::uint32_t q = begin; q < end; ++q, ++out) {
          grid_points[out] = points[q];
          source[out] = sources[slot[q]];
        }
      }
    } else {
      sortCell(points, slot, begin, end, scratch.sort);
      const std::uint32_t first = out;
      const std::size_t merged_first = merged.size();
      out = mergeCell(points, slot, sources, begin, end, out, vertex);
      const std::uint32_t distinct = out - first;
      if (distinct > CROWDED_CELL_POINTS) { // its quadtree may move the vertices
        result.roots.emplace_back(static_cast<CellId>(c0 + c),
                                  static_cast<std::uint32_t>(result.nodes.size()));
        scratch.slots.resize(distinct);
        std::iota(scratch.slots.begin(), scratch.slots.end(), first);
        const auto i = static_cast<std::uint32_t>(c % nx);
        const auto j = static_cast<std::uint32_t>(r0 + c / nx);
        detail::subdivideCell(grid_, i, j, grid_points, scratch.slots.data(), first,
                              first, out, result.nodes);
        scratch.moved.resize(distinct);
        scratch.moved_sources.resize(distinct);
        scratch.new_id.resize(distinct);
        for (std::uint32_t q = 0; q < distinct; ++q) {
          const std::uint32_t old = scratch.slots[q] - first;
          scratch.moved[q] = grid_points[first + old];
          scratch.moved_sources[q] = source[first + old];
          scratch.new_id[old] = first + q;
        }
        std::copy(scratch.moved.begin(), scratch.moved.end(), grid_points + first);
        std::copy(scratch.moved_sources.begin(), scratch.moved_sources.end(),
                  source + first);
        for (std::size_t q = merged_first; q < merged.size(); ++q)
          merged[q].second = scratch.new_id[merged[q].second - first];
      }
    }
  }
  if (out != be)
    std::fill(cell_start + unset, cell_start + cells, out);
  result.distinct = out - bs;
}

void GridBuilder::finish(std::size_t inputs)
{
  const std::size_t band_count = bands_.count();
  const std::size_t m = bands_.start.back();
  // Where each band's vertices go, and how far they move down from their slots.
  std::vector<std::uint32_t> shift(band_count);
  std::uint32_t distinct = 0;
  for (std::size_t b = 0; b < band_count; ++b) {
    shift[b] = bands_.start[b] - distinct;
    distinct += results_[b].distinct;
  }
  Point2* points = grid_.points.data();
  std::uint32_t* source = stage_.source.data();
  const std::size_t nx = grid_.nx;
  if (distinct < m) {
    for (std::size_t b = 0; b < band_count; ++b)
      if (shift[b] > 0) { // moving down: in band order, nothing is overwritten early
        const std::uint32_t from = bands_.start[b], count = results_[b].distinct;
        std::memmove(points + from - shift[b], points + from, count * sizeof(Point2));
        std::memmove(source + from - shift[b], source + from,
                     count * sizeof(std::uint32_t));
      }
    parallelChunks(usefulThreads(threads_, grid_.cellCount()), band_count,
                   [&](std::size_t first, std::size_t last, unsigned) {
                     for (std::size_t b = first; b < last; ++b) {
                       if (shift[b] == 0) // the first band: no shift
                         continue;
                       for (std::size_t c = bands_.first_row[b] * nx;
                            c < bands_.first_row[b + 1] * nx; ++c)
                         grid_.cell_start[c] -= shift[b];
                     }
                   });
  }
  grid_.cell_start[grid_.cellCount()] = distinct;
  grid_.points.resize(distinct);
  stage_.source.resize(distinct);
  // Each input point's vertex, where points were merged: the inverse of the sources,
  // then the merged runs' points (else the caller has the inverse when needed).
  if (input_to_vertex_ != nullptr && distinct < m) {
    std::vector<VertexId>& map = *input_to_vertex_;
    map.clear();
    detail::fillPopulated(map, inputs, VertexId{INVALID_ID});
    parallelRanges(threads_, distinct, [&](std::size_t v0, std::size_t v1) {
      for (std::size_t v = v0; v < v1; ++v)
        map[source[v]] = static_cast<VertexId>(v);
    });
    for (std::size_t b = 0; b < band_count; ++b)
      for (const auto& [input, v] : results_[b].merged)
        map[input] = v - shift[b];
  }
  // The quadtrees, in cell order as subdivideCrowdedCells numbers them.
  CellSubdivision& sub = stage_.subdivision;
  sub = CellSubdivision{};
  for (std::size_t b = 0; b < band_count; ++b) {
    const BandResult& result = results_[b];
    if (result.roots.empty())
      continue;
    if (sub.root.empty())
      sub.root.assign(grid_.cellCount(), INVALID_ID);
    const auto base = static_cast<std::uint32_t>(sub.nodes.size());
    for (SubCell node : result.nodes) {
      node.begin -= shift[b];
      node.end -= shift[b];
      if (node.first_child != INVALID_ID)
        node.first_child += base;
      sub.nodes.push_back(node);
    }
    for (const auto& [cell, root] : result.roots)
      sub.root[cell] = base + root;
  }
  results_.clear();
}

} // namespace

Status buildGridStage(const double* xyz, std::size_t n, double cell_size,
                      DuplicateRule rule, unsigned threads, GridStage& stage,
                      std::vector<VertexId>& input_to_vertex, Diagnostics& diag)
{
  return buildGridStage(xyz, n, cell_size, rule, threads, stage, &input_to_vertex,
                        diag);
}

Status buildGridStage(const double* xyz, std::size_t n, double cell_size,
                      DuplicateRule rule, unsigned threads, GridStage& stage,
                      std::vector<VertexId>* input_to_vertex, Diagnostics& diag)
{
  stage = GridStage{};
  if (input_to_vertex != nullptr)
    input_to_vertex->clear();
  // First pass: the finite points' bounding box, non-finite ones counted, the first
  // coordinate out of range found. Chunks combine in order, as one loop would (a min
  // or max tie keeps the first value: -0.0 and +0.0 stay as a serial loop has them).
  const unsigned chunks = usefulThreads(threads, n);
  std::vector<Scan> scans(chunks);
  parallelChunks(chunks, n, [&](std::size_t begin, std::size_t end, unsigned t) {
    scans[t] = scanFinitePoints(xyz, begin, end);
  });
  Scan all;
  for (const Scan& s : scans) {
    if (s.out_of_range != std::numeric_limits<std::size_t>::max()) {
      const std::size_t k = s.out_of_range;
      return Status::error(
          StatusCode::COORDINATE_RANGE,
          "point " + std::to_string(k) + " has XY (" + formatValue(xyz[3 * k]) + ", " +
              formatValue(xyz[3 * k + 1]) + "), beyond +-" +
              formatValue(MAX_ABS_COORDINATE) + "; shift or rescale the coordinates");
    }
    all.finite += s.finite;
    all.xmin = std::min(all.xmin, s.xmin);
    all.xmax = std::max(all.xmax, s.xmax);
    all.ymin = std::min(all.ymin, s.ymin);
    all.ymax = std::max(all.ymax, s.ymax);
  }
  const std::size_t m = all.finite;
  diag.non_finite_dropped = n - m;
  if (m == 0)
    return Status::error(StatusCode::EMPTY_INPUT,
                         n == 0 ? std::string("the input has no points")
                                : "none of the " + std::to_string(n) +
                                      " input points has finite x, y and z");
  const double width = all.xmax - all.xmin, height = all.ymax - all.ymin;
  const double extent = std::max(width, height);
  if (extent > 0.0 && extent < MIN_EXTENT)
    return Status::error(StatusCode::COORDINATE_RANGE,
                         "the XY extent " + formatValue(extent) + " is below " +
                             formatValue(MIN_EXTENT) + "; rescale the coordinates");

  // The finite points: a compacted copy only when some were dropped.
  std::vector<double> kept_xyz;
  std::vector<std::uint32_t> kept_source;
  Input in{xyz, nullptr, m};
  if (m < n) {
    kept_xyz.resize(3 * m);
    kept_source.resize(m);
    std::vector<std::size_t> at(chunks, 0);
    for (unsigned t = 1; t < chunks; ++t)
      at[t] = at[t - 1] + scans[t - 1].finite;
    parallelChunks(chunks, n, [&](std::size_t begin, std::size_t end, unsigned t) {
      std::size_t out = at[t];
      for (std::size_t k = begin; k < end; ++k) {
        const double x = xyz[3 * k], y = xyz[3 * k + 1], h = xyz[3 * k + 2];
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(h))
          continue;
        std::copy(xyz + 3 * k, xyz + 3 * k + 3, kept_xyz.data() + 3 * out);
        kept_source[out++] = static_cast<std::uint32_t>(k);
      }
    });
    in = Input{kept_xyz.data(), kept_source.data(), m};
  }

  // The cell size: automatic, refined by a count of the occupied cells, or the one
  // asked for. The count (in parallel: one bit per cell per chunk, then or-ed) shares
  // its pass with the count of the points per row, the bands' histogram when the size
  // stays (the same rows as grid.row's). Where the size cannot change (a size asked
  // for, fewer than REFINE_MIN_POINTS points) or a sample says it stays, that pass
  // counts the rows alone and the band sort counts the occupied cells of the grid it
  // builds (the same cells); should they refine the size after all, the grid is
  // built again at the refined size: the same grid as the count first would give.
  CellGrid& grid = stage.grid;
  const double initial = detail::initialCellSize(cell_size, width, height, m);
  const bool automatic = cell_size == 0.0 && width > 0.0 && height > 0.0;
  const bool may_refine = automatic && m >= detail::REFINE_MIN_POINTS;
  bool count_first = may_refine && !sampleKeepsCellSize(in, all.xmin, all.ymin, width,
                                                        height, initial);
  for (;;) {
    double size = initial;
    std::vector<std::uint32_t> rows;
    std::size_t rows_ny = 0;
    // Fewer points than a band holds: the rows are counted only should the grid's
    // cells need several bands (makeBands).
    if (automatic && (count_first || m >= BAND_POINTS)) {
      const std::size_t cx = detail::occupancyColumns(width, size);
      const std::size_t cy = detail::occupancyColumns(height, size);
      const std::size_t words = count_first ? (cx * cy + 63) / 64 : 0;
      const unsigned parts = usefulThreads(threads, m);
      std::vector<std::vector<std::uint64_t>> bits(parts);
      rows.assign(parts * cy, 0);
      rows_ny = cy;
      const double inv = 1.0 / size, xmin = all.xmin, ymin = all.ymin;
      parallelChunks(parts, m, [&](std::size_t begin, std::size_t end, unsigned t) {
        std::uint32_t* row_count = &rows[t * cy];
        if (!count_first) {
          for (std::size_t k = begin; k < end; ++k)
            ++row_count[std::min(static_cast<std::size_t>((in.y(k) - ymin) * inv),
                                 cy - 1)];
          return;
        }
        std::vector<std::uint64_t>& mine = bits[t];
        mine.assign(words, 0);
        for (std::size_t k = begin; k < end; ++k) {
          const auto i =
              std::min(static_cast<std::size_t>((in.x(k) - xmin) * inv), cx - 1);
          const auto j =
              std::min(static_cast<std::size_t>((in.y(k) - ymin) * inv), cy - 1);
          const std::size_t c = j * cx + i;
          mine[c >> 6] |= std::uint64_t{1} << (c & 63);
          ++row_count[j];
        }
      });
      if (count_first) {
        std::size_t occupied = 0;
        for (std::size_t w = 0; w < words; ++w) {
          std::uint64_t word = 0;
          for (const auto& part : bits)
            word |= part[w];
          occupied += std::bitset<64>(word).count();
        }
        size = detail::refinedCellSize(width, height, m, size, occupied);
        if (size != initial)
          std::vector<std::uint32_t>().swap(rows);
      }
    }
    if (Status s =
            detail::setGridGeometry(all.xmin, all.ymin, width, height, m, size, grid);
        !s.ok())
      return s;
    if (grid.ny != rows_ny)
      std::vector<std::uint32_t>().swap(rows);
    const std::size_t occupied = GridBuilder(xyz, rule, threads, stage, input_to_vertex)
                                     .run(in, n, std::move(rows));
    if (!may_refine || count_first ||
        detail::refinedCellSize(width, height, m, initial, occupied) == initial)
      break;
    stage = GridStage{}; // the sample was wrong: count first
    if (input_to_vertex != nullptr)
      input_to_vertex->clear();
    count_first = true;
  }
  diag.duplicates_merged = m - grid.points.size();
  diag.distinct_points = grid.points.size();
  diag.cells = grid.cellCount();
  diag.cell_size = grid.cell_size;
  buildCellPyramidLevels(stage.pyramid, threads); // level 0 from the band sort
  return Status::success();
}

} // namespace pcl_vts
