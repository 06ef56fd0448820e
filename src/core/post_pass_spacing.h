// The spacing handed from the trim to the fill inside reconstructSurface (internal to
// the core): the fill needs the trimmed mesh's spacing, which differs from the
// trim's only at the corners of removed triangles, so those are measured again
// instead of the whole mesh. Every figure equals measurePointSpacing's on the
// trimmed mesh (point_spacing.h).
#pragma once

#include "post_pass_scratch.h"

#include <pcl_vts/core/boundary_loops.h>
#include <pcl_vts/core/export.h>
#include <pcl_vts/core/fill_holes.h>
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/point_spacing.h>
#include <pcl_vts/core/trim_outward_triangles.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pcl_vts::detail {

/// A count of a vertex's triangles this large is not trusted (VertexSpacing).
constexpr unsigned MANY_TRIANGLES = 255;

/// An own median changed by the trim (VertexSpacing::own_changes).
struct OwnChange {
  double before = 0.0, after = 0.0;
  bool kept = true; ///< false when the vertex lost all its triangles
};

/// The histogram selection of a median over own medians (of the vertices with a
/// row): the IEEE bits less low, shifted, counted per bucket; the median's bucket
/// and its members (values, any order).
struct MedianSelection {
  std::uint64_t low = 0;
  unsigned shift = 0;
  std::size_t count = 0;
  std::size_t bucket = 0;
  std::vector<std::size_t> histogram; ///< empty: no histogram was built
  std::vector<double> members;

  /// The median after the changes (own: every vertex's figure after them, 0 for a
  /// vertex without triangles) in median; false when they do not fit the histogram
  /// (then it is left in any state).
  bool update(const std::vector<double>& own, const std::vector<OwnChange>& changes,
              double& median);
};

/// What the trim hands to the fill: per vertex the median length of its edges, and
/// either (own_settled) the vertices left without triangles, own being the trimmed
/// mesh's already, or own before the trim and the vertices whose rows the trim
/// changed. settle() brings them to the trimmed mesh (own for it, and the median of
/// own over the vertices with triangles, PointSpacing::global_median): only a fill
/// that found holes pays for it.
struct VertexSpacing {
  std::vector<double> own;
  bool own_settled = false;
  std::vector<VertexId> without_triangles; ///< when own_settled
  std::vector<OwnChange> own_changes;      ///< when own_settled
  MedianSelection selection;               ///< the input's global median's
  std::vector<bool> changed;               ///< when not own_settled
  double global_median = 0.0;
  bool settled = false;
  /// The trimmed mesh's boundary halfedges (no twin) in increasing order, when
  /// boundary_known: the fill's loops start from them instead of a scan.
  std::vector<HalfedgeId> boundary;
  bool boundary_known = false;
  /// Per vertex its triangles in the trimmed mesh, up to MANY_TRIANGLES (a count
  /// not trusted): the fill walks the fans of rim vertices and checks them whole.
  std::vector<std::uint8_t> triangle_count;

  void settle(const TriangleMesh& trimmed, unsigned threads = 1);
};

/// The error for the first triangle corner of mesh that is not a vertex id, or
/// success when there is none.
Status checkCorners(const TriangleMesh& mesh);

/// Triangle abc's squared edges and twice its area, as every test of the trim
/// computes them (classifyTriangle, the per-triangle clearance, Clearance::need and
/// its SSE2 lanes): the clearance's proof needs the same roundings in all of them.
struct TriangleSquares {
  double ab, bc, ca, twice_area;
};
[[gnu::always_inline]] inline TriangleSquares
triangleSquares(const Point2& a, const Point2& b, const Point2& c)
{
  auto square = [](const Point2& u, const Point2& w) {
    const double dx = u.x - w.x, dy = u.y - w.y;
    return dx * dx + dy * dy;
  };
  return {square(a, b), square(b, c), square(c, a),
          std::fabs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y))};
}

