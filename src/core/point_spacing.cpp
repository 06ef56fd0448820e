// Point spacing: median incident edge per vertex, then a one-ring median.
#include "cpu_features.h"
#include "post_pass_spacing.h"
#include "release_memory.h"

#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/point_spacing.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace pcl_vts {

namespace {

/// The compare-exchanges of Batcher's odd-even merge sort of N values (N a power of
/// two), as a table computed at compile time.
template <std::size_t N>
struct SortNetwork {
  static constexpr std::size_t size()
  {
    std::size_t count = 0;
    forEach([&](std::size_t, std::size_t) { ++count; });
    return count;
  }
  template <typename F>
  static constexpr void forEach(F&& f)
  {
    for (std::size_t p = 1; p < N; p <<= 1)
      for (std::size_t k = p; k >= 1; k >>= 1)
        for (std::size_t j = k % p; j + k < N; j += 2 * k)
          for (std::size_t i = 0; i < std::min(k, N - j - k); ++i)
            if ((i + j) / (2 * p) == (i + j + k) / (2 * p))
              f(i + j, i + j + k);
  }
  struct Pair {
    std::uint8_t lo = 0, hi = 0;
  };
  struct Table {
    Pair pairs[size()];
  };
  static constexpr Table table()
  {
    Table t{};
    std::size_t m = 0;
    forEach([&](std::size_t lo, std::size_t hi) {
      t.pairs[m].lo = static_cast<std::uint8_t>(lo);
      t.pairs[m].hi = static_cast<std::uint8_t>(hi);
      ++m;
    });
    return t;
  }
};

/// Sorts a[0..N) through the network: compare-exchanges as min/max, no
/// data-dependent branch (the comparisons of a vertex ring mispredict a sort).
template <std::size_t N>
void sortNetwork(double* a)
{
  static constexpr typename SortNetwork<N>::Table t = SortNetwork<N>::table();
  for (const auto& [lo, hi] : t.pairs) {
    const double low = std::min(a[lo], a[hi]);
    a[hi] = std::max(a[lo], a[hi]);
    a[lo] = low;
  }
}

/// The element at index size / 2 of values sorted, for 0 < size <= N and no NaN:
/// padded with +inf, which sorts after every value.
template <std::size_t N>
double smallMedian(const double* values, std::size_t size)
{
  double a[N];
  std::fill(std::copy(values, values + size, a), a + N,
            std::numeric_limits<double>::infinity());
  sortNetwork<N>(a);
  return a[size / 2];
}

/// The compare-exchanges (lo, hi) of the 12-comparator sorting network of six values
/// less those that do not reach index 3; then index 3 is the smaller of a[3], a[4].
constexpr std::uint8_t MEDIAN_OF_SIX[9][2] = {{0, 5}, {1, 3}, {2, 4}, {1, 2}, {3, 4},
                                              {0, 3}, {2, 5}, {2, 3}, {4, 5}};

/// The element at index 3 of six values sorted, no NaN, through MEDIAN_OF_SIX (the
/// usual vertex row, six edges, takes it instead of smallMedian<8>'s 19).
double medianOfSix(const double* values)
{
  double a[6];
  std::copy(values, values + 6, a);
  for (const auto& pair : MEDIAN_OF_SIX) {
    const double low = std::min(a[pair[0]], a[pair[1]]);
    a[pair[1]] = std::max(a[pair[0]], a[pair[1]]);
    a[pair[0]] = low;
  }
  return std::min(a[3], a[4]);
}

/// The element at index N / 2 of N values sorted, no NaN, through the compare-exchanges
/// (lo, hi) of an optimal sorting network of N values that reach that index (five:
/// 9, seven: 14, against the 19 of smallMedian<8>'s network).
template <std::size_t N, std::size_t M>
double networkMedian(const double* values, const std::uint8_t (&pairs)[M][2])
{
  double a[N];
  std::copy(values, values + N, a);
  for (const auto& pair : pairs) {
    const double low = std::min(a[pair[0]], a[pair[1]]);
    a[pair[1]] = std::max(a[pair[0]], a[pair[1]]);
    a[pair[0]] = low;
  }
  return a[N / 2];
}

constexpr std::uint8_t MEDIAN_OF_FIVE[9][2] = {{0, 3}, {1, 4}, {0, 2}, {1, 3}, {0, 1},
                                               {2, 4}, {1, 2}, {3, 4}, {2, 3}};
constexpr std::uint8_t MEDIAN_OF_SEVEN[14][2] = {{0, 6}, {2, 3}, {4, 5}, {0, 2}, {1, 4},
                                                 {3, 6}, {0, 1}, {2, 5}, {3, 4}, {1, 2},
                                                 {4, 6}, {2, 3}, {4, 5}, {3, 4}};

/// Upper median of values, reordering them (0 when empty).
double medianInPlace(std::vector<double>& values)
{
  if (values.empty())
    return 0.0;
  const std::size_t size = values.size();
  if (size <= 16 && std::none_of(values.begin(), values.end(),
                                 [](double v) { return std::isnan(v); }))
    return size <= 8 ? smallMedian<8>(values.data(), size)
                     : smallMedian<16>(values.data(), size);
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(size / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

std::uint64_t bitsOf(double value)
{
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

} // namespace

namespace detail {

Status checkCorners(const TriangleMesh& mesh)
{
  for (const VertexId v : mesh.triangles)
    if (v >= mesh.vertexCount())
      return Status::error(StatusCode::INVALID_PARAMETER,
                           "triangle corner " + std::to_string(v) +
                               " is not a vertex id (" +
                               std::to_string(mesh.vertexCount()) + " vertices)");
  return Status::success();
}

bool VertexRows::build(const TriangleMesh& mesh, std::vector<HalfedgeId>* boundary,
                       std::vector<double>* need, double edge_limit2)
{
  // A row entry per halfedge, two for a boundary one.
  if (boundary != nullptr)
    boundary->clear();
  offsets_.reset();
  ids_.reset();
  wide_entries_.clear();
  wide_rows_.clear();
  Built slotted = Built::NOT_SLOTTED;
  if (slots_allowed_)
    slotted = need != nullptr ? fillSlots<true>(mesh, boundary, need, edge_limit2)
                              : fillSlots<false>(mesh, boundary, need, edge_limit2);
  const bool built =
      slotted == Built::ROWS ||
      (slotted == Built::NOT_SLOTTED &&
       (2 * mesh.triangles.size() < std::numeric_limits<std::uint32_t>::max()
            ? fill(mesh, start32_, boundary, need, edge_limit2)
            : fill(mesh, start64_, boundary, need, edge_limit2)));
  slotted_ = slotted == Built::ROWS;
  if (!slotted_)
    first32_ = start32_.data();
  if (!built && boundary != nullptr)
    boundary->clear();
  return built;
}

namespace {

/// A count byte of the slotted rows: not a character type, so that its stores do not
/// alias every other object (GCC would load the scatter's values again after each).
enum class RowCount : std::uint8_t {};

/// An entry of a row past its VertexRows::SLOTS first: the vertex, its index in the
/// row's fill order, the 16-bit entry.
struct LongRowEntry {
  VertexId v;
  std::uint32_t j;
  std::int16_t entry;
};

/// Entry j of v's row, past the slot, into the side list. Out of line and cold,
/// taking its values by copy (see VertexRows::noteFar).
[[gnu::cold, gnu::noinline]] void
noteLongRow(std::vector<LongRowEntry>& list, VertexId v, unsigned j, std::int16_t entry)
{
  list.push_back({v, j, entry});
}

/// A count byte holds a row's size up to FULL_COUNT; the entries of a longer row
/// past it are counted in a side map (the convex hull's fans: a corner of a
/// lattice's ragged last row sees a whole row below it).
constexpr unsigned FULL_COUNT = 255;

/// The index in v's row of its next entry once its count byte is full: FULL_COUNT
/// plus the entries already past it (which `past` counts).
[[gnu::cold, gnu::noinline]] unsigned
nextPastFullCount(std::unordered_map<VertexId, std::uint32_t>& past, VertexId v)
{
  return FULL_COUNT + past[v]++;
}

/// The need slots of n vertices, all 0 (VertexRows::build's `need`), their pages
/// faulted in at once when the vector grows.
void zeroNeeds(std::vector<double>& need, std::size_t n)
{
  reserveDiscarding(need, n);
  need.assign(n, 0.0);
}

/// Vertex v's need slot (Clearance::slot) after its triangle `id` (in the high 32
/// bits) of need t_need: the larger need (the float bits of non-negative values
/// order as the values) and that triangle.
[[gnu::always_inline]] inline void raiseNeed(double* needs, VertexId v,
                                             std::uint64_t id, std::uint32_t t_need)
{
  std::uint64_t bits = 0;
  std::memcpy(&bits, needs + v, sizeof bits);
  bits = id | std::max(static_cast<std::uint32_t>(bits), t_need);
  std::memcpy(needs + v, &bits, sizeof bits);
}

} // namespace

template <bool NEED>
VertexRows::Built
VertexRows::fillSlots(const TriangleMesh& mesh, std::vector<HalfedgeId>* boundary,
                      [[maybe_unused]] std::vector<double>* need, double edge_limit2)
{
  const std::size_t n = mesh.vertexCount();
  const std::size_t corners = mesh.triangles.size();
  // The slots' entry indices and the starts in 32 bits.
  if (n == 0 || SLOTS * n + SLOTS >= std::numeric_limits<std::uint32_t>::max() ||
      2 * corners >= std::numeric_limits<std::uint32_t>::max())
    return Built::NOT_SLOTTED;
  const VertexId* corner = mesh.triangles.data();
  for (std::size_t e = corners - corners % 3; e < corners; ++e)
    if (corner[e] >= n)
      return Built::BAD_CORNER; // a corner past the last triangle
  const ScratchBlock lent = scratch_;
  // Vertex v's slot: entries SLOTS v to SLOTS v + SLOTS - 1, filled from the last;
  // count[v] entries so far (all of them, those past the slot in `long_rows`; past
  // FULL_COUNT, the rest in `past_full`).
  ScratchArray<std::int16_t> slots = scratchArray<std::int16_t>(SLOTS * n, scratch_);
  // The count bytes die with build: in the temporary memory when it holds them.
  ScratchArray<RowCount> bytes = scratchArray<RowCount>(n, temporary_);
  RowCount* const count = bytes.get();
  std::fill(count, count + n, RowCount{0});
  if constexpr (NEED)
    zeroNeeds(*need, n);
  std::vector<LongRowEntry> long_rows;
  std::unordered_map<VertexId, std::uint32_t> past_full; // entries past FULL_COUNT
  // As fill's: ids once more than one neighbour in 2048 is farther than 32767 ids.
  const std::size_t far_limit = corners / 2048;
  // The slots (and the needs, the points) a corner writes fetched AHEAD triangles
  // before (fill's distance).
  constexpr std::size_t AHEAD = 3 * 64;
  std::size_t open = 0;
  auto scatter = [&]() -> Built {
    double* const needs = NEED ? need->data() : nullptr;
    const Point2* const xy = mesh.xy.data();
    std::int16_t* const slot = slots.get();
    RowCount* const counts = count;
    const VertexId* const corner_at = corner;
    const HalfedgeId* const twin_at = mesh.halfedges.data();
    const std::size_t corner_count = corners, vertex_count = n;
    const double limit2 = edge_limit2;
    // Neighbour u into v's row: the 16-bit entry (FAR, listed, for a neighbour more
    // than 32767 ids away, by its slot position, v and j, until packed) into the
    // slot's next entry from its end, or the side list past SLOTS entries.
    bool stop = false;
    auto put = [&](VertexId v, VertexId u) __attribute__((always_inline))
    {
      auto j = static_cast<unsigned>(counts[v]);
      if (__builtin_expect(j < FULL_COUNT, 1))
        counts[v] = static_cast<RowCount>(j + 1);
      else
        j = nextPastFullCount(past_full, v);
      constexpr std::int64_t NEAR = std::numeric_limits<std::int16_t>::max();
      const std::int64_t offset =
          static_cast<std::int64_t>(u) - static_cast<std::int64_t>(v);
      std::int16_t entry = static_cast<std::int16_t>(offset);
      if (__builtin_expect(static_cast<std::uint64_t>(offset + NEAR) >
                               static_cast<std::uint64_t>(2 * NEAR),
                           0)) {
        entry = FAR;
        // Listed by its place in the first 256 (8 bits); past them, the counting sort.
        stop = stop || j > FULL_COUNT ||
               !noteFar((std::size_t{v} << 8) | j, v, u, far_limit);
      }
      if (__builtin_expect(j < SLOTS, 1))
        slot[SLOTS * std::size_t{v} + (SLOTS - 1 - j)] = entry;
      else
        noteLongRow(long_rows, v, j, entry);
    };
    // Triangle t (its corners from e, checked): its entries, and its need (t_need)
    // into its corners' slots.
    // Far enough from the end (AHEAD), the fetch needs no test.
    auto triangle = [&](auto far_from_end, std::size_t e, std::size_t t,
                        [[maybe_unused]] std::uint32_t t_need)
        __attribute__((always_inline))
    {
      if (decltype(far_from_end)::value || e + AHEAD + 2 < corner_count) {
        const VertexId pa = corner_at[e + AHEAD], pb = corner_at[e + AHEAD + 1],
                       pc = corner_at[e + AHEAD + 2];
        __builtin_prefetch(slot + SLOTS * std::size_t{pa}, 1);
        __builtin_prefetch(slot + SLOTS * std::size_t{pb}, 1);
        __builtin_prefetch(slot + SLOTS * std::size_t{pc}, 1);
        __builtin_prefetch(counts + pa, 1);
        __builtin_prefetch(counts + pb, 1);
        __builtin_prefetch(counts + pc, 1);
        if constexpr (NEED) {
          __builtin_prefetch(needs + pa, 1);
          __builtin_prefetch(needs + pb, 1);
          __builtin_prefetch(needs + pc, 1);
          __builtin_prefetch(xy + pa);
          __builtin_prefetch(xy + pb);
          __builtin_prefetch(xy + pc);
        }
      }
      const VertexId a = corner_at[e], b = corner_at[e + 1], c = corner_at[e + 2];
      // INVALID_ID is the largest id: a triangle has a boundary edge when the
      // largest of its twins is INVALID_ID (the twins themselves read again then).
      if (__builtin_expect(std::max(std::max(twin_at[e], twin_at[e + 1]),
                                    twin_at[e + 2]) != INVALID_ID,
                           1)) {
        put(a, b);
        put(b, c);
        put(c, a);
      } else {
        // Boundary edges, seen from one side only: an entry for each end, and into
        // the boundary list in increasing order.
        const HalfedgeId ta = twin_at[e], tb = twin_at[e + 1], tc = twin_at[e + 2];
        put(a, b);
        if (ta == INVALID_ID)
          put(b, a);
        put(b, c);
        if (tb == INVALID_ID)
          put(c, b);
        put(c, a);
        if (tc == INVALID_ID)
          put(a, c);
        for (std::size_t k = e; k < e + 3; ++k)
          if (twin_at[k] == INVALID_ID) {
            ++open;
            if (boundary != nullptr)
              boundary->push_back(static_cast<HalfedgeId>(k));
          }
      }
      if constexpr (NEED) {
        const std::uint64_t id = std::uint64_t{t} << 32;
        raiseNeed(needs, a, id, t_need);
        raiseNeed(needs, b, id, t_need);
        raiseNeed(needs, c, id, t_need);
      }
    };
    auto bad = [&](std::size_t e, std::size_t corners_here) {
      VertexId most = 0;
      for (std::size_t k = e; k < e + corners_here; ++k)
        most = std::max(most, corner_at[k]);
      return most >= vertex_count;
    };
    std::size_t e = 0, t = 0;
    if constexpr (NEED) {
      // Two triangles' needs at once (Clearance::roundedUpNeeds: the same figures),
      // the triangles still entered one after the other.
      // The pairs whose fetches lie before the end, then the others.
      auto pairs = [&](auto far_from_end, std::size_t end)
          __attribute__((always_inline))
      {
        for (; e + 5 < end; e += 6, t += 2) {
          if (bad(e, 6))
            return false;
          const std::uint64_t two = Clearance::roundedUpNeeds(
              xy[corner_at[e]], xy[corner_at[e + 1]], xy[corner_at[e + 2]],
              xy[corner_at[e + 3]], xy[corner_at[e + 4]], xy[corner_at[e + 5]], limit2);
          triangle(far_from_end, e, t, static_cast<std::uint32_t>(two));
          triangle(far_from_end, e + 3, t + 1, static_cast<std::uint32_t>(two >> 32));
          if (__builtin_expect(stop, 0))
            return false;
        }
        return true;
      };
      if (!pairs(std::true_type{},
                 corner_count > AHEAD + 3 ? corner_count - AHEAD - 3 : 0) ||
          !pairs(std::false_type{}, corner_count))
        return stop ? Built::NOT_SLOTTED : Built::BAD_CORNER;
    }
    for (; e + 2 < corner_count; e += 3, ++t) {
      if (bad(e, 3))
        return Built::BAD_CORNER;
      std::uint32_t t_need = 0;
      if constexpr (NEED)
        t_need = Clearance::roundedUp(Clearance::need(
            xy[corner_at[e]], xy[corner_at[e + 1]], xy[corner_at[e + 2]], limit2));
      triangle(std::false_type{}, e, t, t_need);
      if (__builtin_expect(stop, 0))
        return Built::NOT_SLOTTED;
    }
    return Built::ROWS;
  };
  const Built scattered = scatter();
  if (scattered != Built::ROWS) {
    // Nothing kept: fill starts again from the lent scratch (or stops at the bad
    // corner).
    slots.reset();
    scratch_ = lent;
    wide_entries_.clear();
    wide_rows_.clear();
    if (boundary != nullptr)
      boundary->clear();
    return scattered;
  }
  // Row v's size: its count byte, and for a full one the entries counted past it.
  const auto rowSize = [&](std::size_t v) -> std::size_t {
    const auto size = static_cast<std::size_t>(count[v]);
    if (__builtin_expect(size < FULL_COUNT, 1))
      return size;
    const auto more = past_full.find(static_cast<VertexId>(v));
    return size + (more != past_full.end() ? more->second : 0);
  };
  // The packing: row v is the last rowSize(v) entries of its slot (at most SLOTS),
  // after its entries from the side list, at the sum of the rows before it. Its
  // slot's SLOTS entries are moved as one block, read from where the row's slot
  // entries start (so past them lie the next slot's first entries, overwritten by
  // the next row), written where they go: in place while that block ends before
  // the next slot starts (a row's packed start is mostly below its slot's: rows
  // average about 6 entries), else into an array of its own from there on.
  const std::size_t total = corners + open;
  std::vector<std::size_t>().swap(start64_); // 32-bit starts
  std::int16_t* const slot = slots.get();
  std::int16_t* row = slot; // where the rows go
  ScratchArray<std::int16_t> own_rows;
  std::size_t at = 0; // the sum of the rows so far
  auto block = [&](std::size_t v, std::size_t to) {
    std::int16_t entries[SLOTS];
    const std::size_t in_slot =
        std::min<std::size_t>(static_cast<std::size_t>(count[v]), SLOTS);
    std::memcpy(entries, slot + SLOTS * v + (SLOTS - in_slot), sizeof entries);
    std::memcpy(row + to, entries, sizeof entries);
  };
  std::size_t v = 0;
  for (; v + 1 < n; ++v) {
    const std::size_t size = rowSize(v);
    const std::size_t in_slot = std::min<std::size_t>(size, SLOTS);
    const std::size_t to = at + size - in_slot; // the slot's entries' place
    if (__builtin_expect(row == slot && to > SLOTS * v, 0)) {
      // The block would overwrite the next slot: the rows in an array of their own
      // (SLOTS entries past the last row for the last block).
      own_rows = scratchArray<std::int16_t>(total + SLOTS, scratch_);
      std::memcpy(own_rows.get(), slot, at * sizeof(std::int16_t));
      row = own_rows.get();
    }
    block(v, to);
    at += size;
  }
  { // the last row: its slot's entries alone (no slot follows it)
    const std::size_t size = rowSize(v);
    const std::size_t in_slot = std::min<std::size_t>(size, SLOTS);
    std::memmove(row + at + size - in_slot, slot + SLOTS * v + (SLOTS - in_slot),
                 in_slot * sizeof(std::int16_t));
    at += size;
  }
  // The starts, summed from the count bytes: past the packed rows in the slots'
  // array when they fit there (resident pages: the slots were written; the pack
  // wrote no further than SLOTS entries past the rows), else an array of their own.
  std::uint32_t* first = nullptr;
  if (row == slot) {
    const auto past_rows = reinterpret_cast<std::uintptr_t>(slot + total + SLOTS);
    const std::uintptr_t aligned = (past_rows + alignof(std::uint32_t) - 1) &
                                   ~std::uintptr_t{alignof(std::uint32_t) - 1};
    const auto slots_end = reinterpret_cast<std::uintptr_t>(slot + SLOTS * n);
    if (aligned <= slots_end && (slots_end - aligned) / sizeof(std::uint32_t) >= n + 1)
      first = std::uninitialized_default_construct_n(
                  reinterpret_cast<std::uint32_t*>(aligned), n + 1) -
              (n + 1);
  }
  if (first == nullptr) {
    reserveDiscarding(start32_, n + 1);
    start32_.resize(n + 1);
    first = start32_.data();
  } else
    std::vector<std::uint32_t>().swap(start32_);
  std::size_t sum = 0;
  for (std::size_t u = 0; u < n; ++u) {
    first[u] = static_cast<std::uint32_t>(sum);
    sum += rowSize(u);
  }
  first[n] = static_cast<std::uint32_t>(sum);
  first32_ = first;
  // The entries past the slots, and the far neighbours' positions: entry j of v's
  // fill order is at its row's end less j + 1.
  for (const LongRowEntry& extra : long_rows)
    row[first[extra.v + 1] - 1 - extra.j] = extra.entry;
  for (auto& [k, u] : wide_entries_) {
    const std::size_t w = k >> 8, j = k & 255;
    k = first[w + 1] - 1 - j;
  }
  std::sort(wide_entries_.begin(), wide_entries_.end());
  std::sort(wide_rows_.begin(), wide_rows_.end());
  wide_rows_.erase(std::unique(wide_rows_.begin(), wide_rows_.end()), wide_rows_.end());
  offsets_ = row == slot ? std::move(slots) : std::move(own_rows);
  return Built::ROWS;
}

template <typename Index>
bool VertexRows::fill(const TriangleMesh& mesh, std::vector<Index>& start,
                      std::vector<HalfedgeId>* boundary, std::vector<double>* need,
                      double edge_limit2)
{
  const std::size_t n = mesh.vertexCount();
  const std::size_t corners = mesh.triangles.size();
  // Counting sort of directed edges (both directions of a boundary edge): start[v]
  // counts row v, then holds its end, and the scatter moves it back to its
  // beginning. A row's order does not matter: only its medians are read.
  // Per triangle, its three halfedges at once (no remainder by 3 per halfedge).
  detail::reserveDiscarding(start, n + 1);
  const VertexId* corner = mesh.triangles.data();
  const HalfedgeId* twin = mesh.halfedges.data();
  // The counts first in bytes, a quarter of the starts' cache footprint (a
  // triangle's corners are far apart: the increments are random accesses), summed
  // into the starts; a count that wrapped past 255 shows in the total, and the
  // counting is done again in the starts.
  std::unique_ptr<std::uint8_t[]> bytes(new std::uint8_t[n]);
  std::uint8_t* count = bytes.get();
  detail::populatePages(count, count + n);
  std::fill(count, count + n, std::uint8_t{0});
  std::size_t open = 0;
  for (std::size_t e = corners - corners % 3; e < corners; ++e)
    if (corner[e] >= n)
      return false; // a corner past the last triangle (not counted)
  // A bit per triangle with an edge without twin: the scatter reads the twins of
  // those alone (a 64th of the twins' bytes otherwise streamed again).
  std::vector<std::uint64_t> open_triangles((corners / 3 + 63) / 64, 0);
  for (std::size_t e = 0; e + 2 < corners; e += 3) {
    const VertexId a = corner[e], b = corner[e + 1], c = corner[e + 2];
    if (std::max(a, std::max(b, c)) >= n)
      return false; // the corners checked here, not in a pass of their own
    ++count[a];
    ++count[b];
    ++count[c];
    if (twin[e] == INVALID_ID || twin[e + 1] == INVALID_ID ||
        twin[e + 2] == INVALID_ID) {
      open_triangles[e / 3 / 64] |= std::uint64_t{1} << (e / 3 % 64);
      for (std::size_t k = e; k < e + 3; ++k)
        if (twin[k] == INVALID_ID) { // boundary edge: seen from one side only
          ++count[corner[nextHalfedge(static_cast<HalfedgeId>(k))]];
          ++open;
          if (boundary != nullptr)
            boundary->push_back(static_cast<HalfedgeId>(k));
        }
    }
  }
  start.resize(n + 1);
  std::size_t sum = 0;
  for (std::size_t v = 0; v < n; ++v) {
    sum += count[v];
    start[v] = static_cast<Index>(sum);
  }
  bytes.reset();
  // The ends of the rows counted in full width (a byte count wrapped, or the
  // scatter of 16-bit entries gave up: the starts are then moved).
  auto count_in_full = [&] {
    start.assign(n + 1, 0);
    for (std::size_t e = 0; e < corners; ++e) {
      ++start[corner[e]];
      if (twin[e] == INVALID_ID)
        ++start[corner[nextHalfedge(static_cast<HalfedgeId>(e))]];
    }
    for (std::size_t v = 1; v < n; ++v)
      start[v] += start[v - 1];
  };
  if (sum != corners + open)
    count_in_full();
  const Index total = n > 0 ? start[n - 1] : 0;
  // The rows written by a triangle lie far apart: each corner's next entry is
  // fetched AHEAD triangles before (the scatter otherwise waits on the writes'
  // cache misses; jittered 1e6: 16 -> 11 ms).
  constexpr std::size_t AHEAD = 3 * 64;
  // 16-bit entries first; ids when more than one neighbour in 2048 is farther than
  // 32767 ids (the starts counted again, the needs from zero).
  const std::size_t far_limit = corners / 2048;
  auto scatter = [&](auto with_need, auto* row) {
    constexpr bool NEED = decltype(with_need)::value;
    double* needs = NEED ? need->data() : nullptr;
    const Point2* xy = mesh.xy.data();
    const std::uint64_t* open_bits = open_triangles.data();
    Index* first = start.data();
    // The captured arrays, count and limit as locals: the needs' stores (memcpy)
    // may alias anything, and the captured ones would be loaded again after each.
    const VertexId* const corner_at = corner;
    const HalfedgeId* const twin_at = twin;
    const std::size_t corner_count = corners;
    const double limit2 = edge_limit2;
    // Neighbour u into v's row (its next slot from the end). The 16-bit entries
    // give up past far_limit farther neighbours (ids in no spatial order).
    bool given_up = false;
    auto put = [&](VertexId v, VertexId u) __attribute__((always_inline))
    {
      using Entry = std::remove_pointer_t<decltype(row)>;
      const Index k = --first[v];
      if constexpr (std::is_same_v<Entry, VertexId>)
        row[k] = u;
      else {
        constexpr std::int64_t NEAR = std::numeric_limits<std::int16_t>::max();
        const std::int64_t offset =
            static_cast<std::int64_t>(u) - static_cast<std::int64_t>(v);
        if (__builtin_expect(static_cast<std::uint64_t>(offset + NEAR) <=
                                 static_cast<std::uint64_t>(2 * NEAR),
                             1))
          row[k] = static_cast<Entry>(offset);
        else {
          row[k] = FAR;
          given_up = given_up || !noteFar(k, v, u, far_limit);
        }
      }
    };
    // Triangle t (its corners from e): its entries, and its need (t_need) into its
    // corners' slots. It and put always inlined (GCC left put a call otherwise).
    auto triangle = [&](std::size_t e, std::size_t t,
                        [[maybe_unused]] std::uint32_t t_need)
        __attribute__((always_inline))
    {
      if (e + AHEAD + 2 < corner_count) {
        const VertexId pa = corner_at[e + AHEAD], pb = corner_at[e + AHEAD + 1],
                       pc = corner_at[e + AHEAD + 2];
        __builtin_prefetch(row + first[pa], 1);
        __builtin_prefetch(row + first[pb], 1);
        __builtin_prefetch(row + first[pc], 1);
        if constexpr (NEED) {
          __builtin_prefetch(needs + pa, 1);
          __builtin_prefetch(needs + pb, 1);
          __builtin_prefetch(needs + pc, 1);
          __builtin_prefetch(xy + pa);
          __builtin_prefetch(xy + pb);
          __builtin_prefetch(xy + pc);
        }
      }
      const VertexId a = corner_at[e], b = corner_at[e + 1], c = corner_at[e + 2];
      if (((open_bits[t / 64] >> (t % 64)) & 1u) == 0) {
        put(a, b);
        put(b, c);
        put(c, a);
      } else {
        put(a, b);
        if (twin_at[e] == INVALID_ID)
          put(b, a);
        put(b, c);
        if (twin_at[e + 1] == INVALID_ID)
          put(c, b);
        put(c, a);
        if (twin_at[e + 2] == INVALID_ID)
          put(a, c);
      }
      if constexpr (NEED) {
        const std::uint64_t id = std::uint64_t{t} << 32;
        raiseNeed(needs, a, id, t_need);
        raiseNeed(needs, b, id, t_need);
        raiseNeed(needs, c, id, t_need);
      }
    };
    std::size_t e = 0, t = 0;
    if constexpr (NEED) {
      // Two triangles' needs at once (Clearance::roundedUpNeeds: the same figures),
      // the triangles still entered one after the other.
      for (; e + 5 < corner_count; e += 6, t += 2) {
        const std::uint64_t two = Clearance::roundedUpNeeds(
            xy[corner_at[e]], xy[corner_at[e + 1]], xy[corner_at[e + 2]],
            xy[corner_at[e + 3]], xy[corner_at[e + 4]], xy[corner_at[e + 5]], limit2);
        triangle(e, t, static_cast<std::uint32_t>(two));
        triangle(e + 3, t + 1, static_cast<std::uint32_t>(two >> 32));
        if (__builtin_expect(given_up, 0))
          return false;
      }
    }
    for (; e + 2 < corner_count; e += 3, ++t) {
      std::uint32_t t_need = 0;
      if constexpr (NEED)
        t_need = Clearance::roundedUp(Clearance::need(
            xy[corner_at[e]], xy[corner_at[e + 1]], xy[corner_at[e + 2]], limit2));
      triangle(e, t, t_need);
      if (__builtin_expect(given_up, 0))
        return false;
    }
    return true;
  };
  auto scatter_entries = [&](auto with_need) {
    offsets_ = detail::scratchArray<std::int16_t>(total, scratch_);
    if (scatter(with_need, offsets_.get()))
      return;
    offsets_.reset();
    wide_entries_.clear();
    wide_rows_.clear();
    count_in_full();
    if constexpr (decltype(with_need)::value)
      need->assign(n, 0.0);
    ids_ = detail::scratchArray<VertexId>(total, scratch_);
    scatter(with_need, ids_.get());
  };
  if (need != nullptr) {
    zeroNeeds(*need, n);
    scatter_entries(std::true_type{});
  } else
    scatter_entries(std::false_type{});
  std::sort(wide_entries_.begin(), wide_entries_.end());
  std::sort(wide_rows_.begin(), wide_rows_.end());
  wide_rows_.erase(std::unique(wide_rows_.begin(), wide_rows_.end()), wide_rows_.end());
  start[n] = total;
  return true;
}

bool VertexRows::noteFar(std::size_t k, VertexId v, VertexId u, std::size_t limit)
{
  wide_entries_.emplace_back(k, u);
  wide_rows_.push_back(v);
  return wide_entries_.size() <= limit;
}

namespace {

double ownMedian(const TriangleMesh& mesh, const VertexRows& rows, std::size_t v,
                 std::vector<double>& values)
{
  const std::size_t begin = rows.begin(v), end = rows.end(v);
  const std::size_t size = end - begin;
  if (size == 0)
    return 0.0;
  // Squared lengths: sqrt is monotonic and correctly rounded, so the root of the
  // median square is the median length (a NaN takes the lengths' own path).
  const Point2& p = mesh.xy[v];
  if (size <= 16) {
    double squares[16];
    bool nan = false;
    for (std::size_t k = 0; k < size; ++k) {
      const Point2& q = mesh.xy[rows.entry(v, begin + k)];
      const double dx = p.x - q.x, dy = p.y - q.y;
      squares[k] = dx * dx + dy * dy;
      nan = nan || std::isnan(squares[k]);
    }
    if (!nan)
      return std::sqrt(size == 6   ? medianOfSix(squares)
                       : size == 5 ? networkMedian<5>(squares, MEDIAN_OF_FIVE)
                       : size == 7 ? networkMedian<7>(squares, MEDIAN_OF_SEVEN)
                       : size <= 8 ? smallMedian<8>(squares, size)
                                   : smallMedian<16>(squares, size));
  }
  values.clear();
  for (std::size_t k = begin; k < end; ++k) {
    const Point2& q = mesh.xy[rows.entry(v, k)];
    const double dx = p.x - q.x, dy = p.y - q.y;
    values.push_back(std::sqrt(dx * dx + dy * dy)); // hypot is 5x slower
  }
  return medianInPlace(values);
}

#if defined(__SSE2__)
/// Per-vertex values (points, own medians) seen from v's row (VertexRows::visitRows'
/// entries): rowBase(values, v, entries)[rowOffset(entries, k)] is values[rowEntry(
/// entries, k, v)], a 16-bit entry indexing from v's own value (no id computed).
template <typename T>
inline const T* rowBase(const T* values, std::size_t v, const std::int16_t* /*entries*/)
{
  return values + v;
}
template <typename T>
inline const T* rowBase(const T* values, std::size_t /*v*/, const VertexId* /*entries*/)
{
  return values;
}
inline std::ptrdiff_t rowOffset(const std::int16_t* entries, std::size_t k)
{
  return entries[k];
}
inline std::size_t rowOffset(const VertexId* entries, std::size_t k)
{
  return entries[k];
}

/// The longest row ownMedians takes two vertices at a time (one per SSE2 lane).
constexpr std::size_t MAX_LANE_ROW = 12;

/// The lanes a row of N entries takes: rows of 9 and more are padded with +inf
/// to smallMedian<16>'s network, as in the scalar path.
template <std::size_t N>
constexpr std::size_t LANE_SLOTS = N <= 8 ? N : 16;

/// The compare-exchanges (lo, hi) of a sorting network of N values, N <= 8 (those
/// that do not reach the median are left to the compiler to drop).
constexpr std::uint8_t SORT_TWO[1][2] = {{0, 1}};
constexpr std::uint8_t SORT_THREE[3][2] = {{0, 1}, {1, 2}, {0, 1}};
constexpr std::uint8_t SORT_FOUR[5][2] = {{0, 1}, {2, 3}, {0, 2}, {1, 3}, {1, 2}};
/// smallMedian<8>'s and smallMedian<16>'s networks (Batcher's odd-even merge sort).
constexpr SortNetwork<8>::Table SORT_EIGHT = SortNetwork<8>::table();
constexpr SortNetwork<16>::Table SORT_SIXTEEN = SortNetwork<16>::table();

/// The network that laneMedian and quadMedian run on N values (ownMedian's choice):
/// after it the element at index N / 2 of the values sorted is in place (N = 6: the
/// smaller of those at indices 3 and 4).
template <std::size_t N>
constexpr const auto& laneNetwork()
{
  static_assert(N >= 2 && N <= 16);
  if constexpr (N == 2)
    return SORT_TWO;
  else if constexpr (N == 3)
    return SORT_THREE;
  else if constexpr (N == 4)
    return SORT_FOUR;
  else if constexpr (N == 5)
    return MEDIAN_OF_FIVE;
  else if constexpr (N == 6)
    return MEDIAN_OF_SIX;
  else if constexpr (N == 7)
    return MEDIAN_OF_SEVEN;
  else if constexpr (N == 8)
    return SORT_EIGHT;
  else
    return SORT_SIXTEEN;
}

/// A network's compare-exchanges, in a table of byte pairs or SortNetwork's: their
/// count, and exchange k as (lo, hi).
template <std::size_t M>
constexpr std::size_t pairCount(const std::uint8_t (&)[M][2])
{
  return M;
}
template <class Table>
constexpr std::size_t pairCount(const Table& table)
{
  return sizeof table.pairs / sizeof table.pairs[0];
}
template <std::size_t M>
constexpr std::pair<std::size_t, std::size_t> pairAt(const std::uint8_t (&pairs)[M][2],
                                                     std::size_t k)
{
  return {pairs[k][0], pairs[k][1]};
}
template <class Table>
constexpr std::pair<std::size_t, std::size_t> pairAt(const Table& table, std::size_t k)
{
  return {table.pairs[k].lo, table.pairs[k].hi};
}

/// One compare-exchange in both lanes: a[lo] gets the smaller, a[hi] the larger.
inline void exchangeLanes(__m128d* a, std::size_t lo, std::size_t hi)
{
  const __m128d low = _mm_min_pd(a[lo], a[hi]);
  a[hi] = _mm_max_pd(a[lo], a[hi]);
  a[lo] = low;
}

template <class Network, std::size_t... I>
inline void exchangeLanes(__m128d* a, const Network& network, std::index_sequence<I...>)
{
  (exchangeLanes(a, pairAt(network, I).first, pairAt(network, I).second), ...);
}

/// The element at index N / 2 of each lane's N values sorted, a[N, LANE_SLOTS<N>)
/// holding +inf (ownMedian's networks: min and max in the lanes pick the same
/// values, none being NaN or -0).
template <std::size_t N>
inline __m128d laneMedian(__m128d* a)
{
  if constexpr (N == 1) {
    return a[0];
  } else {
    constexpr const auto& network = laneNetwork<N>();
    exchangeLanes(a, network, std::make_index_sequence<pairCount(network)>());
    if constexpr (N == 6)
      return _mm_min_pd(a[3], a[4]);
    else
      return a[N / 2];
  }
}

/// ownMedian of u and w, both with rows of N entries, one per lane, into
/// medians[u - first] and medians[w - first]; false, nothing written, when a squared
/// length is NaN (ownMedian's own path then).
template <std::size_t N, typename Index, typename Entry>
inline bool laneMedians(const Point2* xy, const Entry* ring, const Index* start,
                        VertexId u, VertexId w, double* medians, std::size_t first,
                        __m128d& low, __m128d& high)
{
  const __m128d pu = _mm_loadu_pd(&xy[u].x), pw = _mm_loadu_pd(&xy[w].x);
  const Entry* row_u = ring + start[u];
  const Entry* row_w = ring + start[w];
  const Point2* xy_u = rowBase(xy, u, ring);
  const Point2* xy_w = rowBase(xy, w, ring);
  __m128d a[LANE_SLOTS<N>];
  __m128d sum = _mm_setzero_pd(); // NaN when a square is (none is -inf)
#pragma GCC unroll 16
  for (std::size_t k = 0; k < N; ++k) {
    const __m128d du = _mm_sub_pd(pu, _mm_loadu_pd(&xy_u[rowOffset(row_u, k)].x));
    const __m128d dw = _mm_sub_pd(pw, _mm_loadu_pd(&xy_w[rowOffset(row_w, k)].x));
    const __m128d su = _mm_mul_pd(du, du), sw = _mm_mul_pd(dw, dw);
    // (dx * dx of u, of w) + (dy * dy of u, of w): ownMedian's squares.
    a[k] = _mm_add_pd(_mm_unpacklo_pd(su, sw), _mm_unpackhi_pd(su, sw));
    sum = _mm_add_pd(sum, a[k]);
  }
  if (_mm_movemask_pd(_mm_cmpunord_pd(sum, sum)) != 0)
    return false;
  for (std::size_t k = N; k < LANE_SLOTS<N>; ++k)
    a[k] = _mm_set1_pd(std::numeric_limits<double>::infinity());
  const __m128d median = _mm_sqrt_pd(laneMedian<N>(a));
  _mm_storel_pd(medians + (u - first), median);
  _mm_storeh_pd(medians + (w - first), median);
  low = _mm_min_pd(low, median);
  high = _mm_max_pd(high, median);
  return true;
}

/// laneMedians over the pairs of ids[0, count), vertices with rows of N entries, in
/// order; a pair with a NaN square and an odd last vertex go to scalar(v). True when
/// a pair took the lanes.
template <std::size_t N, typename Index, typename Entry, typename Scalar>
bool laneMediansOfRows(const Point2* xy, const Entry* ring, const Index* start,
                       const VertexId* ids, std::size_t count, double* medians,
                       std::size_t first, __m128d& low, __m128d& high, Scalar& scalar)
{
  bool any_lane = false;
  std::size_t k = 0;
  for (; k + 1 < count; k += 2)
    if (laneMedians<N>(xy, ring, start, ids[k], ids[k + 1], medians, first, low, high))
      any_lane = true;
    else {
      scalar(ids[k]);
      scalar(ids[k + 1]);
    }
  if (k < count)
    scalar(ids[k]);
  return any_lane;
}

/// f(std::integral_constant<std::size_t, size>()) for 1 <= size <= sizeof...(S), its
/// value (false for another size): a row size picks its instance of the lanes'
/// medians once for all its vertices.
template <typename F, std::size_t... S>
bool forRowSize(std::size_t size, std::index_sequence<S...>, const F& f)
{
  bool result = false;
  (void)((size == S + 1 &&
          (result = f(std::integral_constant<std::size_t, S + 1>()), true)) ||
         ...);
  return result;
}

// Four vertices at a time in AVX2 registers, where the CPU has it (chosen at run
// time: never -march): every lane the same operations as laneMedians' on the same
// operands (the squares as dx * dx + dy * dy, the same networks, the root), so the
// same bits; a quad with a NaN square goes to the pairs' path.
#define PCL_VTS_AVX2 __attribute__((target("avx2")))

PCL_VTS_AVX2 inline void exchangeQuads(__m256d* a, std::size_t lo, std::size_t hi)
{
  const __m256d low = _mm256_min_pd(a[lo], a[hi]);
  a[hi] = _mm256_max_pd(a[lo], a[hi]);
  a[lo] = low;
}

template <class Network, std::size_t... I>
PCL_VTS_AVX2 inline void exchangeQuads(__m256d* a, const Network& network,
                                       std::index_sequence<I...>)
{
  (exchangeQuads(a, pairAt(network, I).first, pairAt(network, I).second), ...);
}

/// laneMedian in four lanes.
template <std::size_t N>
PCL_VTS_AVX2 inline __m256d quadMedian(__m256d* a)
{
  if constexpr (N == 1) {
    return a[0];
  } else {
    constexpr const auto& network = laneNetwork<N>();
    exchangeQuads(a, network, std::make_index_sequence<pairCount(network)>());
    if constexpr (N == 6)
      return _mm256_min_pd(a[3], a[4]);
    else
      return a[N / 2];
  }
}

/// laneMedians of ids[0..4), rows of N entries, one per lane; false, nothing
/// written, when a squared length is NaN.
template <std::size_t N, typename Index, typename Entry>
PCL_VTS_AVX2 inline bool quadMedians(const Point2* xy, const Entry* ring,
                                     const Index* start, const VertexId* ids,
                                     double* medians, std::size_t first, __m256d& low,
                                     __m256d& high)
{
  // Lanes 0-3: ids[0-3]. (p0, p2) and (p1, p3) as 256-bit halves, unpacked into
  // (x0, x1, x2, x3) and (y0, y1, y2, y3).
  auto xs_ys = [](const double* p0, const double* p1, const double* p2,
                  const double* p3, __m256d& x, __m256d& y) PCL_VTS_AVX2 {
    const __m256d a = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p0)),
                                           _mm_loadu_pd(p2), 1);
    const __m256d b = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p1)),
                                           _mm_loadu_pd(p3), 1);
    x = _mm256_unpacklo_pd(a, b);
    y = _mm256_unpackhi_pd(a, b);
  };
  const VertexId u0 = ids[0], u1 = ids[1], u2 = ids[2], u3 = ids[3];
  __m256d px, py;
  xs_ys(&xy[u0].x, &xy[u1].x, &xy[u2].x, &xy[u3].x, px, py);
  const Entry* row0 = ring + start[u0];
  const Entry* row1 = ring + start[u1];
  const Entry* row2 = ring + start[u2];
  const Entry* row3 = ring + start[u3];
  const Point2* xy0 = rowBase(xy, u0, ring);
  const Point2* xy1 = rowBase(xy, u1, ring);
  const Point2* xy2 = rowBase(xy, u2, ring);
  const Point2* xy3 = rowBase(xy, u3, ring);
  __m256d a[LANE_SLOTS<N>];
  __m256d sum = _mm256_setzero_pd(); // NaN when a square is (none is -inf)
