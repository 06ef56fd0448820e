// The trim's compaction (src/core/trim_compaction.h): the survivors in their order,
// the twins remapped, the open halfedges listed, against a plain renumbering; its
// AVX2 loop (when the CPU has it) and its portable loop, on 1-3 threads, for dropped
// triangles at the ends of the mesh, in runs of every length (so runs end at every
// position of the loops' groups of four and eight halfedges), sparse and dense.
#include "../../src/core/trim_compaction.h"
#include "support/generators.h"
#include "support/pipeline_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace pcl_vts {
namespace {

struct Compacted {
  std::vector<VertexId> triangles;
  std::vector<HalfedgeId> halfedges, boundary;
};

/// The oracle: every survivor's new id from a count of the dropped ones before it.
Compacted renumbered(const TriangleMesh& mesh, const std::vector<TriangleId>& dropped)
{
  const std::size_t count = mesh.triangleCount();
  std::vector<bool> gone(count, false);
  for (const TriangleId t : dropped)
    gone[t] = true;
  std::vector<TriangleId> new_id(count, INVALID_ID);
  TriangleId next = 0;
  for (std::size_t t = 0; t < count; ++t)
    if (!gone[t])
      new_id[t] = next++;
  Compacted out;
  for (std::size_t t = 0; t < count; ++t) {
    if (gone[t])
      continue;
    for (std::size_t k = 0; k < 3; ++k) {
      out.triangles.push_back(mesh.triangles[3 * t + k]);
      const HalfedgeId twin = mesh.halfedges[3 * t + k];
      const HalfedgeId remapped = twin == INVALID_ID || gone[twin / 3]
                                      ? INVALID_ID
                                      : 3 * new_id[twin / 3] + twin % 3;
      if (remapped == INVALID_ID)
        out.boundary.push_back(static_cast<HalfedgeId>(out.halfedges.size()));
      out.halfedges.push_back(remapped);
    }
  }
  return out;
}

void expectCompaction(const TriangleMesh& mesh, std::vector<TriangleId> dropped,
                      const std::string& what)
{
  std::sort(dropped.begin(), dropped.end());
  dropped.erase(std::unique(dropped.begin(), dropped.end()), dropped.end());
  ASSERT_FALSE(dropped.empty()) << what;
  const Compacted expected = renumbered(mesh, dropped);
  // Any order of the dropped ids: the trim hands them in its flood's order.
  std::vector<TriangleId> shuffled = dropped;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937_64(dropped.size()));
  for (const detail::CompactionLoop loop :
       {detail::CompactionLoop::BEST, detail::CompactionLoop::PORTABLE})
    for (unsigned threads = 1; threads <= 3; ++threads) {
      TriangleMesh copy = mesh;
      std::vector<HalfedgeId> boundary{7}; // replaced
      detail::compactTriangles(copy, shuffled, threads, &boundary, loop);
      const std::string where =
          what + (loop == detail::CompactionLoop::BEST ? ", best loop" : ", portable") +
          ", threads " + std::to_string(threads);
      EXPECT_EQ(copy.xy.size(), mesh.xy.size()) << where;
      EXPECT_TRUE(copy.triangles == expected.triangles) << where;
      EXPECT_TRUE(copy.halfedges == expected.halfedges) << where;
      EXPECT_TRUE(boundary == expected.boundary) << where;
      TriangleMesh without_boundary = mesh;
      detail::compactTriangles(without_boundary, shuffled, threads, nullptr, loop);
      EXPECT_TRUE(without_boundary.halfedges == expected.halfedges) << where;
    }
}

TEST(TrimCompaction, EveryLoopMatchesARenumbering)
{
  if (!detail::compactionHasAvx2())
    std::printf("note: this CPU has no AVX2; only the portable loop is compared\n");
  // 70000 jittered points: about 140000 triangles, so two and three threads take
  // ranges of their own (a range per 65536 triangles).
  const test::PipelineRun run = test::runPipeline(
      test::generatePoints(test::Distribution::JITTERED_GRID, 70000, 3));
  ASSERT_TRUE(run.status.ok()) << run.status.toString();
  const TriangleMesh& mesh = run.result.mesh;
  const auto count = static_cast<TriangleId>(mesh.triangleCount());
  ASSERT_GT(count, 2u * 65536u);
  std::mt19937_64 random(15);
  auto any = [&] { return static_cast<TriangleId>(random() % count); };

  expectCompaction(mesh, {0}, "the first triangle");
  expectCompaction(mesh, {count - 1}, "the last triangle");
  expectCompaction(mesh, {0, 1, 2, count - 3, count - 2, count - 1}, "both ends");
  {
    std::vector<TriangleId> all_but_one;
    for (TriangleId t = 1; t < count; ++t)
      all_but_one.push_back(t);
    expectCompaction(mesh, all_but_one, "all but the first");
    all_but_one.back() = 0;
    expectCompaction(mesh, all_but_one, "all but the last");
  }
  {
    // Runs of survivors of every length from 0 to 40 triangles (0 to 120 halfedges),
    // each after a dropped triangle: every end of a run modulo 4 and 8.
    std::vector<TriangleId> steps;
    TriangleId t = 0;
    for (TriangleId length = 0; t < count; length = (length + 1) % 41) {
      steps.push_back(t);
      t += length + 1;
    }
    expectCompaction(mesh, steps, "runs of every length");
  }
  {
    // Sparse (one in 600, as the trim of jittered points), with runs of 1-30
    // consecutive dropped triangles, the first and the last, and around the
    // threads' range borders.
    std::vector<TriangleId> sparse{0, count - 1};
    for (TriangleId k = 0; k < count / 600; ++k)
      sparse.push_back(any());
    for (int k = 0; k < 40; ++k) {
      const TriangleId start = any(),
                       length = 1 + static_cast<TriangleId>(random() % 30);
      for (TriangleId u = start; u < std::min(count, start + length); ++u)
        sparse.push_back(u);
    }
    for (const TriangleId border :
         {(count + 1) / 2, (count + 2) / 3, 2 * ((count + 2) / 3)})
      for (TriangleId u = border - 2; u < border + 2; ++u)
        sparse.push_back(u);
    expectCompaction(mesh, sparse, "sparse and clustered");
  }
  {
    // Dense: one in three, and a wide band in the middle (every twin of its rim
    // leads into the dropped triangles).
    std::vector<TriangleId> dense, band;
    for (TriangleId k = 0; k < count / 3; ++k)
      dense.push_back(any());
    expectCompaction(mesh, dense, "dense");
    for (TriangleId u = count / 3; u < 2 * (count / 3); ++u)
      band.push_back(u);
    expectCompaction(mesh, band, "a band");
  }
  // A small mesh: runs shorter than one group of eight halfedges.
  const test::PipelineRun small =
      test::runPipeline(test::generatePoints(test::Distribution::UNIFORM, 40, 5));
  ASSERT_TRUE(small.status.ok()) << small.status.toString();
  const auto small_count = static_cast<TriangleId>(small.result.mesh.triangleCount());
  for (TriangleId t = 0; t < small_count; ++t)
    expectCompaction(small.result.mesh, {t, (t * 7 + 3) % small_count}, "small mesh");
}

} // namespace
} // namespace pcl_vts