/// The trim's vertex-level clearance (classifyTriangles in
/// trim_outward_triangles.cpp, where the proof is): the range of the figures it
/// trusts and its relative margin, far above their rounding errors.
struct Clearance {
  static constexpr double LOW = 1e-60, HIGH = 1e60, MARGIN = 1.0 - 1e-12;
  /// The squared limit triangle abc needs: the largest of its squared edges and its
  /// squared circumradius (the product of the squared edges over four squared
  /// areas), as computed; +inf when a figure lies outside [LOW, HIGH] or is NaN, or
  /// the longest squared edge exceeds edge_limit2 (max_edge squared times MARGIN,
  /// +inf without max_edge).
  static double need(const Point2& a, const Point2& b, const Point2& c,
                     double edge_limit2);
  /// need as a float rounded up (its IEEE bits): need <= the float's value, +inf
  /// beyond the float range. need is never NaN, so the bits order as the values.
  static std::uint32_t roundedUp(double need)
  {
    // Past the float range (+inf included) the conversion is undefined: +inf's bits.
    if (!(need <= static_cast<double>(std::numeric_limits<float>::max())))
      return 0x7f800000u;
    const auto f = static_cast<float>(need);
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, sizeof bits);
    // The next float up of a non-negative float is its bits plus one (FLT_MAX's is
    // +inf's).
    return bits + (static_cast<double>(f) < need ? 1u : 0u);
  }
  /// A vertex's slot of VertexRows::build's `need`: the largest roundedUp of its
  /// triangles in the low 32 bits, the last of its triangles in the high ones.
  static std::uint64_t slot(double stored)
  {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &stored, sizeof bits);
    return bits;
  }
  /// roundedUp(need(a0, b0, c0)) in the low 32 bits, roundedUp(need(a1, b1, c1))
  /// in the high ones: the same figures bit for bit (with SSE2, the two triangles
  /// in the two lanes of the same operations; see its definition).
  static std::uint64_t roundedUpNeeds(const Point2& a0, const Point2& b0,
                                      const Point2& c0, const Point2& a1,
                                      const Point2& b1, const Point2& c1,
                                      double edge_limit2);
  static float slotNeed(std::uint64_t slot)
  {
    const auto low = static_cast<std::uint32_t>(slot);
    float f = 0.0F;
    std::memcpy(&f, &low, sizeof f);
    return f;
  }
};

// Always inlined: the rows' scatter calls it per triangle, and with its four
// instances (need or not, 16- or 32-bit entries) GCC otherwise leaves it a call.
[[gnu::always_inline]] inline double
Clearance::need(const Point2& a, const Point2& b, const Point2& c, double edge_limit2)
{
  const auto [ab, bc, ca, twice_area] = triangleSquares(a, b, c);
  const double longest = std::max(std::max(ab, bc), ca);
  // min and max may pass over a NaN, but then the product or the area is NaN and
  // so is the figure returned, which the last test turns into +inf.
  const double low = std::min(std::min(ab, bc), std::min(ca, twice_area));
  const double high = std::max(std::max(ab, bc), std::max(ca, twice_area));
  const double product = ab * bc * ca, areas = 4.0 * twice_area * twice_area;
  // The squared circumradius exceeds the longest squared edge only past an angle
  // of 150 degrees: the division is left to those (and need >= longest always).
  const double need =
      product <= areas * longest ? longest : std::max(longest, product / areas);
  constexpr double INF = std::numeric_limits<double>::infinity();
  // One branch on the four tests (bitwise and: no short-circuit branches).
  const bool in_range = (low >= LOW) & (high <= HIGH) & (longest <= edge_limit2) &
                        (need <= std::numeric_limits<double>::max());
  return in_range ? need : INF;
}