#pragma GCC unroll 16
  for (std::size_t k = 0; k < N; ++k) {
    __m256d qx, qy;
    xs_ys(&xy0[rowOffset(row0, k)].x, &xy1[rowOffset(row1, k)].x,
          &xy2[rowOffset(row2, k)].x, &xy3[rowOffset(row3, k)].x, qx, qy);
    const __m256d dx = _mm256_sub_pd(px, qx), dy = _mm256_sub_pd(py, qy);
    a[k] = _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy));
    sum = _mm256_add_pd(sum, a[k]);
  }
  if (_mm256_movemask_pd(_mm256_cmp_pd(sum, sum, _CMP_UNORD_Q)) != 0)
    return false;
  for (std::size_t k = N; k < LANE_SLOTS<N>; ++k)
    a[k] = _mm256_set1_pd(std::numeric_limits<double>::infinity());
  const __m256d median = _mm256_sqrt_pd(quadMedian<N>(a));
  double out[4];
  _mm256_storeu_pd(out, median);
  medians[u0 - first] = out[0];
  medians[u1 - first] = out[1];
  medians[u2 - first] = out[2];
  medians[u3 - first] = out[3];
  low = _mm256_min_pd(low, median);
  high = _mm256_max_pd(high, median);
  return true;
}

/// laneMediansOfRows with the quads first: the pairs' path for a quad with a NaN
/// square and for the last count % 4 vertices.
template <std::size_t N, typename Index, typename Entry, typename Scalar>
PCL_VTS_AVX2 bool
quadMediansOfRows(const Point2* xy, const Entry* ring, const Index* start,
                  const VertexId* ids, std::size_t count, double* medians,
                  std::size_t first, __m128d& low, __m128d& high, Scalar& scalar)
{
  bool any_lane = false;
  __m256d low4 = _mm256_set1_pd(std::numeric_limits<double>::infinity());
  __m256d high4 = _mm256_setzero_pd();
  std::size_t k = 0;
  for (; k + 4 <= count; k += 4)
    if (quadMedians<N>(xy, ring, start, ids + k, medians, first, low4, high4))
      any_lane = true;
    else if (laneMediansOfRows<N>(xy, ring, start, ids + k, 4, medians, first, low,
                                  high, scalar))
      any_lane = true;
  if (k < count && laneMediansOfRows<N>(xy, ring, start, ids + k, count - k, medians,
                                        first, low, high, scalar))
    any_lane = true;
  // The quads' extremes into the pairs' (the lanes' medians are never NaN).
  low = _mm_min_pd(
      low, _mm_min_pd(_mm256_castpd256_pd128(low4), _mm256_extractf128_pd(low4, 1)));
  high = _mm_max_pd(
      high, _mm_max_pd(_mm256_castpd256_pd128(high4), _mm256_extractf128_pd(high4, 1)));
  return any_lane;
}

