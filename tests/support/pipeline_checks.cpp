// Whole-output checks of runVtsPipeline. Each invariant is decided with the exact
// predicates or by an independent construction (exact monotone-chain hull, CGAL), never
// by trusting the pipeline's own bookkeeping.
#include "support/pipeline_checks.h"

#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/predicates.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>

namespace pcl_vts {
namespace test {
namespace {

constexpr double INF = std::numeric_limits<double>::infinity();

Point2 inputXy(const std::vector<double>& xyz, std::size_t i)
{
  return {xyz[3 * i], xyz[3 * i + 1]};
}

bool isFinitePoint(const std::vector<double>& xyz, std::size_t i)
{
  return std::isfinite(xyz[3 * i]) && std::isfinite(xyz[3 * i + 1]) &&
         std::isfinite(xyz[3 * i + 2]);
}

/// The input seen by the triangulation: finite points grouped by equal XY.
struct InputClasses {
  std::vector<std::uint32_t> finite;   ///< input ids of finite points
  std::vector<std::uint32_t> rep;      ///< per input id: smallest id with equal XY
  std::vector<std::uint32_t> distinct; ///< representatives, lexicographic order
  std::size_t non_finite = 0;
};

InputClasses classify(const std::vector<double>& xyz)
{
  InputClasses c;
  const std::size_t n = xyz.size() / 3;
  c.rep.assign(n, INVALID_ID);
  for (std::size_t i = 0; i < n; ++i) {
    if (isFinitePoint(xyz, i))
      c.finite.push_back(static_cast<std::uint32_t>(i));
    else
      ++c.non_finite;
  }
  std::vector<std::uint32_t> sorted = c.finite;
  std::sort(sorted.begin(), sorted.end(), [&](std::uint32_t a, std::uint32_t b) {
    const Point2 pa = inputXy(xyz, a), pb = inputXy(xyz, b);
    return lexLess(pa, pb) || (pa == pb && a < b);
  });
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    if (k == 0 || inputXy(xyz, sorted[k]) != inputXy(xyz, sorted[k - 1]))
      c.distinct.push_back(sorted[k]);
    c.rep[sorted[k]] = c.distinct.back();
  }
  return c;
}

/// What the pipeline must answer, decided independently with exact predicates.
StatusCode expectedCode(const std::vector<double>& xyz, const InputClasses& c)
{
  if (c.finite.empty())
    return StatusCode::EMPTY_INPUT;
  if (c.distinct.size() < 3)
    return StatusCode::TOO_FEW_POINTS;
  const Point2 a = inputXy(xyz, c.distinct[0]), b = inputXy(xyz, c.distinct[1]);
  for (const std::uint32_t i : c.distinct)
    if (orient2d(a, b, inputXy(xyz, i)) != Sign::ZERO)
      return StatusCode::OK;
  return StatusCode::ALL_COLLINEAR;
}

/// Exact convex hull, collinear boundary points kept (Andrew's monotone chain that
/// pops only on a strict right turn), CCW from the lexicographically smallest point.
std::vector<Point2> referenceHull(std::vector<Point2> pts)
{
  std::sort(pts.begin(), pts.end(), lexLess);
  std::vector<Point2> hull;
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t base = hull.size();
    for (const Point2& p : pts) {
      while (hull.size() >= base + 2 &&
             orient2d(hull[hull.size() - 2], hull.back(), p) == Sign::NEGATIVE)
        hull.pop_back();
      hull.push_back(p);
    }
    hull.pop_back(); // the last point starts the other chain
    std::reverse(pts.begin(), pts.end());
  }
  return hull;
}

bool withinBox(const Point2& p, const Point2& a, const Point2& b)
{
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) &&
         std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
}

/// A CCW, weakly convex polygon prepared for point location: a fan from h[0]. The
/// first and the last edge may carry collinear vertices: h[0..first] lie on the first
/// edge's line, h[last..m-1] on the closing edge's line.
struct ConvexPolygon {
  std::vector<Point2> h;
  std::size_t first = 1;
  std::size_t last = 1;