// Two triangles' needs in the two lanes of SSE2 registers: every operation of
// need and roundedUp, in the same order on the same operands, so each lane's
// figures are the scalar ones bit for bit (IEEE operations are correctly rounded
// either way; -ffp-contract=off keeps the scalar ones unfused). std::min(x, y) is
// (y < x) ? y : x and std::max(x, y) is (x < y) ? y : x, which are _mm_min_pd(y, x)
// and _mm_max_pd(y, x) (minpd/maxpd return their second operand unless the first
// compares less/greater), NaN and equal operands included. The quotient is taken
// only where a lane needs it; the other lane's quotient is not used.
// test_trim_outward_triangles' ClearanceNeedsInLanesEqualTheScalarOnes compares
// the lanes with the scalar figures on ordinary, obtuse, degenerate, tiny, huge and
// non-finite triangles.
[[gnu::always_inline]] inline std::uint64_t
Clearance::roundedUpNeeds(const Point2& a0, const Point2& b0, const Point2& c0,
                          const Point2& a1, const Point2& b1, const Point2& c1,
                          double edge_limit2)
{
#if defined(__SSE2__)
  // Lane k: triangle k's x or y.
  auto xs = [](const Point2& p0, const Point2& p1) { return _mm_set_pd(p1.x, p0.x); };
  auto ys = [](const Point2& p0, const Point2& p1) { return _mm_set_pd(p1.y, p0.y); };
  const __m128d ax = xs(a0, a1), ay = ys(a0, a1), bx = xs(b0, b1), by = ys(b0, b1),
                cx = xs(c0, c1), cy = ys(c0, c1);
  auto square = [](__m128d ux, __m128d uy, __m128d wx, __m128d wy) {
    const __m128d dx = _mm_sub_pd(ux, wx), dy = _mm_sub_pd(uy, wy);
    return _mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy));
  };
  const __m128d ab = square(ax, ay, bx, by), bc = square(bx, by, cx, cy),
                ca = square(cx, cy, ax, ay);
  const __m128d cross = _mm_sub_pd(_mm_mul_pd(_mm_sub_pd(bx, ax), _mm_sub_pd(cy, ay)),
                                   _mm_mul_pd(_mm_sub_pd(cx, ax), _mm_sub_pd(by, ay)));
  const __m128d twice_area = _mm_andnot_pd(_mm_set1_pd(-0.0), cross); // fabs
  const __m128d ab_bc = _mm_max_pd(bc, ab);                           // max(ab, bc)
  const __m128d longest = _mm_max_pd(ca, ab_bc);
  const __m128d low =
      _mm_min_pd(_mm_min_pd(twice_area, ca), _mm_min_pd(bc, ab)); // min(min, min)
  const __m128d high = _mm_max_pd(_mm_max_pd(twice_area, ca), ab_bc);
  const __m128d product = _mm_mul_pd(_mm_mul_pd(ab, bc), ca);
  const __m128d areas =
      _mm_mul_pd(_mm_mul_pd(_mm_set1_pd(4.0), twice_area), twice_area);
  const __m128d takes_longest = _mm_cmple_pd(product, _mm_mul_pd(areas, longest));
  __m128d need = longest;
  if (_mm_movemask_pd(takes_longest) != 3) {
    const __m128d radius = _mm_max_pd(_mm_div_pd(product, areas), longest);
    need = _mm_or_pd(_mm_and_pd(takes_longest, longest),
                     _mm_andnot_pd(takes_longest, radius));
  }
  const __m128d in_range = _mm_and_pd(
      _mm_and_pd(_mm_cmpge_pd(low, _mm_set1_pd(LOW)),
                 _mm_cmple_pd(high, _mm_set1_pd(HIGH))),
      _mm_and_pd(_mm_cmple_pd(longest, _mm_set1_pd(edge_limit2)),
                 _mm_cmple_pd(need, _mm_set1_pd(std::numeric_limits<double>::max()))));
  const __m128d inf = _mm_set1_pd(std::numeric_limits<double>::infinity());
  need = _mm_or_pd(_mm_and_pd(in_range, need), _mm_andnot_pd(in_range, inf));
  // roundedUp per lane: the float's bits, plus one where the float is below need;
  // +inf's bits past the float range. The 64-bit masks' low halves moved to the
  // 32-bit lanes 0 and 1.
  const __m128 single = _mm_cvtpd_ps(need);
  const __m128d below = _mm_cmplt_pd(_mm_cvtps_pd(single), need);
  const __m128d fits = _mm_cmple_pd(
      need, _mm_set1_pd(static_cast<double>(std::numeric_limits<float>::max())));
  auto to32 = [](__m128d mask) {
    return _mm_shuffle_epi32(_mm_castpd_si128(mask), _MM_SHUFFLE(2, 0, 2, 0));
  };
  const __m128i bits = _mm_sub_epi32(_mm_castps_si128(single), to32(below));
  const __m128i fit = to32(fits);
  const __m128i rounded = _mm_or_si128(
      _mm_and_si128(fit, bits), _mm_andnot_si128(fit, _mm_set1_epi32(0x7f800000)));
  std::uint64_t both = 0;
  _mm_storel_epi64(reinterpret_cast<__m128i*>(&both), rounded);
  return both;