#undef PCL_VTS_AVX2

#endif

} // namespace

std::vector<double> ownMedians(const TriangleMesh& mesh, const VertexRows& rows,
                               unsigned threads, OwnStats* stats,
                               std::vector<double>* storage)
{
  // Per vertex: median incident edge length. Robust to a few long edges into a
  // void (a rim vertex keeps most of its short ones) and to anisotropic sampling
  // (scan lines: the shortest edge would only see the along-line spacing).
  // Each vertex's median is its own slot's: ranges of vertices on any threads, each
  // with its slot of the stats, joined in range order.
  const std::size_t n = mesh.vertexCount();
  std::vector<double> own;
  if (storage != nullptr) { // its memory, resident
    own.swap(*storage);
    own.clear();
  }
  own.reserve(n);
  detail::populatePages(own.data(), own.data() + n);
  const unsigned parts = usefulThreads(threads, n);
#if defined(__SSE2__)
  // One range appends its chunks (no pass of zeros before), several write their
  // slots.
  if (parts > 1)
    own.assign(n, 0.0);
#else
  own.assign(n, 0.0);
#endif
  std::vector<OwnStats> part_stats(parts);
  parallelChunks(parts, n, [&](std::size_t begin, std::size_t end, unsigned p) {
    std::vector<double> values; // reused across the range: no copy per vertex
    OwnStats local;
#if defined(__SSE2__)
    // The vertices of a chunk listed by row size, then each size's in pairs, one per
    // lane, through that size's network: no branch on the size per vertex. The
    // chunk's medians go to a buffer, then to own. The wide rows (wideRows) take
    // the scalar path.
    rows.visitRows([&](const auto* start, const auto* ring) {
      constexpr std::size_t CHUNK = 256, OTHER = MAX_LANE_ROW + 1;
      VertexId listed[OTHER + 1][CHUNK];
      std::size_t listed_count[OTHER + 1];
      double medians[CHUNK];
      const std::vector<VertexId>& wide_rows = rows.wideRows();
      auto wide = std::lower_bound(wide_rows.begin(), wide_rows.end(), begin);
      std::size_t next_wide = wide != wide_rows.end() ? *wide : n; // n: none
      const Point2* xy = mesh.xy.data();
      __m128d lanes_low = _mm_set1_pd(std::numeric_limits<double>::infinity());
      __m128d lanes_high = _mm_setzero_pd();
      bool any_lane = false;
      const bool avx2 = cpuHasAvx2();
      for (std::size_t first = begin; first < end; first += CHUNK) {
        const std::size_t last = std::min(end, first + CHUNK);
        auto scalar = [&](std::size_t v) {
          const double median = ownMedian(mesh, rows, v, values);
          medians[v - first] = median;
          local.low = std::min(local.low, bitsOf(median));
          local.high = std::max(local.high, bitsOf(median));
        };
        std::fill(listed_count, listed_count + OTHER + 1, std::size_t{0});
        for (std::size_t v = first; v < last; ++v) {
          const std::size_t size = start[v + 1] - start[v];
          std::size_t slot = size < OTHER ? size : OTHER;
          if (__builtin_expect(v == next_wide, 0)) {
            slot = OTHER;
            ++wide;
            next_wide = wide != wide_rows.end() ? *wide : n;
          }
          listed[slot][listed_count[slot]++] = static_cast<VertexId>(v);
        }
        for (std::size_t k = 0; k < listed_count[0]; ++k)
          medians[listed[0][k] - first] = 0.0; // an empty row's
        local.count += last - first - listed_count[0];
        for (std::size_t size = 1; size <= OTHER; ++size) {
          const VertexId* ids = listed[size];
          const std::size_t count = listed_count[size];
          if (size < OTHER) {
            const auto medians_of_rows = [&](auto row_size) {
              constexpr std::size_t N = decltype(row_size)::value;
              return avx2 ? quadMediansOfRows<N>(xy, ring, start, ids, count, medians,
                                                 first, lanes_low, lanes_high, scalar)
                          : laneMediansOfRows<N>(xy, ring, start, ids, count, medians,
                                                 first, lanes_low, lanes_high, scalar);
            };
            if (forRowSize(size, std::make_index_sequence<MAX_LANE_ROW>(),
                           medians_of_rows))
              any_lane = true;
          } else
            for (std::size_t k = 0; k < count; ++k)
              scalar(ids[k]);
        }
        if (parts == 1)
          own.insert(own.end(), medians, medians + (last - first));
        else
          std::copy(medians, medians + (last - first), own.begin() + first);
      }
      if (any_lane) {
        lanes_low = _mm_min_pd(lanes_low, _mm_unpackhi_pd(lanes_low, lanes_low));
        lanes_high = _mm_max_pd(lanes_high, _mm_unpackhi_pd(lanes_high, lanes_high));
        local.low = std::min(local.low, bitsOf(_mm_cvtsd_f64(lanes_low)));
        local.high = std::max(local.high, bitsOf(_mm_cvtsd_f64(lanes_high)));
      }
    });
#else
    for (std::size_t v = begin; v < end; ++v) {
      if (rows.begin(v) == rows.end(v))
        continue;
      own[v] = ownMedian(mesh, rows, v, values);
      local.low = std::min(local.low, bitsOf(own[v]));
      local.high = std::max(local.high, bitsOf(own[v]));
      ++local.count;
    }
#endif
    part_stats[p] = local;
  });
  if (stats != nullptr) {
    *stats = OwnStats{};
    for (const OwnStats& part : part_stats) {
      stats->low = std::min(stats->low, part.low);
      stats->high = std::max(stats->high, part.high);
      stats->count += part.count;
    }
  }
  return own;
}

} // namespace detail