  explicit ConvexPolygon(std::vector<Point2> vertices)
      : h(std::move(vertices))
  {
    const std::size_t m = h.size();
    while (first + 1 < m && orient2d(h[0], h[1], h[first + 1]) == Sign::ZERO)
      ++first;
    last = m - 1;
    while (last > 1 && orient2d(h[0], h[m - 1], h[last - 1]) == Sign::ZERO)
      --last;
  }

  /// p inside or on the boundary. O(log m).
  bool contains(const Point2& p) const
  {
    const Sign s1 = orient2d(h[0], h[first], p);
    if (s1 != Sign::POSITIVE)
      return s1 == Sign::ZERO && withinBox(p, h[0], h[first]);
    const Sign s2 = orient2d(h[0], h[last], p);
    if (s2 != Sign::NEGATIVE)
      return s2 == Sign::ZERO && withinBox(p, h[0], h[last]);
    // p strictly inside the wedge at h[0]: the largest i in [first, last) with p left
    // of or on h[0] -> h[i] (monotone in i) names the fan triangle, never flat here.
    std::size_t lo = first, hi = last - 1;
    while (lo < hi) {
      const std::size_t mid = (lo + hi + 1) / 2;
      if (orient2d(h[0], h[mid], p) != Sign::NEGATIVE)
        lo = mid;
      else
        hi = mid - 1;
    }
    return orient2d(h[lo], h[lo + 1], p) != Sign::NEGATIVE;
  }
};

/// Twice the hull area, shoelace around h[0] (differences first: UTM-safe).
double twiceHullArea(const std::vector<Point2>& h)
{
  double sum = 0.0;
  for (std::size_t i = 1; i + 1 < h.size(); ++i)
    sum += (h[i].x - h[0].x) * (h[i + 1].y - h[0].y) -
           (h[i].y - h[0].y) * (h[i + 1].x - h[0].x);
  return sum;
}

/// Per distinct position, the z and source ids the duplicate rule allows.
void expectDuplicateRule(const std::vector<double>& xyz, const InputClasses& c,
                         const VtsResult& r, DuplicateRule rule)
{
  // Input ids per representative, in input order.
  std::vector<std::vector<std::uint32_t>> members(xyz.size() / 3);
  for (const std::uint32_t i : c.finite)
    members[c.rep[i]].push_back(i);
  int failures = 0;
  for (std::size_t v = 0; v < r.mesh.vertexCount() && failures < 5; ++v) {
    const std::uint32_t src = r.source_index[v];
    const std::vector<std::uint32_t>& group = members[c.rep[src]];
    double lo = INF, hi = -INF, sum = 0.0;
    for (const std::uint32_t i : group) {
      lo = std::min(lo, xyz[3 * i + 2]);
      hi = std::max(hi, xyz[3 * i + 2]);
      sum += xyz[3 * i + 2];
    }
    const double z = r.mesh.z[v];
    bool ok = true;
    switch (rule) {
    case DuplicateRule::LOWEST_Z:
      ok = z == lo && xyz[3 * src + 2] == lo;
      break;
    case DuplicateRule::HIGHEST_Z:
      ok = z == hi && xyz[3 * src + 2] == hi;
      break;
    case DuplicateRule::MEAN_Z: {
      const double mean = sum / static_cast<double>(group.size());
      ok = std::fabs(z - mean) <= 1e-12 * (std::fabs(mean) + 1.0) &&
           src == group.front();
      break;
    }
    case DuplicateRule::FIRST:
      ok = src == group.front() && z == xyz[3 * src + 2];
      break;
    }
    if (!ok) {
      ++failures;
      ADD_FAILURE() << "vertex " << v << " (" << group.size()
                    << " input points, source " << src << ") has z = " << z
                    << " against rule " << duplicateRuleName(rule) << " (min " << lo
                    << ", max " << hi << ", first id " << group.front() << ")";
    }
  }
}

/// Canonical triangles of the result, ids mapped to input representatives.
std::vector<IndexTriangle> resultTriangles(const VtsResult& r, const InputClasses& c)
{
  std::vector<std::uint32_t> map(r.mesh.vertexCount());
  for (std::size_t v = 0; v < map.size(); ++v)
    map[v] = c.rep[r.source_index[v]];
  return test::canonicalTriangles(r.mesh.triangles, map);
}

