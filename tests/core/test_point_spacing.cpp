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

} // namespace
} // namespace pcl_vts