namespace {

/// The upper median of values[v] over the v that selected(v) flags (0 for none):
/// medianInPlace's value.
template <typename Selected>
double upperMedianWhere(const std::vector<double>& values, const Selected& selected,
                        detail::MedianSelection* keep = nullptr)
{
  // Exact selection by a histogram of the IEEE bits (ordered as the values for
  // non-negative doubles): count, find the bucket holding the upper median's rank,
  // select inside it. A NaN or a negative value takes medianInPlace's path.
  const std::size_t n = values.size();
  std::size_t count = 0;
  std::uint64_t low = ~std::uint64_t{0}, high = 0;
  bool plain = true;
  for (std::size_t v = 0; v < n; ++v) {
    if (!selected(v))
      continue;
    ++count;
    const double x = values[v];
    plain = plain && !std::signbit(x) && !std::isnan(x);
    const std::uint64_t bits = bitsOf(x);
    low = std::min(low, bits);
    high = std::max(high, bits);
  }
  std::vector<double> chosen;
  if (!plain || count <= 4096) {
    chosen.reserve(count);
    for (std::size_t v = 0; v < n; ++v)
      if (selected(v))
        chosen.push_back(values[v]);
    return medianInPlace(chosen);
  }
  constexpr unsigned BUCKET_BITS = 16;
  unsigned shift = 0;
  while (((high - low) >> shift) >= (std::uint64_t{1} << BUCKET_BITS))
    ++shift;
  std::vector<std::size_t> histogram(std::size_t{1} << BUCKET_BITS, 0);
  for (std::size_t v = 0; v < n; ++v)
    if (selected(v))
      ++histogram[(bitsOf(values[v]) - low) >> shift];
  std::size_t rank = count / 2, bucket = 0;
  while (rank >= histogram[bucket])
    rank -= histogram[bucket++];
  chosen.reserve(histogram[bucket]);
  for (std::size_t v = 0; v < n; ++v)
    if (selected(v) && ((bitsOf(values[v]) - low) >> shift) == bucket)
      chosen.push_back(values[v]);
  const auto mid = chosen.begin() + static_cast<std::ptrdiff_t>(rank);
  std::nth_element(chosen.begin(), mid, chosen.end());
  const double median = *mid;
  if (keep != nullptr) {
    keep->low = low;
    keep->shift = shift;
    keep->count = count;
    keep->bucket = bucket;
    keep->histogram.swap(histogram);
    keep->members.swap(chosen);
  }
  return median;
}

} // namespace