#else
  return std::uint64_t{roundedUp(need(a0, b0, c0, edge_limit2))} |
         std::uint64_t{roundedUp(need(a1, b1, c1, edge_limit2))} << 32;
#endif
}

/// Each vertex's row of neighbours, measurePointSpacing's rule: the ends of the
/// halfedges leaving it and the starts of the boundary halfedges entering it.
class VertexRows {
 public:
  VertexRows() = default;
  /// build's entries inside `scratch` when they fit there (scratchArray); the
  /// slotted build's count bytes inside `temporary` (memory free until build
  /// returns: the trim's own medians' place).
  explicit VertexRows(ScratchBlock scratch, ScratchBlock temporary = {})
      : scratch_(scratch)
      , temporary_(temporary)
  {}
  /// With `boundary`, also lists the halfedges without twin, in increasing order.
  /// False, the rows left unbuilt, when a triangle corner is not a vertex id (checked
  /// in the count pass: no pass of its own over the corners). With `need`, also per
  /// vertex the largest Clearance::need(edge_limit2) of its triangles (0 for none),
  /// rounded up to a float, and one of its triangles, in its slot (Clearance::slot),
  /// in the scatter that visits every triangle anyway.
  /// Exported for test_vertex_rows.
  PCL_VTS_CORE_EXPORT bool build(const TriangleMesh& mesh,
                                 std::vector<HalfedgeId>* boundary = nullptr,
                                 std::vector<double>* need = nullptr,
                                 double edge_limit2 = 0.0);
  std::size_t begin(std::size_t v) const
  {
    return start64_.empty() ? first32_[v] : start64_[v];
  }
  std::size_t end(std::size_t v) const { return begin(v + 1); }
  /// f(starts), starts[v] being begin(v), as a pointer to their own type (a loop
  /// over the rows then tests the width once).
  template <typename F>
  void visitStarts(F&& f) const
  {
    if (start64_.empty())
      f(first32_);
    else
      f(start64_.data());
  }
  /// f(starts, entries): visitStarts' starts and the rows' entries as a pointer to
  /// their own type. Entry k of v's row (begin(v) <= k < end(v)) is the vertex
  /// rowEntry(entries, k, v), except in the rows of wideRows(): entry(v, k) there.
  template <typename F>
  void visitRows(F&& f) const
  {
    visitStarts([&](const auto* start) {
      if (offsets_ != nullptr)
        f(start, static_cast<const std::int16_t*>(offsets_.get()));
      else
        f(start, static_cast<const VertexId*>(ids_.get()));
    });
  }
  /// The vertices, in increasing order, whose rows hold an entry that rowEntry does
  /// not decode (a neighbour more than 32767 ids away in the 16-bit entries).
  const std::vector<VertexId>& wideRows() const { return wide_rows_; }
  /// Whether the last build was the slotted one (for the tests).
  bool slotted() const { return slotted_; }
  /// Entry k of v's row, in any row.
  VertexId entry(std::size_t v, std::size_t k) const;

  /// The 16-bit entry of a neighbour more than 32767 ids away (wide_entries_ holds it).
  static constexpr std::int16_t FAR = std::numeric_limits<std::int16_t>::min();
  /// SLOTS entries of a vertex's row the slotted build keeps in the vertex's own
  /// slot (fillSlots); the rest of a longer row waits in a side list.
  static constexpr unsigned SLOTS = 8;
  /// Whether build may take the slotted design (fillSlots, the default) or only the
  /// counting sort (fill): the same rows, starts, entries, needs and boundary either
  /// way (a test compares them).
  void allowSlots(bool allow) { slots_allowed_ = allow; }

