// Point spacing against a plain reference: medianOf is the element at size / 2 of the
// sorted values for every size (the sorting networks of short rows included), and
// measurePointSpacing's per-vertex figures are those of neighbour sets built edge by
// edge, on meshes with boundaries, holes and high-degree vertices.
#include "support/generators.h"
#include "support/pipeline_checks.h"

#include <pcl_vts/core/point_spacing.h>
#include <pcl_vts/core/trim_outward_triangles.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

namespace pcl_vts {
namespace {

double sortedMedian(std::vector<double> values)
{
  if (values.empty())
    return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

TEST(MedianOf, IsTheMiddleOfTheSortedValuesForEverySize)
{
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> small(-3, 3); // many ties
  std::uniform_real_distribution<double> real(-1e3, 1e3);
  for (std::size_t size = 0; size <= 40; ++size)
    for (int round = 0; round < 200; ++round) {
      std::vector<double> values(size);
      for (double& v : values)
        v = round % 2 == 0 ? static_cast<double>(small(rng)) : real(rng);
      if (round % 7 == 3 && size > 0)
        values[0] = std::numeric_limits<double>::infinity();
      ASSERT_EQ(medianOf(values), sortedMedian(values))
          << "size " << size << " round " << round;
    }
}

/// Per vertex: the median of its edges' lengths, then of its own and its
/// neighbours' medians (point_spacing.h), from neighbour sets.
PointSpacing referenceSpacing(const TriangleMesh& mesh)
{
  const std::size_t n = mesh.vertexCount();
  std::vector<std::set<VertexId>> around(n);
  for (HalfedgeId e = 0; e < mesh.triangles.size(); ++e) {
    const VertexId a = mesh.triangles[e], b = mesh.triangles[nextHalfedge(e)];
    around[a].insert(b);
    around[b].insert(a);
  }
  std::vector<double> own(n, 0.0), used;
  for (VertexId v = 0; v < n; ++v) {
    if (around[v].empty())
      continue;
    std::vector<double> lengths;
    for (const VertexId w : around[v]) {
      const double dx = mesh.xy[v].x - mesh.xy[w].x, dy = mesh.xy[v].y - mesh.xy[w].y;
      lengths.push_back(std::sqrt(dx * dx + dy * dy));
    }
    own[v] = sortedMedian(lengths);
    used.push_back(own[v]);
  }
  PointSpacing spacing;
  spacing.global_median = sortedMedian(used);
  spacing.local.assign(n, 0.0);
  for (VertexId v = 0; v < n; ++v) {
    if (around[v].empty())
      continue;
    std::vector<double> values{own[v]};
    for (const VertexId w : around[v])
      values.push_back(own[w]);
    spacing.local[v] = sortedMedian(values);
  }
  return spacing;
}

void expectReferenceSpacing(const TriangleMesh& mesh)
{
  const PointSpacing expected = referenceSpacing(mesh);
  const PointSpacing spacing = measurePointSpacing(mesh);
  EXPECT_EQ(spacing.global_median, expected.global_median);
  ASSERT_EQ(spacing.local.size(), expected.local.size());
  for (std::size_t v = 0; v < expected.local.size(); ++v)
    ASSERT_EQ(spacing.local[v], expected.local[v]) << "vertex " << v;
  // Local figures for flagged vertices only; the global median stays the whole's.
  std::vector<bool> flagged(mesh.vertexCount(), false);
  for (std::size_t v = 0; v < flagged.size(); v += 3)
    flagged[v] = true;
  const PointSpacing some = measurePointSpacing(mesh, &flagged);
  EXPECT_EQ(some.global_median, expected.global_median);
  for (std::size_t v = 0; v < expected.local.size(); ++v)
    ASSERT_EQ(some.local[v], flagged[v] ? expected.local[v] : 0.0) << "vertex " << v;
}

TEST(MeasurePointSpacing, MatchesNeighbourSetsOnTriangulationsAndTrimmedMeshes)
{
  using test::Distribution;
  for (const Distribution d :
       {Distribution::UNIFORM, Distribution::CLUSTERED, Distribution::BIG_VOIDS,
        Distribution::CONCENTRIC_RINGS, Distribution::ANISOTROPIC}) {
    SCOPED_TRACE(test::distributionName(d));
    const test::PipelineRun run = test::runPipeline(test::generatePoints(d, 3000, 5));
    ASSERT_TRUE(run.status.ok()) << run.status.toString();
    TriangleMesh mesh = run.result.mesh;
    expectReferenceSpacing(mesh);
    TrimResult trimmed;
    ASSERT_TRUE(trimOutwardTriangles(mesh, TrimOptions{}, trimmed).ok());
    expectReferenceSpacing(mesh); // boundary rows, vertices left without triangles
  }
}

TEST(MeasurePointSpacing, MatchesNeighbourSetsAtAVertexWithMoreThan255Edges)
{
  // A centre joined to 300 points around it: its row of 300 entries wraps the
  // byte-wide counts of VertexRows, which then counts again in full width.
  std::vector<double> xyz = {0.0, 0.0, 0.0};
  const double pi = std::acos(-1.0);
  for (int k = 0; k < 300; ++k) {
    const double angle = 2.0 * pi * k / 300.0, radius = 100.0;
    xyz.insert(xyz.end(), {radius * std::cos(angle), radius * std::sin(angle), 1.0});
  }
  const test::PipelineRun run = test::runPipeline(xyz);
  ASSERT_TRUE(run.status.ok()) << run.status.toString();
  std::size_t centre_edges = 0;
  for (const VertexId v : run.result.mesh.triangles)
    centre_edges += run.result.mesh.xy[v].x == 0.0 && run.result.mesh.xy[v].y == 0.0;
  ASSERT_GT(centre_edges, 255u);
  TriangleMesh mesh = run.result.mesh;
  expectReferenceSpacing(mesh);
  TrimResult trimmed;
  ASSERT_TRUE(trimOutwardTriangles(mesh, TrimOptions{}, trimmed).ok());
  expectReferenceSpacing(mesh);
}

/// mesh with vertex v renamed label[v] (label a permutation of the ids).
TriangleMesh relabelled(const TriangleMesh& mesh, const std::vector<VertexId>& label)
{
  TriangleMesh out = mesh;
  for (std::size_t v = 0; v < label.size(); ++v) {
    out.xy[label[v]] = mesh.xy[v];
    out.z[label[v]] = mesh.z[v];
  }
  for (VertexId& corner : out.triangles)
    corner = label[corner];
  return out;
}

TEST(MeasurePointSpacing, MatchesNeighbourSetsWithNeighboursFarApartInIds)
{
  // The rows hold a neighbour as its id less the row's vertex in 16 bits, one more
  // than 32767 ids away apart, and every neighbour as its id once more than one in
  // 2048 are. Ids renamed so that two vertices have neighbours exactly 32767 and
  // 32768 ids away (below and above), a few vertices far from their neighbours, and
  // every id shuffled; the trim of a renamed mesh is the renamed trim.
  const test::PipelineRun run =
      test::runPipeline(test::generatePoints(test::Distribution::BIG_VOIDS, 80000, 7));
  ASSERT_TRUE(run.status.ok()) << run.status.toString();
  const TriangleMesh& mesh = run.result.mesh;
  const std::size_t n = mesh.vertexCount();
  ASSERT_GT(n, 40000u);
  std::vector<VertexId> identity(n);
  for (std::size_t v = 0; v < n; ++v)
    identity[v] = static_cast<VertexId>(v);
  // Two neighbours of v (ends of halfedges leaving it) other than `not_these`.
  auto neighbours = [&](VertexId v, const std::vector<VertexId>& not_these) {
    std::vector<VertexId> found;
    for (std::size_t e = 0; e < mesh.triangles.size() && found.size() < 2; ++e) {
      const VertexId w = mesh.triangles[nextHalfedge(static_cast<HalfedgeId>(e))];
      if (mesh.triangles[e] == v &&
          std::find(not_these.begin(), not_these.end(), w) == not_these.end() &&
          std::find(found.begin(), found.end(), w) == found.end())
        found.push_back(w);
    }
    return found;
  };
  std::vector<VertexId> bounds = identity;
  auto name = [&](VertexId w, VertexId id) { // w takes id, the holder of id w's
    const auto holder = static_cast<std::size_t>(
        std::find(bounds.begin(), bounds.end(), id) - bounds.begin());
    std::swap(bounds[w], bounds[holder]);
  };
  const VertexId low = 100, high = static_cast<VertexId>(n - 100);
  const std::vector<VertexId> near_low = neighbours(low, {low, high});
  ASSERT_EQ(near_low.size(), 2u);
  const std::vector<VertexId> near_high =
      neighbours(high, {low, high, near_low[0], near_low[1]});
  ASSERT_EQ(near_high.size(), 2u);
  name(near_low[0], low + 32767);
  name(near_low[1], low + 32768);
  name(near_high[0], high - 32767);
  name(near_high[1], high - 32768);
  ASSERT_EQ(bounds[low], low);
  ASSERT_EQ(bounds[high], high);
  std::vector<VertexId> few = identity;
  for (std::size_t v = 0; v < n / 2; v += n / 6)
    std::swap(few[v], few[n - 1 - v]);
  std::vector<VertexId> shuffled = identity;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937_64(11));
  TriangleMesh trimmed = mesh;
  TrimResult expected;
  ASSERT_TRUE(trimOutwardTriangles(trimmed, TrimOptions{}, expected).ok());
  ASSERT_GT(expected.triangles_removed, 0u);
  for (const auto* label : {&identity, &bounds, &few, &shuffled}) {
    SCOPED_TRACE(label == &identity ? "identity"
                 : label == &bounds ? "bounds"
                 : label == &few    ? "few"
                                    : "shuffled");
    TriangleMesh renamed = relabelled(mesh, *label);
    expectReferenceSpacing(renamed);
    TrimResult result;
    ASSERT_TRUE(trimOutwardTriangles(renamed, TrimOptions{}, result).ok());
    EXPECT_EQ(result.triangles_removed, expected.triangles_removed);
    EXPECT_EQ(result.spacing, expected.spacing);
    const TriangleMesh expected_mesh = relabelled(trimmed, *label);
    EXPECT_EQ(renamed.triangles, expected_mesh.triangles);
    EXPECT_EQ(renamed.halfedges, expected_mesh.halfedges);
    expectReferenceSpacing(renamed);
  }
}

} // namespace
} // namespace pcl_vts