/// CGAL on the finite input points, ids mapped to input representatives. ties is set
/// when some interior edge of the result has 4 exactly cocircular points.
std::vector<IndexTriangle> oracleTriangles(const std::vector<double>& xyz,
                                           const InputClasses& c, bool mirrored,
                                           bool* ties)
{
  std::vector<Point2> pts;
  pts.reserve(c.finite.size());
  for (const std::uint32_t i : c.finite)
    pts.push_back(inputXy(xyz, i));
  const std::vector<IndexTriangle> raw =
      mirrored ? test::cgalDelaunayMirrored(pts) : test::cgalDelaunay(pts);
  if (ties) {
    TriangleMesh mesh;
    mesh.xy = pts;
    mesh.z.assign(pts.size(), 0.0);
    for (const IndexTriangle& t : raw)
      mesh.triangles.insert(mesh.triangles.end(), t.begin(), t.end());
    EXPECT_TRUE(mesh.rebuildHalfedges());
    *ties = false;
    for (std::size_t e = 0; e < mesh.halfedges.size() && !*ties; ++e) {
      const HalfedgeId twin = mesh.halfedges[e];
      if (twin == INVALID_ID)
        continue;
      const auto he = static_cast<HalfedgeId>(e);
      *ties = incircle(pts[mesh.triangles[he]], pts[mesh.triangles[nextHalfedge(he)]],
                       pts[mesh.triangles[prevHalfedge(he)]],
                       pts[mesh.triangles[prevHalfedge(twin)]]) == Sign::ZERO;
    }
  }
  std::vector<std::uint32_t> map(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k)
    map[k] = c.rep[c.finite[k]];
  std::vector<std::uint32_t> flat;
  flat.reserve(3 * raw.size());
  for (const IndexTriangle& t : raw)
    flat.insert(flat.end(), t.begin(), t.end());
  return test::canonicalTriangles(flat, map);
}

/// First few differences between two canonical triangle lists, for the message.
std::string describeDifference(const std::vector<IndexTriangle>& ours,
                               const std::vector<IndexTriangle>& theirs)
{
  std::vector<IndexTriangle> only_ours, only_theirs;
  std::set_difference(ours.begin(), ours.end(), theirs.begin(), theirs.end(),
                      std::back_inserter(only_ours));
  std::set_difference(theirs.begin(), theirs.end(), ours.begin(), ours.end(),
                      std::back_inserter(only_theirs));
  std::ostringstream out;
  out << ours.size() << " vs " << theirs.size() << " triangles; " << only_ours.size()
      << " only in pcl_vts, " << only_theirs.size() << " only in CGAL. e.g.";
  for (std::size_t k = 0; k < std::min<std::size_t>(3, only_ours.size()); ++k)
    out << " ours(" << only_ours[k][0] << "," << only_ours[k][1] << ","
        << only_ours[k][2] << ")";
  for (std::size_t k = 0; k < std::min<std::size_t>(3, only_theirs.size()); ++k)
    out << " cgal(" << only_theirs[k][0] << "," << only_theirs[k][1] << ","
        << only_theirs[k][2] << ")";
  return out.str();
}

} // namespace

PipelineRun runPipeline(const std::vector<double>& xyz, const VtsOptions& options)
{
  PipelineRun run;
  run.status = runVtsPipeline(xyz.empty() ? nullptr : xyz.data(), xyz.size() / 3,
                              options, run.result);
  return run;
}

StatusCode expectedStatusCode(const std::vector<double>& xyz)
{
  return expectedCode(xyz, classify(xyz));
}

/// Every interior edge strictly locally Delaunay under the perturbation: the
/// triangulation is then the unique Delaunay triangulation of the perturbed set.
bool isPerturbedDelaunay(const TriangleMesh& mesh, std::string* why)
{
  for (std::size_t i = 0; i < mesh.halfedges.size(); ++i) {
    const auto e = static_cast<HalfedgeId>(i);
    const HalfedgeId twin = mesh.halfedges[e];
    if (twin == INVALID_ID || twin < e)
      continue;
    const VertexId a = mesh.triangles[e], b = mesh.triangles[nextHalfedge(e)];
    const VertexId c = mesh.triangles[prevHalfedge(e)];
    const VertexId d = mesh.triangles[prevHalfedge(twin)];
    if (incirclePerturbed(mesh.xy[a], mesh.xy[b], mesh.xy[c], mesh.xy[d]) !=
        Sign::NEGATIVE) {
      std::ostringstream out;
      out << "edge " << a << "-" << b << " (triangles " << triangleOf(e) << ", "
          << triangleOf(twin) << ") breaks the lexicographic tie-break: vertex " << d
          << " is not outside the perturbed circle of " << a << ", " << b << ", " << c;
      if (why)
        *why = out.str();
      return false;
    }
  }
  return true;
}