namespace detail {

double medianOverRows(const std::vector<double>& own, const VertexRows& rows,
                      MedianSelection* keep)
{
  bool all = true; // the usual case: every vertex has triangles
  for (std::size_t v = 0; v < own.size() && all; ++v)
    all = rows.begin(v) != rows.end(v);
  if (all)
    return upperMedianWhere(
        own, [](std::size_t) { return true; }, keep);
  return upperMedianWhere(
      own, [&](std::size_t v) { return rows.begin(v) != rows.end(v); }, keep);
}

namespace {

constexpr unsigned BUCKET_BITS = 16; ///< upperMedianWhere's histogram: 65536 buckets

/// The largest IEEE bits of a non-negative double that is not NaN (+inf's): a
/// negative value or a NaN has larger ones.
constexpr std::uint64_t PLAIN_BITS = 0x7ff0000000000000ull;

/// upperMedianWhere's shift for the bits [low, high].
unsigned bucketShift(std::uint64_t low, std::uint64_t high)
{
  unsigned shift = 0;
  while (((high - low) >> shift) >= (std::uint64_t{1} << BUCKET_BITS))
    ++shift;
  return shift;
}

/// Whether medianOverRows takes its histogram for these stats.
bool histogramFits(const OwnStats& stats)
{
  return stats.count > 4096 && stats.high <= PLAIN_BITS;
}

/// ringLowerBound of v, whose row's entry k is the vertex at(k), for k in [begin,
/// end).
template <typename At>
inline double rowLowerBound(const double* own, const At& at, std::size_t v,
                            std::size_t begin, std::size_t end)
{
  // The three smallest of the values, kept sorted (s0 <= s1 <= s2) by
  // compare-exchanges; localMedian's index (the upper median of size values) is
  // size / 2, so the value of sorted index min(size / 2, 2) is at most it.
  constexpr double INF = std::numeric_limits<double>::infinity();
  double s0 = own[v], s1 = INF, s2 = INF;
  bool nan = std::isnan(s0);
  for (std::size_t k = begin; k < end; ++k) {
    const double x = own[at(k)];
    nan = nan || std::isnan(x);
    s2 = std::min(s2, std::max(s1, x));
    s1 = std::min(s1, std::max(s0, x));
    s0 = std::min(s0, x);
  }
  const std::size_t index = (end - begin + 1) / 2;
  return nan          ? std::numeric_limits<double>::quiet_NaN()
         : index == 0 ? s0
         : index == 1 ? s1
                      : s2;
}

#if defined(__SSE2__)
/// The longest row ringLowerBounds takes two vertices at a time (one per SSE2 lane).
constexpr std::size_t MAX_BOUND_ROW = 8;

/// rowLowerBound of u and w, both with rows of N entries (16-bit or id entries that
/// rowEntry decodes), one per lane, into bounds[u - first] and bounds[w - first],
/// no value being NaN (the caller knows it from the stats). The same
/// compare-exchanges in the same order: min and max in the lanes pick the same
/// values, none being NaN or -0.
template <std::size_t N, typename Index, typename Entry>
inline void laneBounds(const double* own, const Entry* ring, const Index* start,
                       VertexId u, VertexId w, double* bounds, std::size_t first)
{
  const Entry* row_u = ring + start[u];
  const Entry* row_w = ring + start[w];
  const double* own_u = rowBase(own, u, ring);
  const double* own_w = rowBase(own, w, ring);
  const __m128d inf = _mm_set1_pd(std::numeric_limits<double>::infinity());
  __m128d s0 = _mm_set_pd(own[w], own[u]), s1 = inf, s2 = inf;
#pragma GCC unroll 8
  for (std::size_t k = 0; k < N; ++k) {
    const __m128d x =
        _mm_set_pd(own_w[rowOffset(row_w, k)], own_u[rowOffset(row_u, k)]);
    s2 = _mm_min_pd(s2, _mm_max_pd(s1, x));
    s1 = _mm_min_pd(s1, _mm_max_pd(s0, x));
    s0 = _mm_min_pd(s0, x);
  }
  constexpr std::size_t INDEX = (N + 1) / 2;
  const __m128d result = INDEX == 0 ? s0 : INDEX == 1 ? s1 : s2;
  _mm_storel_pd(bounds + (u - first), result);
  _mm_storeh_pd(bounds + (w - first), result);
}

/// laneBounds over the pairs of ids[0, count), vertices with rows of N entries; an
/// odd last vertex goes to scalar(v).
template <std::size_t N, typename Index, typename Entry, typename Scalar>
void laneBoundsOfRows(const double* own, const Entry* ring, const Index* start,
                      const VertexId* ids, std::size_t count, double* bounds,
                      std::size_t first, Scalar& scalar)
{
  std::size_t k = 0;
  for (; k + 1 < count; k += 2)
    laneBounds<N>(own, ring, start, ids[k], ids[k + 1], bounds, first);
  if (k < count)
    scalar(ids[k]);
}

/// laneBoundsOfRows for rows of `size` entries, 1 <= size <= MAX_BOUND_ROW.
template <typename Index, typename Entry, typename Scalar, std::size_t... S>
void laneBoundsOfRows(std::size_t size, std::index_sequence<S...>, const double* own,
                      const Entry* ring, const Index* start, const VertexId* ids,
                      std::size_t count, double* bounds, std::size_t first,
                      Scalar& scalar)
{
  (void)((size == S + 1 &&
          (laneBoundsOfRows<S + 1>(own, ring, start, ids, count, bounds, first, scalar),
           true)) ||
         ...);
}
#endif

} // namespace

void ringLowerBounds(const VertexRows& rows, const std::vector<double>& own,
                     const OwnStats& stats, unsigned threads,
                     std::vector<double>& bound, MedianSelection* histogram,
                     ClearedVertices* cleared)
{
  const std::size_t n = own.size();
  if (cleared == nullptr)
    detail::reserveDiscarding(bound, n);
  bound.resize(n);
  const bool count = histogram != nullptr && histogramFits(stats);
  const unsigned shift = count ? bucketShift(stats.low, stats.high) : 0;
  const std::size_t words = (n + 63) / 64;
  if (cleared != nullptr)
    cleared->bits.assign(words, 0);
  const unsigned parts = usefulThreads(threads, n);
  // One histogram per range, summed after (the same counts on any threads). The
  // ranges are of 64 vertices (a word of cleared bits each).
  std::vector<std::vector<std::size_t>> part_counts(count ? parts : 0);
  std::vector<std::vector<std::pair<VertexId, TriangleId>>> uncleared(
      cleared != nullptr ? parts : 0);
  parallelChunks(parts, words, [&](std::size_t first, std::size_t last, unsigned p) {
    const std::size_t begin = 64 * first, end = std::min(n, 64 * last);
    std::size_t* buckets = nullptr;
    if (count) {
      part_counts[p].assign(std::size_t{1} << BUCKET_BITS, 0);
      buckets = part_counts[p].data();
    }
    // On the starts' and entries' own types (no test of their width per vertex);
    // the wide rows (wideRows) through VertexRows::entry.
    rows.visitRows([&](const auto* start, const auto* ring) {
      const double* values = own.data();
      double* out = bound.data();
      const std::vector<VertexId>& wide_rows = rows.wideRows();
      auto wide = std::lower_bound(wide_rows.begin(), wide_rows.end(), begin);
      auto bound_of = [&](std::size_t v) { // v increasing
        if (__builtin_expect(wide != wide_rows.end() && *wide == v, 0)) {
          ++wide;
          return rowLowerBound(
              values, [&](std::size_t k) { return rows.entry(v, k); }, v, start[v],
              start[v + 1]);
        }
        return rowLowerBound(
            values, [&](std::size_t k) { return rowEntry(ring, k, v); }, v, start[v],
            start[v + 1]);
      };
      if (cleared == nullptr) {
        for (std::size_t v = begin; v < end; ++v) {
          out[v] = bound_of(v);
          if (buckets != nullptr && start[v] != start[v + 1])
            ++buckets[(bitsOf(values[v]) - stats.low) >> shift];
        }
        return;
      }
      const double factor = cleared->trim_factor;
      std::uint64_t* bits = cleared->bits.data();
      std::vector<std::pair<VertexId, TriangleId>>& left = uncleared[p];
      // Vertex v, whose clearance slot (the need and the triangle that set it) is
      // `slot`, cleared when the need is within the trim's limit; else its bound is
      // written over the slot (only an uncleared vertex's bound is read after) and,
      // with a row, it is listed.
      auto settle = [&](std::size_t v, std::uint64_t slot, double v_bound) {
        const double need = Clearance::slotNeed(slot);
        const double limit = factor * v_bound;
        const bool clear = (limit >= Clearance::LOW) & (limit <= Clearance::HIGH) &
                           (need <= limit * limit * Clearance::MARGIN);
        bits[v / 64] |= std::uint64_t{clear} << (v % 64);
        if (__builtin_expect(!clear, 0)) {
          out[v] = v_bound;
          if (start[v] != start[v + 1])
            left.emplace_back(static_cast<VertexId>(v),
                              static_cast<TriangleId>(slot >> 32));
        }
      };
      // The histogram of a word's vertices with a row (every vertex when none is
      // empty).
      auto count_word = [&](std::size_t from, std::size_t to, bool all_rows) {
        if (buckets == nullptr)
          return;
        const std::uint64_t low = stats.low;
        if (all_rows)
          for (std::size_t v = from; v < to; ++v)
            ++buckets[(bitsOf(values[v]) - low) >> shift];
        else
          for (std::size_t v = from; v < to; ++v)
            if (start[v] != start[v + 1])
              ++buckets[(bitsOf(values[v]) - low) >> shift];
      };
#if defined(__SSE2__)
      // Own medians are 0 without a row and within the stats' bits with one: no NaN
      // (nor a negative value) among them when those bits are a plain double's. Then
      // a word's vertices are listed by row size, and each size's taken in pairs, one
      // per lane (ownMedians' scheme: no branch on the size per vertex); rows longer
      // than MAX_BOUND_ROW, empty and wide ones take rowLowerBound. Their bounds go
      // to a buffer, then two vertices at a time are settled in the lanes (settle's
      // operations on the same operands: the same bits). With a NaN, the scalar path.
      if (stats.high <= PLAIN_BITS) {
        constexpr std::size_t WORD = 64, OTHER = MAX_BOUND_ROW + 1;
        VertexId listed[OTHER + 1][WORD];
        std::size_t listed_count[OTHER + 1];
        double bounds[WORD];
        std::size_t next_wide = wide != wide_rows.end() ? *wide : n;
        const __m128d factor2 = _mm_set1_pd(factor);
        const __m128d low2 = _mm_set1_pd(Clearance::LOW);
        const __m128d high2 = _mm_set1_pd(Clearance::HIGH);
        const __m128d margin2 = _mm_set1_pd(Clearance::MARGIN);
        for (std::size_t from = begin; from < end; from += WORD) {
          const std::size_t to = std::min(end, from + WORD);
          std::fill(listed_count, listed_count + OTHER + 1, std::size_t{0});
          for (std::size_t v = from; v < to; ++v) {
            const std::size_t size = start[v + 1] - start[v];
            std::size_t slot = size < OTHER ? size : OTHER;
            if (__builtin_expect(v == next_wide, 0)) {
              slot = 0;
              ++wide;
              next_wide = wide != wide_rows.end() ? *wide : n;
            }
            listed[slot][listed_count[slot]++] = static_cast<VertexId>(v);
          }
          auto scalar = [&](std::size_t v) {
            bounds[v - from] = rowLowerBound(
                values, [&](std::size_t k) { return rows.entry(v, k); }, v, start[v],
                start[v + 1]);
          };
          for (std::size_t k = 0; k < listed_count[0]; ++k)
            scalar(listed[0][k]);
          for (std::size_t k = 0; k < listed_count[OTHER]; ++k)
            scalar(listed[OTHER][k]);
          for (std::size_t size = 1; size < OTHER; ++size)
            laneBoundsOfRows(size, std::make_index_sequence<MAX_BOUND_ROW>(), values,
                             ring, start, listed[size], listed_count[size], bounds,
                             from, scalar);
          // settle in the lanes: the needs (a slot's low 32 bits, a float) widened,
          // the limits and the tests per lane; the word's bits kept in a register.
          std::uint64_t word = 0;
          std::size_t v = from;
          for (; v + 1 < to; v += 2) {
            const __m128d v_bound = _mm_loadu_pd(bounds + (v - from));
            const __m128i two_slots =
                _mm_loadu_si128(reinterpret_cast<const __m128i*>(out + v));
            const __m128d need = _mm_cvtps_pd(_mm_castsi128_ps(
                _mm_shuffle_epi32(two_slots, _MM_SHUFFLE(2, 0, 2, 0))));
            const __m128d limit = _mm_mul_pd(factor2, v_bound);
            const __m128d clear = _mm_and_pd(
                _mm_and_pd(_mm_cmpge_pd(limit, low2), _mm_cmple_pd(limit, high2)),
                _mm_cmple_pd(need, _mm_mul_pd(_mm_mul_pd(limit, limit), margin2)));
            const int mask = _mm_movemask_pd(clear);
            word |= static_cast<std::uint64_t>(mask) << (v - from);
            if (__builtin_expect(mask != 3, 0))
              for (std::size_t k = 0; k < 2; ++k)
                if (((mask >> k) & 1) == 0) {
                  out[v + k] = bounds[v + k - from];
                  if (start[v + k] != start[v + k + 1]) {
                    std::uint64_t slot = 0;
                    _mm_storel_epi64(reinterpret_cast<__m128i*>(&slot),
                                     k == 0 ? two_slots
                                            : _mm_unpackhi_epi64(two_slots, two_slots));
                    left.emplace_back(static_cast<VertexId>(v + k),
                                      static_cast<TriangleId>(slot >> 32));
                  }
                }
          }
          bits[from / 64] |= word;
          if (v < to)
            settle(v, Clearance::slot(out[v]), bounds[v - from]);
          count_word(from, to, listed_count[0] == 0);
        }
        return;
      }
#endif
      for (std::size_t v = begin; v < end; ++v) {
        const std::uint64_t slot = Clearance::slot(out[v]);
        settle(v, slot, bound_of(v));
        count_word(v, v + 1, false);
      }
    });
  });
  if (cleared != nullptr) {
    cleared->uncleared.clear();
    for (const auto& part : uncleared)
      cleared->uncleared.insert(cleared->uncleared.end(), part.begin(), part.end());
  }
  if (!count)
    return;
  *histogram = MedianSelection{};
  histogram->low = stats.low;
  histogram->shift = shift;
  histogram->count = stats.count;
  histogram->histogram.swap(part_counts[0]);
  for (std::size_t p = 1; p < part_counts.size(); ++p)
    for (std::size_t b = 0; b < histogram->histogram.size(); ++b)
      histogram->histogram[b] += part_counts[p][b];
}

double medianOverRows(const std::vector<double>& own, const VertexRows& rows,
                      const OwnStats& stats, MedianSelection& histogram)
{
  if (histogram.histogram.empty() || !histogramFits(stats))
    return medianOverRows(own, rows, &histogram);
  // upperMedianWhere's last steps: the bucket holding the rank, its members.
  std::size_t rank = histogram.count / 2, bucket = 0;
  while (rank >= histogram.histogram[bucket])
    rank -= histogram.histogram[bucket++];
  std::vector<double>& chosen = histogram.members;
  chosen.clear();
  chosen.reserve(histogram.histogram[bucket]);
  std::size_t v = 0;
#if defined(__SSE2__)
  // The bucket's bits are [first, end): with every figure of a row non-negative and
  // not NaN (histogramFits) and 0 without a row, that is first's value <= x < end's
  // as doubles when end is a double's bits too (not past +inf's).
  const std::uint64_t first =
      histogram.low + (std::uint64_t{bucket} << histogram.shift);
  const std::uint64_t end = first + (std::uint64_t{1} << histogram.shift);
  if (end <= PLAIN_BITS) {
    double low = 0.0, high = 0.0;
    std::memcpy(&low, &first, sizeof low);
    std::memcpy(&high, &end, sizeof high);
    const __m128d low2 = _mm_set1_pd(low), high2 = _mm_set1_pd(high);
    const double* values = own.data();
    auto inside = [&](std::size_t u) {
      const __m128d x = _mm_loadu_pd(values + u);
      return _mm_movemask_pd(_mm_and_pd(_mm_cmple_pd(low2, x), _mm_cmplt_pd(x, high2)));
    };
    for (; v + 4 <= own.size(); v += 4) {
      const int mask = inside(v) | inside(v + 2) << 2;
      if (mask == 0)
        continue;
      for (std::size_t k = 0; k < 4; ++k)
        if (((mask >> k) & 1) != 0 && rows.begin(v + k) != rows.end(v + k))
          chosen.push_back(values[v + k]);
    }
  }
#endif
  for (; v < own.size(); ++v)
    if (((bitsOf(own[v]) - histogram.low) >> histogram.shift) == bucket &&
        rows.begin(v) != rows.end(v))
      chosen.push_back(own[v]);
  histogram.bucket = bucket;
  std::vector<double> sorted = chosen;
  const auto mid = sorted.begin() + static_cast<std::ptrdiff_t>(rank);
  std::nth_element(sorted.begin(), mid, sorted.end());
  return *mid;
}

bool MedianSelection::update(const std::vector<double>& own,
                             const std::vector<OwnChange>& changes, double& median)
{
  if (histogram.empty() || low == 0)
    return false; // no histogram, or an unused vertex's 0 would fall in a bucket
  auto bucket_of = [&](double x, std::size_t& b) {
    const std::uint64_t bits = bitsOf(x);
    if (std::signbit(x) || std::isnan(x) || bits < low)
      return false;
    b = static_cast<std::size_t>((bits - low) >> shift);
    return b < histogram.size();
  };
  for (const OwnChange& change : changes) {
    std::size_t b = 0;
    if (!bucket_of(change.before, b) || histogram[b] == 0 || count == 0)
      return false;
    --histogram[b];
    --count;
    if (b == bucket) {
      const auto it = std::find(members.begin(), members.end(), change.before);
      if (it == members.end())
        return false;
      *it = members.back();
      members.pop_back();
    }
    if (!change.kept)
      continue;
    if (!bucket_of(change.after, b))
      return false;
    ++histogram[b];
    ++count;
    if (b == bucket)
      members.push_back(change.after);
  }
  if (count == 0)
    return false;
  std::size_t rank = count / 2, b = 0;
  while (rank >= histogram[b])
    rank -= histogram[b++];
  if (b != bucket) {
    // The median moved to another bucket: its members from every value (those of
    // vertices without triangles are 0, below low).
    members.clear();
    for (const double x : own) {
      std::size_t xb = 0;
      if (bucket_of(x, xb) && xb == b)
        members.push_back(x);
    }
    bucket = b;
    if (members.size() != histogram[b])
      return false;
  }
  std::vector<double> chosen = members;
  const auto mid = chosen.begin() + static_cast<std::ptrdiff_t>(rank);
  std::nth_element(chosen.begin(), mid, chosen.end());
  median = *mid;
  return true;
}

double localMedian(const VertexRows& rows, const std::vector<double>& own,
                   std::size_t v, std::vector<double>& values)
{
  const std::size_t begin = rows.begin(v), end = rows.end(v);
  if (begin == end)
    return 0.0;
  values.assign(1, own[v]);
  for (std::size_t k = begin; k < end; ++k)
    values.push_back(own[rows.entry(v, k)]);
  return medianInPlace(values);
}

double ringLowerBound(const VertexRows& rows, const std::vector<double>& own,
                      std::size_t v)
{
  return rowLowerBound(
      own.data(), [&](std::size_t k) { return rows.entry(v, k); }, v, rows.begin(v),
      rows.end(v));
}

} // namespace detail

