// Point spacing: median incident edge per vertex, then a one-ring median.
#include "post_pass_spacing.h"

#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/point_spacing.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

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

/// measurePointSpacing with rows indexed by Index (32 bits while they fit).
template <typename Index>
PointSpacing measure(const TriangleMesh& mesh, const std::vector<bool>* local_for,
                     std::vector<double>* own_out, unsigned threads)
{
  const std::size_t n = mesh.vertexCount();
  const std::size_t corners = mesh.triangles.size();
  PointSpacing spacing;

  // One-ring rows by counting sort of directed edges (both directions of a boundary
  // edge): start[v] counts row v, then holds its end, and the scatter moves it back
  // to its beginning. A row's order does not matter: only its medians are read.
  std::vector<Index> start(n + 1, 0);
  for (HalfedgeId e = 0; e < corners; ++e) {
    ++start[mesh.triangles[e]];
    if (mesh.halfedges[e] == INVALID_ID) // boundary edge: seen from one side only
      ++start[mesh.triangles[nextHalfedge(e)]];
  }
  for (std::size_t v = 1; v < n; ++v)
    start[v] += start[v - 1];
  const Index total = n > 0 ? start[n - 1] : 0;
  std::vector<VertexId> ring(total);
  for (HalfedgeId e = 0; e < corners; ++e) {
    const VertexId a = mesh.triangles[e];
    const VertexId b = mesh.triangles[nextHalfedge(e)];
    ring[--start[a]] = b;
    if (mesh.halfedges[e] == INVALID_ID)
      ring[--start[b]] = a;
  }
  start[n] = total;
  // Per vertex: median incident edge length. Robust to a few long edges into a
  // void (a rim vertex keeps most of its short ones) and to anisotropic sampling
  // (scan lines: the shortest edge would only see the along-line spacing).
  // Each vertex's medians are its own slot's: ranges of vertices on any threads.
  std::vector<double> own(n, 0.0);
  parallelRanges(threads, n, [&](std::size_t begin, std::size_t end) {
    std::vector<double> values; // reused across the range: no copy per vertex
    for (std::size_t v = begin; v < end; ++v) {
      if (start[v] == start[v + 1])
        continue;
      values.clear();
      const Point2& p = mesh.xy[v];
      for (Index k = start[v]; k < start[v + 1]; ++k) {
        const Point2& q = mesh.xy[ring[k]];
        const double dx = p.x - q.x, dy = p.y - q.y;
        values.push_back(std::sqrt(dx * dx + dy * dy)); // hypot is 5x slower
      }
      own[v] = medianInPlace(values);
    }
  });
  std::vector<double> used;
  used.reserve(n);
  for (std::size_t v = 0; v < n; ++v)
    if (start[v] != start[v + 1])
      used.push_back(own[v]);
  spacing.global_median = medianInPlace(used);
  std::vector<double>().swap(used);
  spacing.local.assign(n, 0.0);
  parallelRanges(threads, n, [&](std::size_t begin, std::size_t end) {
    std::vector<double> values;
    for (std::size_t v = begin; v < end; ++v) {
      if (start[v] == start[v + 1] || (local_for != nullptr && !(*local_for)[v]))
        continue;
      values.assign(1, own[v]);
      for (Index k = start[v]; k < start[v + 1]; ++k)
        values.push_back(own[ring[k]]);
      spacing.local[v] = medianInPlace(values);
    }
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
  // A row entry per halfedge, two for a boundary one.
  if (2 * mesh.triangles.size() < std::numeric_limits<std::uint32_t>::max())
    return measure<std::uint32_t>(mesh, local_for, own, threads);
  return measure<std::size_t>(mesh, local_for, own, threads);
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
  const auto parts = static_cast<unsigned>(
      std::min<std::size_t>(threads > 0 ? threads : allCores(),
                            std::max<std::size_t>(1, mesh.triangles.size() >> 16)));
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
  remeasureOwnSpacing(trimmed, changed, own, threads);
  global_median = medianOverUsed(own, has_triangle);
  std::vector<bool>().swap(changed);
  std::vector<bool>().swap(has_triangle);
  settled = true;
}

double medianOverUsed(const std::vector<double>& own,
                      const std::vector<bool>& has_triangle)
{
  std::vector<double> used;
  used.reserve(own.size());
  for (std::size_t v = 0; v < own.size(); ++v)
    if (has_triangle[v])
      used.push_back(own[v]);
  return medianInPlace(used);
}

} // namespace detail

} // namespace pcl_vts