 private:
  enum class Built { ROWS, BAD_CORNER, NOT_SLOTTED };
  /// build in one scatter instead of a count and a scatter: each vertex's entries go
  /// to a slot of SLOTS 16-bit entries (from its end: the counting sort's order) and
  /// a count byte, the few beyond SLOTS to a side list, and one sequential pass packs
  /// the slots into the rows, in place (a row of more than 255 entries counted past
  /// its full count byte in a side map). NOT_SLOTTED, nothing kept, where the design
  /// does not apply (too many far neighbours for the 16-bit entries, a far one past
  /// a row's 256th entry, 32-bit starts too narrow): fill builds the rows then.
  template <bool NEED>
  Built fillSlots(const TriangleMesh& mesh, std::vector<HalfedgeId>* boundary,
                  std::vector<double>* need, double edge_limit2);
  template <typename Index>
  bool fill(const TriangleMesh& mesh, std::vector<Index>& start,
            std::vector<HalfedgeId>* boundary, std::vector<double>* need,
            double edge_limit2);
  /// Entry k of v's row is u, more than 32767 ids away: listed; false past `limit`
  /// such entries. Out of line and cold, so that the scatter's loop keeps its values
  /// in registers (the lists' calls took them by reference: stored per entry).
  [[gnu::cold, gnu::noinline]] bool noteFar(std::size_t k, VertexId v, VertexId u,
                                            std::size_t limit);
  std::vector<std::uint32_t> start32_; ///< while the entries fit 32 bits
  std::vector<std::size_t> start64_;
  /// The 32-bit starts: start32_'s, or the slotted build's inside the entries'
  /// array, past the packed rows (fillSlots: no fresh pages for them).
  const std::uint32_t* first32_ = nullptr;
  /// The entries, uninitialised until build writes them. Vertex ids follow the
  /// points' spatial order, so a neighbour is mostly a few thousand ids away: the
  /// entries are its id less the row's vertex in 16 bits (half the bytes of ids to
  /// write, fault in and read), FAR for the few farther ones (their ids by position in
  /// wide_entries_), unless more than one entry in 2048 is: then ids.
  ScratchArray<std::int16_t> offsets_; // uninitialised, written by build
  ScratchArray<VertexId> ids_;         // uninitialised, written by build
  std::vector<std::pair<std::size_t, VertexId>> wide_entries_; ///< by position
  std::vector<VertexId> wide_rows_;
  ScratchBlock scratch_;
  ScratchBlock temporary_;
  bool slots_allowed_ = true;
  bool slotted_ = false;
};

/// The vertex of entry k of v's row (VertexRows::visitRows).
inline VertexId rowEntry(const VertexId* entries, std::size_t k, std::size_t /*v*/)
{
  return entries[k];
}
inline VertexId rowEntry(const std::int16_t* entries, std::size_t k, std::size_t v)
{
  return static_cast<VertexId>(static_cast<std::int64_t>(v) + entries[k]);
}

inline VertexId VertexRows::entry(std::size_t v, std::size_t k) const
{
  if (offsets_ == nullptr)
    return ids_[k];
  if (offsets_[k] != FAR)
    return rowEntry(offsets_.get(), k, v);
  const auto it = std::lower_bound(wide_entries_.begin(), wide_entries_.end(), k,
                                   [](const std::pair<std::size_t, VertexId>& e,
                                      std::size_t at) { return e.first < at; });
  return it->second;
}

/// The IEEE bits' range and the count of own medians over the vertices with a
/// non-empty row.
struct OwnStats {
  std::uint64_t low = ~std::uint64_t{0}, high = 0;
  std::size_t count = 0;
};

/// Per vertex the median length of the edges of its row (0 for an empty row), on
/// `threads` threads (the same figures for any value); with stats, their OwnStats;
/// with storage, in its memory (taken over: storage is left empty).
PCL_VTS_CORE_EXPORT std::vector<double>
ownMedians(const TriangleMesh& mesh, const VertexRows& rows, unsigned threads,
           OwnStats* stats = nullptr, std::vector<double>* storage = nullptr);