namespace {

/// Every invariant of a successful run, plus the comparison with CGAL.
void checkTriangulation(const std::vector<double>& xyz, const PipelineRun& run,
                        const VtsOptions& options, ValidationSummary& summary)
{
  const InputClasses c = classify(xyz);
  const VtsResult& r = run.result;
  const TriangleMesh& mesh = r.mesh;
  const std::size_t n = c.distinct.size();
  ASSERT_TRUE(run.status.ok()) << run.status.toString();

  // Vertices: exactly the distinct finite positions, mapped both ways.
  ASSERT_EQ(mesh.vertexCount(), n);
  ASSERT_EQ(mesh.xy.size(), n);
  ASSERT_EQ(r.source_index.size(), n);
  ASSERT_EQ(r.input_to_vertex.size(), xyz.size() / 3);
  for (std::size_t v = 0; v < n; ++v) {
    ASSERT_LT(r.source_index[v], xyz.size() / 3);
    ASSERT_EQ(mesh.xy[v], inputXy(xyz, r.source_index[v])) << "vertex " << v;
    ASSERT_EQ(r.input_to_vertex[r.source_index[v]], v) << "vertex " << v;
  }
  for (std::size_t i = 0; i < xyz.size() / 3; ++i) {
    if (!isFinitePoint(xyz, i)) {
      ASSERT_EQ(r.input_to_vertex[i], INVALID_ID) << "dropped input " << i;
      continue;
    }
    ASSERT_LT(r.input_to_vertex[i], n) << "input " << i;
    ASSERT_EQ(mesh.xy[r.input_to_vertex[i]], inputXy(xyz, i)) << "input " << i;
  }
  expectDuplicateRule(xyz, c, r, options.duplicate_rule);
  // Preconditions of everything below (no out-of-range reads on a broken result).
  ASSERT_EQ(mesh.triangles.size() % 3, 0u);
  ASSERT_EQ(mesh.halfedges.size(), mesh.triangles.size());
  for (const VertexId v : mesh.triangles)
    ASSERT_LT(v, n) << "triangle vertex id out of range";

  // Counts and diagnostics.
  const std::size_t h = r.hull.size();
  summary.distinct_points = n;
  summary.hull_vertices = h;
  ASSERT_GE(h, 3u);
  EXPECT_EQ(mesh.triangleCount(), 2 * n - h - 2) << "n = " << n << ", h = " << h;
  EXPECT_EQ(r.diagnostics.points_in, xyz.size() / 3);
  EXPECT_EQ(r.diagnostics.non_finite_dropped, c.non_finite);
  EXPECT_EQ(r.diagnostics.duplicates_merged, c.finite.size() - n);
  EXPECT_EQ(r.diagnostics.distinct_points, n);
  EXPECT_EQ(r.diagnostics.hull_vertices, h);
  EXPECT_EQ(r.diagnostics.triangles, mesh.triangleCount());

  // Topology and the Delaunay property, exactly.
  std::string why;
  EXPECT_TRUE(allTrianglesCcw(mesh, &why)) << why;
  EXPECT_TRUE(halfedgesConsistent(mesh, &why)) << why;
  EXPECT_TRUE(isEdgeManifold(mesh, &why)) << why;
  EXPECT_TRUE(allVerticesUsed(mesh, &why)) << why;
  EXPECT_TRUE(isDelaunay(mesh, &why)) << why;
  EXPECT_EQ(eulerCharacteristic(mesh), 1);
  EXPECT_EQ(boundaryEdgeCount(mesh), h);
  TriangleMesh rebuilt = mesh;
  EXPECT_TRUE(rebuilt.rebuildHalfedges());
  EXPECT_EQ(rebuilt.halfedges, mesh.halfedges) << "twins differ from a fresh match";
  if (halfedgesConsistent(mesh)) {
    EXPECT_TRUE(isPerturbedDelaunay(mesh, &why)) << why;
  }

  // Hull: the exact convex hull (collinear points kept), CCW, containing every
  // point, its edges the boundary of the mesh, its area the mesh's area.
  std::vector<Point2> hull;
  for (const VertexId v : r.hull) {
    ASSERT_LT(v, n);
    hull.push_back(mesh.xy[v]);
  }
  for (std::size_t i = 0; i < h; ++i)
    EXPECT_NE(orient2d(hull[i], hull[(i + 1) % h], hull[(i + 2) % h]), Sign::NEGATIVE)
        << "hull turns right at hull vertex " << (i + 1) % h;
  std::vector<Point2> reference = referenceHull(mesh.xy);
  const auto smallest = std::min_element(hull.begin(), hull.end(), lexLess);
  std::rotate(hull.begin(), smallest, hull.end());
  EXPECT_TRUE(hull == reference)
      << "hull has " << h << " vertices, the exact hull " << reference.size();
  std::size_t outside = 0;
  const ConvexPolygon polygon(hull);
  for (const Point2& p : mesh.xy)
    outside += !polygon.contains(p);
  EXPECT_EQ(outside, 0u) << "points outside the hull";
  std::vector<std::uint64_t> boundary, hull_edges;
  for (std::size_t e = 0; e < mesh.halfedges.size(); ++e)
    if (mesh.halfedges[e] == INVALID_ID)
      boundary.push_back((std::uint64_t{mesh.triangles[e]} << 32) |
                         mesh.triangles[nextHalfedge(static_cast<HalfedgeId>(e))]);
  for (std::size_t i = 0; i < h; ++i)
    hull_edges.push_back((std::uint64_t{r.hull[i]} << 32) | r.hull[(i + 1) % h]);
  std::sort(boundary.begin(), boundary.end());
  std::sort(hull_edges.begin(), hull_edges.end());
  EXPECT_TRUE(boundary == hull_edges) << "mesh boundary is not the hull polygon";
  // Areas in doubles underflow for subnormal extents; CCW above is exact anyway.
  const double hull_area = twiceHullArea(hull);
  if (hull_area > 0x1p-900) {
    EXPECT_NEAR(twiceArea(mesh), hull_area, 1e-9 * hull_area);
  }

  // The oracle. Mirrored CGAL uses pcl_vts' tie-break, so it must match with or
  // without ties; without ties plain CGAL must match too (the triangulation is unique).
  const std::vector<IndexTriangle> ours = resultTriangles(r, c);
  bool ties = false;
  const std::vector<IndexTriangle> mirrored = oracleTriangles(xyz, c, true, &ties);
  summary.cocircular_ties = ties;
  EXPECT_TRUE(ours == mirrored)
      << (ties ? "with" : "without")
      << " cocircular ties: " << describeDifference(ours, mirrored);
  if (!ties) {
    const std::vector<IndexTriangle> plain = oracleTriangles(xyz, c, false, nullptr);
    EXPECT_TRUE(ours == plain) << describeDifference(ours, plain);
  }
}

} // namespace

ValidationSummary expectValidTriangulation(const std::vector<double>& xyz,
                                           const PipelineRun& run,
                                           const VtsOptions& options)
{
  ValidationSummary summary;
  checkTriangulation(xyz, run, options, summary);
  return summary;
}

/// Triangles as coordinates: each vertex replaced by its lexicographic rank among the
/// mesh's positions, so two runs over permuted inputs compare directly.
std::vector<IndexTriangle> trianglesByPosition(const TriangleMesh& mesh)
{
  std::vector<std::uint32_t> order(mesh.vertexCount());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return lexLess(mesh.xy[a], mesh.xy[b]);
  });
  std::vector<std::uint32_t> rank(order.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    rank[order[k]] = static_cast<std::uint32_t>(k);
  return test::canonicalTriangles(mesh.triangles, rank);
}

} // namespace test
} // namespace pcl_vts