namespace {

/// measurePointSpacing from the rows.
PointSpacing measure(const TriangleMesh& mesh, const std::vector<bool>* local_for,
                     std::vector<double>* own_out, unsigned threads)
{
  const std::size_t n = mesh.vertexCount();
  PointSpacing spacing;
  detail::VertexRows rows;
  rows.build(mesh);
  std::vector<double> own = detail::ownMedians(mesh, rows, threads);
  spacing.global_median = detail::medianOverRows(own, rows);
  spacing.local.assign(n, 0.0);
  parallelRanges(threads, n, [&](std::size_t begin, std::size_t end) {
    std::vector<double> values;
    for (std::size_t v = begin; v < end; ++v)
      if (local_for == nullptr || (*local_for)[v])
        spacing.local[v] = detail::localMedian(rows, own, v, values);
  });
  if (own_out != nullptr)
    own_out->swap(own);
  return spacing;
}

} // namespace

double medianOf(std::vector<double> values)
{
  return medianInPlace(values);
}

PointSpacing measurePointSpacing(const TriangleMesh& mesh,
                                 const std::vector<bool>* local_for)
{
  return detail::measurePointSpacing(mesh, local_for, nullptr);
}

namespace detail {

PointSpacing measurePointSpacing(const TriangleMesh& mesh,
                                 const std::vector<bool>* local_for,
                                 std::vector<double>* own, unsigned threads)
{
  threads = threads > 0 ? threads : allCores();
  return measure(mesh, local_for, own, threads);
}

void remeasureOwnSpacing(const TriangleMesh& mesh, const std::vector<bool>& changed,
                         std::vector<double>& own, unsigned threads)
{
  // The rows of the changed vertices only (measure's rule: every halfedge leaving
  // the vertex, and the boundary ones entering it), as (vertex, edge length).
  std::vector<std::pair<VertexId, double>> rows;
  auto length = [&](VertexId a, VertexId b) {
    const double dx = mesh.xy[a].x - mesh.xy[b].x, dy = mesh.xy[a].y - mesh.xy[b].y;
    return std::sqrt(dx * dx + dy * dy);
  };
  // Each range of halfedges collects its own, then they are joined in range order
  // (sorted below, so the order would not matter anyway).
  const unsigned parts =
      usefulThreads(threads > 0 ? threads : allCores(), mesh.triangles.size());
  std::vector<std::vector<std::pair<VertexId, double>>> found(parts);
  parallelChunks(parts, mesh.triangles.size(),
                 [&](std::size_t begin, std::size_t end, unsigned t) {
                   for (std::size_t i = begin; i < end; ++i) {
                     const auto e = static_cast<HalfedgeId>(i);
                     const VertexId a = mesh.triangles[e];
                     const VertexId b = mesh.triangles[nextHalfedge(e)];
                     if (changed[a])
                       found[t].emplace_back(a, length(a, b));
                     if (mesh.halfedges[e] == INVALID_ID && changed[b])
                       found[t].emplace_back(b, length(b, a));
                   }
                 });
  for (const auto& part : found)
    rows.insert(rows.end(), part.begin(), part.end());
  std::vector<std::vector<std::pair<VertexId, double>>>().swap(found);
  std::sort(rows.begin(), rows.end()); // a row's order does not change its median
  for (std::size_t v = 0; v < changed.size(); ++v)
    if (changed[v])
      own[v] = 0.0; // left without triangles unless a row says otherwise
  std::vector<double> values;
  for (std::size_t i = 0; i < rows.size();) {
    std::size_t j = i;
    values.clear();
    for (; j < rows.size() && rows[j].first == rows[i].first; ++j)
      values.push_back(rows[j].second);
    own[rows[i].first] = medianInPlace(values);
    i = j;
  }
}

void VertexSpacing::settle(const TriangleMesh& trimmed, unsigned threads)
{
  if (settled)
    return;
  // The trim's histogram of the input's own medians, updated at the changed
  // vertices, when the trimmed figures fit it.
  if (own_settled && selection.update(own, own_changes, global_median)) {
    std::vector<VertexId>().swap(without_triangles);
    selection = MedianSelection{};
    std::vector<OwnChange>().swap(own_changes);
    settled = true;
    return;
  }
  std::vector<bool> has_triangle(trimmed.vertexCount(), own_settled);
  if (own_settled) {
    for (const VertexId v : without_triangles)
      has_triangle[v] = false;
  } else {
    remeasureOwnSpacing(trimmed, changed, own, threads);
    for (const VertexId v : trimmed.triangles)
      has_triangle[v] = true;
  }
  global_median = medianOverUsed(own, has_triangle);
  selection = MedianSelection{};
  std::vector<OwnChange>().swap(own_changes);
  std::vector<bool>().swap(changed);
  std::vector<VertexId>().swap(without_triangles);
  settled = true;
}

double medianOverUsed(const std::vector<double>& own,
                      const std::vector<bool>& has_triangle)
{
  return upperMedianWhere(own, [&](std::size_t v) { return has_triangle[v]; });
}

} // namespace detail

} // namespace pcl_vts