/// The upper median of own over the vertices with a non-empty row; with keep, its
/// histogram selection when it takes one.
PCL_VTS_CORE_EXPORT double medianOverRows(const std::vector<double>& own,
                                          const VertexRows& rows,
                                          MedianSelection* keep = nullptr);

/// The vertices ringLowerBounds clears: a bit per vertex (bit v % 64 of word v / 64).
struct ClearedVertices {
  double trim_factor = 0.0;
  std::vector<std::uint64_t> bits;
  /// The vertices with a non-empty row left uncleared, each with one of its
  /// triangles, in increasing order.
  std::vector<std::pair<VertexId, TriangleId>> uncleared;
};

/// ringLowerBound of every vertex into bound, on `threads` threads; with histogram,
/// also the histogram of own over the vertices with a non-empty row that
/// medianOverRows would count for these stats (ownMedians'), else it is left empty.
/// With cleared, bound holds on entry each vertex's slot (VertexRows::build), and
/// v's bit is set when its need <= (trim_factor * bound)^2 * Clearance::MARGIN with
/// trim_factor * bound in Clearance's range (classifyTriangles).
PCL_VTS_CORE_EXPORT void
ringLowerBounds(const VertexRows& rows, const std::vector<double>& own,
                const OwnStats& stats, unsigned threads, std::vector<double>& bound,
                MedianSelection* histogram, ClearedVertices* cleared = nullptr);

/// medianOverRows from the histogram ringLowerBounds built (keeping its selection
/// in it), or by medianOverRows when it built none.
PCL_VTS_CORE_EXPORT double medianOverRows(const std::vector<double>& own,
                                          const VertexRows& rows, const OwnStats& stats,
                                          MedianSelection& histogram);

/// The median of own over v and its row (measurePointSpacing's local figure; 0 for
/// an empty row). values: a buffer.
double localMedian(const VertexRows& rows, const std::vector<double>& own,
                   std::size_t v, std::vector<double>& values);

/// The value of index min(size / 2, 2) of own over v and its row sorted (size values),
/// a lower bound of localMedian, whose index is size / 2 (NaN when one of them is
/// NaN).
PCL_VTS_CORE_EXPORT double
ringLowerBound(const VertexRows& rows, const std::vector<double>& own, std::size_t v);

/// measurePointSpacing, also giving each vertex's own median (own may be null), on
/// `threads` threads (0 = all cores; the same figures for any value).
PointSpacing measurePointSpacing(const TriangleMesh& mesh,
                                 const std::vector<bool>* local_for,
                                 std::vector<double>* own, unsigned threads = 1);

/// Measures own[v] again on mesh for every vertex flagged in `changed` (0 for one
/// left without triangles); the others keep theirs.
void remeasureOwnSpacing(const TriangleMesh& mesh, const std::vector<bool>& changed,
                         std::vector<double>& own, unsigned threads = 1);

/// The upper median of own over the vertices flagged in `has_triangle`.
double medianOverUsed(const std::vector<double>& own,
                      const std::vector<bool>& has_triangle);

/// trimOutwardTriangles; with `after`, also the trimmed mesh's VertexSpacing; on
/// `threads` threads (0 = all cores; the same mesh for any value); its rows inside
/// `scratch` when they fit there.
Status trimOutwardTriangles(TriangleMesh& mesh, const TrimOptions& options,
                            TrimResult& result, VertexSpacing* after,
                            unsigned threads = 1, ScratchBlock scratch = {});

/// traceBoundaryLoops; with `boundary` (every halfedge without twin, in increasing
/// order), the loops start from its halfedges instead of a scan of all of them.
Status traceBoundaryLoops(const TriangleMesh& mesh, std::vector<BoundaryLoop>& loops,
                          const std::vector<HalfedgeId>* boundary);

/// fillHolesOfPart; with `spacing` (handed over by the trim of this mesh), the
/// local spacing at hole rims is read from it instead of measuring the whole mesh.
Status fillHolesOfPart(TriangleMesh& mesh, const FillOptions& options,
                       const MeshPart* part, VertexSpacing* spacing, FillResult& result,
                       unsigned threads = 1);

} // namespace pcl_vts::detail
