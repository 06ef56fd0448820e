// The trim's vertex rows (detail::VertexRows): the slotted build (one scatter into
// fixed slots, the longer rows' extra entries apart, then a packing pass) gives the
// same starts, entries, far-neighbour lists, needs and boundary list as the counting
// sort, on triangulations and on meshes made to reach each of its rules: rows longer
// than the slots, a long row at the first vertex (the packing cannot stay in place),
// far neighbours in and past the slots, too many far neighbours (32-bit ids), rows
// of more than 255 entries (past the full count byte), a far neighbour past a row's
// 256th entry (the counting sort builds those rows), a corner that is no vertex.
#include "../../src/core/post_pass_spacing.h"
#include "support/generators.h"
#include "support/mesh_shuffle.h"
#include "support/pipeline_checks.h"
#include "support/special_triangles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

namespace pcl_vts {
namespace {

/// Everything a build leaves for its readers.
struct BuiltRows {
  bool built = false;
  bool slotted = false; ///< built by the slotted scatter
  std::vector<std::size_t> begins;
  std::vector<VertexId> entries; ///< entry(v, k), row after row
  std::vector<std::int64_t> raw; ///< visitRows' entries as stored
  bool sixteen_bits = false;     ///< visitRows gave 16-bit entries
  std::vector<VertexId> wide_rows;
  std::vector<std::uint64_t> needs; ///< the need slots' bits
  std::vector<HalfedgeId> boundary;
};

BuiltRows buildRows(const TriangleMesh& mesh, bool slots, bool with_need,
                    bool with_boundary, detail::ScratchBlock scratch = {})
{
  detail::VertexRows rows(scratch);
  rows.allowSlots(slots);
  BuiltRows out;
  std::vector<double> need;
  std::vector<HalfedgeId> boundary;
  out.built = rows.build(mesh, with_boundary ? &boundary : nullptr,
                         with_need ? &need : nullptr, 2.5e3);
  if (!out.built)
    return out;
  out.slotted = rows.slotted();
  const std::size_t n = mesh.vertexCount();
  for (std::size_t v = 0; v <= n; ++v)
    out.begins.push_back(rows.begin(v));
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t k = rows.begin(v); k < rows.end(v); ++k)
      out.entries.push_back(rows.entry(v, k));
  rows.visitRows([&](const auto* start, const auto* entries) {
    out.sixteen_bits = sizeof(*entries) == 2;
    for (std::size_t k = 0; k < start[n]; ++k)
      out.raw.push_back(static_cast<std::int64_t>(entries[k]));
  });
  out.wide_rows = rows.wideRows();
  for (const double value : need)
    out.needs.push_back(detail::Clearance::slot(value));
  out.boundary = boundary;
  return out;
}

/// The slotted build equals the counting sort's, with and without the needs and the
/// boundary list, in a scratch block and without one; the width of the entries is
/// returned (16 or 32 bits).
bool expectSameRows(const TriangleMesh& mesh)
{
  bool sixteen = false;
  for (const bool with_need : {true, false})
    for (const bool with_boundary : {true, false}) {
      SCOPED_TRACE(::testing::Message()
                   << "need " << with_need << " boundary " << with_boundary);
      const BuiltRows counted = buildRows(mesh, false, with_need, with_boundary);
      const BuiltRows slotted = buildRows(mesh, true, with_need, with_boundary);
      // A scratch block as the pipeline lends it: 24 bytes a vertex.
      std::vector<double> lent(3 * mesh.vertexCount() + 1, 0.5);
      const BuiltRows in_scratch =
          buildRows(mesh, true, with_need, with_boundary,
                    detail::ScratchBlock{lent.data() + 1,
                                         (lent.size() - 1) * sizeof(double), nullptr});
      for (const BuiltRows* other : {&slotted, &in_scratch}) {
        EXPECT_EQ(other->built, counted.built);
        EXPECT_EQ(other->begins, counted.begins);
        EXPECT_EQ(other->entries, counted.entries);
        EXPECT_EQ(other->raw, counted.raw);
        EXPECT_EQ(other->sixteen_bits, counted.sixteen_bits);
        EXPECT_EQ(other->wide_rows, counted.wide_rows);
        EXPECT_EQ(other->needs, counted.needs);
        EXPECT_EQ(other->boundary, counted.boundary);
      }
      sixteen = counted.sixteen_bits;
    }
  return sixteen;
}

/// mesh with ids a and b exchanged.
TriangleMesh swapped(TriangleMesh mesh, VertexId a, VertexId b)
{
  std::swap(mesh.xy[a], mesh.xy[b]);
  std::swap(mesh.z[a], mesh.z[b]);
  for (VertexId& corner : mesh.triangles)
    corner = corner == a ? b : corner == b ? a : corner;
  return mesh;
}

/// The vertex with the longest row (most triangle corners).
VertexId busiest(const TriangleMesh& mesh)
{
  std::vector<std::size_t> corners(mesh.vertexCount(), 0);
  for (const VertexId v : mesh.triangles)
    ++corners[v];
  return static_cast<VertexId>(std::max_element(corners.begin(), corners.end()) -
                               corners.begin());
}

/// A centre joined to `rim` points on a circle around it (a row of rim + 1 or more
/// entries at the centre), the centre then renamed `centre_id`.
TriangleMesh star(int rim, VertexId centre_id)
{
  std::vector<double> xyz = {0.0, 0.0, 0.0};
  const double pi = std::acos(-1.0);
  for (int k = 0; k < rim; ++k) {
    const double angle = 2.0 * pi * k / rim;
    xyz.insert(xyz.end(), {100.0 * std::cos(angle), 100.0 * std::sin(angle), 1.0});
  }
  const test::PipelineRun run = test::runPipeline(xyz);
  EXPECT_TRUE(run.status.ok()) << run.status.toString();
  const TriangleMesh& mesh = run.result.mesh;
  return swapped(mesh, busiest(mesh), centre_id);
}

TEST(VertexRows, SlottedEqualsCountedOnTriangulations)
{
  using test::Distribution;
  for (const Distribution d :
       {Distribution::UNIFORM, Distribution::CLUSTERED, Distribution::JITTERED_GRID,
        Distribution::EXACT_GRID, Distribution::BIG_VOIDS,
        Distribution::CONCENTRIC_RINGS, Distribution::THIN_STRIP}) {
    SCOPED_TRACE(test::distributionName(d));
    const test::PipelineRun run = test::runPipeline(test::generatePoints(d, 20000, 3));
    ASSERT_TRUE(run.status.ok()) << run.status.toString();
    const TriangleMesh& mesh = run.result.mesh;
    // Uniform points give rows longer than the slots (hull corners, busy vertices).
    std::vector<std::size_t> corners(mesh.vertexCount(), 0);
    for (const VertexId v : mesh.triangles)
      ++corners[v];
    if (d == Distribution::UNIFORM) {
      ASSERT_GT(*std::max_element(corners.begin(), corners.end()),
                std::size_t{detail::VertexRows::SLOTS});
    }
    EXPECT_TRUE(expectSameRows(mesh));
  }
}

TEST(VertexRows, SlottedEqualsCountedWithLongRowsAtTheFirstVertices)
{
  // The first vertex's row longer than its slot: packed in place, its slot's block
  // would overwrite the second slot, so the rows go to an array of their own; the
  // same row at the last vertex (no slot after it) and in the middle.
  for (const int rim : {9, 20, 200, 254}) {
    SCOPED_TRACE(rim);
    const TriangleMesh first = star(rim, 0);
    ASSERT_GT(std::count(first.triangles.begin(), first.triangles.end(), VertexId{0}),
              detail::VertexRows::SLOTS - 1);
    EXPECT_TRUE(expectSameRows(first));
    EXPECT_TRUE(expectSameRows(star(rim, static_cast<VertexId>(rim))));
    EXPECT_TRUE(expectSameRows(star(rim, static_cast<VertexId>(rim / 2))));
  }
}

/// The vertices and triangles of a, then those of b (ids and twins shifted).
TriangleMesh joined(const TriangleMesh& a, const TriangleMesh& b)
{
  TriangleMesh out = a;
  const auto vertices = static_cast<VertexId>(a.vertexCount());
  const auto halfedges = static_cast<HalfedgeId>(a.halfedges.size());
  out.xy.insert(out.xy.end(), b.xy.begin(), b.xy.end());
  out.z.insert(out.z.end(), b.z.begin(), b.z.end());
  for (const VertexId v : b.triangles)
    out.triangles.push_back(v + vertices);
  for (const HalfedgeId e : b.halfedges)
    out.halfedges.push_back(e == INVALID_ID ? INVALID_ID : e + halfedges);
  return out;
}

TEST(VertexRows, SlottedEqualsCountedWithMoreThan255Entries)
{
  // A row of more than 255 entries fills its count byte: the entries past it are
  // counted apart, and the slotted build still makes the rows.
  for (const int rim : {254, 255, 256, 300, 700}) {
    SCOPED_TRACE(rim);
    for (const VertexId centre :
         {VertexId{0}, static_cast<VertexId>(rim / 3), static_cast<VertexId>(rim)}) {
      const TriangleMesh mesh = star(rim, centre);
      EXPECT_TRUE(expectSameRows(mesh));
      EXPECT_TRUE(buildRows(mesh, true, true, true).slotted);
    }
  }
}

TEST(VertexRows, SlottedLeavesAFarNeighbourPastTheRowsFirst256ToTheCountingSort)
{
  // A star's centre moved more than 32767 ids from its rim, in a mesh with corners
  // enough (one in 2048 may be far) for all 600 far entries, the rim's 300 and the
  // centre's 300: the 16-bit rows with a far list. The centre's entries past its
  // 256th no longer fit the far list's 8-bit place in the row: the counting sort.
  const test::PipelineRun run =
      test::runPipeline(test::generatePoints(test::Distribution::UNIFORM, 230000, 5));
  ASSERT_TRUE(run.status.ok()) << run.status.toString();
  const TriangleMesh near = joined(star(300, 0), run.result.mesh);
  const auto last = static_cast<VertexId>(near.vertexCount() - 1);
  ASSERT_GT(near.triangles.size() / 2048, 2u * 300u);
  EXPECT_TRUE(buildRows(near, true, true, true).slotted);
  const TriangleMesh far = swapped(near, 0, last);
  EXPECT_TRUE(expectSameRows(far)); // 16-bit entries
  EXPECT_FALSE(buildRows(far, true, true, true).slotted);
  // A centre of 255 entries: every far one in place, slotted.
  const TriangleMesh shorter_near = joined(star(255, 0), run.result.mesh);
  const TriangleMesh shorter =
      swapped(shorter_near, 0, static_cast<VertexId>(shorter_near.vertexCount() - 1));
  EXPECT_TRUE(expectSameRows(shorter));
  EXPECT_TRUE(buildRows(shorter, true, true, true).slotted);
}

TEST(VertexRows, SlottedEqualsCountedWithFarNeighbours)
{
  const test::PipelineRun run =
      test::runPipeline(test::generatePoints(test::Distribution::BIG_VOIDS, 80000, 11));
  ASSERT_TRUE(run.status.ok()) << run.status.toString();
  const TriangleMesh& mesh = run.result.mesh;
  const std::size_t n = mesh.vertexCount();
  ASSERT_GT(n, 70000u);
  // A few vertices far from their neighbours in ids: 16-bit entries with FAR ones,
  // some in the slots, some past them (the busiest vertex's row, longer than its
  // slot, moved to the far end).
  TriangleMesh few = swapped(mesh, busiest(mesh), static_cast<VertexId>(n - 1));
  for (VertexId k = 0; k < 4; ++k)
    few = swapped(few, 1000 + 97 * k, static_cast<VertexId>(n - 2 - 3000 * k));
  EXPECT_TRUE(expectSameRows(few));
  BuiltRows rows = buildRows(few, true, true, true);
  EXPECT_TRUE(rows.sixteen_bits);
  EXPECT_FALSE(rows.wide_rows.empty());
  // Every id shuffled: more than one far neighbour in 2048, 32-bit ids.
  EXPECT_FALSE(expectSameRows(test::shuffledIds(mesh, 5)));
}

TEST(VertexRows, SlottedNeedsEqualTheCountedOnesOnSpecialTriangles)
{
  // Triangles of their own (no twins) with ordinary, obtuse, degenerate, tiny, huge
  // and non-finite corners: the slotted scatter's needs equal the counting sort's
  // against several edge limits. Each vertex in one triangle: its slot is that
  // triangle's need.
  std::mt19937_64 random(21);
  constexpr double INF = std::numeric_limits<double>::infinity();
  TriangleMesh mesh;
  for (std::size_t t = 0; t < 40003; ++t) {
    Point2 p[3];
    test::specialTriangle(random, static_cast<int>(t % test::SPECIAL_TRIANGLE_KINDS),
                          p);
    for (const Point2& q : p) {
      mesh.triangles.push_back(static_cast<VertexId>(mesh.xy.size()));
      mesh.xy.push_back(q);
      mesh.z.push_back(0.0);
      mesh.halfedges.push_back(INVALID_ID);
    }
  }
  for (const double limit : {INF, 1e-20, 1.0, 1e6, 1e40}) {
    SCOPED_TRACE(limit);
    std::vector<std::uint64_t> bits[2];
    for (const bool slots : {false, true}) {
      detail::VertexRows rows;
      rows.allowSlots(slots);
      std::vector<double> need;
      ASSERT_TRUE(rows.build(mesh, nullptr, &need, limit));
      for (const double value : need)
        bits[slots].push_back(detail::Clearance::slot(value));
    }
    EXPECT_EQ(bits[1], bits[0]);
  }
}

TEST(VertexRows, SlottedRejectsACornerThatIsNoVertex)
{
  const test::PipelineRun run =
      test::runPipeline(test::generatePoints(test::Distribution::UNIFORM, 2000, 4));
  ASSERT_TRUE(run.status.ok()) << run.status.toString();
  for (const std::size_t at : {std::size_t{0}, std::size_t{7}, std::size_t{3000}}) {
    TriangleMesh mesh = run.result.mesh;
    ASSERT_LT(at, mesh.triangles.size());
    mesh.triangles[at] = static_cast<VertexId>(mesh.vertexCount());
    for (const bool slots : {true, false}) {
      std::vector<HalfedgeId> boundary;
      std::vector<double> need;
      detail::VertexRows rows;
      rows.allowSlots(slots);
      EXPECT_FALSE(rows.build(mesh, &boundary, &need, 1.0));
      EXPECT_TRUE(boundary.empty());
    }
  }
}

} // namespace
} // namespace pcl_vts
