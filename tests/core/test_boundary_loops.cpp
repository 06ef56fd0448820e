// Boundary loops: every twin-less halfedge in exactly one loop, loops closed and
// oriented with the mesh on their left, one outer loop per connected piece, holes
// negative, the signed areas of all loops summing to the mesh area (Green), and pinch
// vertices walked fan by fan.
#include "support/surface_checks.h"

#include <pcl_vts/core/boundary_loops.h>
#include <pcl_vts/core/mesh_checks.h>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pcl_vts {
namespace {

/// side x side unit squares, each split along its (0,0)-(1,1) diagonal; squares for
/// which keep(i, j) is false are left out. Vertex (i, j) has id j * (side + 1) + i.
TriangleMesh squareGrid(int side, bool (*keep)(int, int))
{
  TriangleMesh mesh;
  for (int j = 0; j <= side; ++j)
    for (int i = 0; i <= side; ++i) {
      mesh.xy.push_back({static_cast<double>(i), static_cast<double>(j)});
      mesh.z.push_back(0.0);
    }
  auto id = [side](int i, int j) { return static_cast<VertexId>(j * (side + 1) + i); };
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      if (!keep(i, j))
        continue;
      mesh.triangles.insert(mesh.triangles.end(),
                            {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.insert(mesh.triangles.end(),
                            {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  EXPECT_TRUE(mesh.rebuildHalfedges());
  return mesh;
}

/// Checks the properties every loop set must have, whatever the mesh.
void expectLoopInvariants(const TriangleMesh& mesh, const BoundaryLoops& loops)
{
  std::vector<int> uses(mesh.halfedges.size(), 0);
  double area_sum = 0.0;
  std::vector<int> outer(loops.componentCount(), 0);
  for (const BoundaryLoop& loop : loops.loops) {
    ASSERT_EQ(loop.halfedges.size(), loop.vertices.size());
    for (std::size_t i = 0; i < loop.halfedges.size(); ++i) {
      const HalfedgeId e = loop.halfedges[i];
      EXPECT_EQ(mesh.halfedges[e], INVALID_ID);
      ++uses[e];
      EXPECT_EQ(mesh.triangles[e], loop.vertices[i]);
      const HalfedgeId f = loop.halfedges[(i + 1) % loop.halfedges.size()];
      EXPECT_EQ(mesh.triangles[nextHalfedge(e)], mesh.triangles[f])
          << "loop not closed";
      EXPECT_EQ(loops.triangle_component[triangleOf(e)], loop.component);
    }
    area_sum += loop.twice_area;
    outer[loop.component] += loop.is_outer ? 1 : 0;
    EXPECT_EQ(loop.is_outer, loop.twice_area > 0.0);
  }
  for (std::size_t e = 0; e < mesh.halfedges.size(); ++e)
    EXPECT_EQ(uses[e], mesh.halfedges[e] == INVALID_ID ? 1 : 0) << "halfedge " << e;
  for (const int count : outer)
    EXPECT_EQ(count, 1);
  EXPECT_NEAR(area_sum, twiceArea(mesh), 1e-9 * (1.0 + std::fabs(twiceArea(mesh))));
}

TEST(BoundaryLoops, SquareHasOneCcwOuterLoop)
{
  const TriangleMesh mesh = squareGrid(4, [](int, int) { return true; });
  BoundaryLoops loops;
  ASSERT_TRUE(findBoundaryLoops(mesh, loops).ok());
  expectLoopInvariants(mesh, loops);
  ASSERT_EQ(loops.loops.size(), 1u);
  EXPECT_TRUE(loops.loops[0].is_outer);
  EXPECT_EQ(loops.loops[0].halfedges.size(), 16u);
  EXPECT_DOUBLE_EQ(loops.loops[0].twice_area, 32.0);
  EXPECT_EQ(loops.holeCount(), 0u);
  EXPECT_EQ(loops.componentCount(), 1u);
}

TEST(BoundaryLoops, MissingSquaresInsideAreClockwiseHoles)
{
  const TriangleMesh mesh = squareGrid(6, [](int i, int j) {
    return !((i == 1 && j == 1) || (i >= 3 && i <= 4 && j >= 2 && j <= 4));
  });
  BoundaryLoops loops;
  ASSERT_TRUE(findBoundaryLoops(mesh, loops).ok());
  expectLoopInvariants(mesh, loops);
  ASSERT_EQ(loops.loops.size(), 3u);
  EXPECT_EQ(loops.holeCount(), 2u);
  std::vector<double> hole_areas;
  for (const BoundaryLoop& loop : loops.loops)
    if (!loop.is_outer) {
      hole_areas.push_back(-loop.twice_area / 2);
      EXPECT_FALSE(loop.has_repeated_vertex);
    }
  std::sort(hole_areas.begin(), hole_areas.end());
  EXPECT_DOUBLE_EQ(hole_areas[0], 1.0);
  EXPECT_DOUBLE_EQ(hole_areas[1], 6.0);
}

TEST(BoundaryLoops, SeparatePiecesEachHaveTheirOuterLoop)
{
  // Two 2 x 2 blocks of squares and one square touching nothing.
  const TriangleMesh mesh = squareGrid(7, [](int i, int j) {
    return (i < 2 && j < 2) || (i >= 4 && i < 6 && j < 2) || (i == 6 && j == 6);
  });
  BoundaryLoops loops;
  ASSERT_TRUE(findBoundaryLoops(mesh, loops).ok());
  expectLoopInvariants(mesh, loops);
  EXPECT_EQ(loops.componentCount(), 3u);
  EXPECT_EQ(loops.loops.size(), 3u);
  EXPECT_EQ(loops.holeCount(), 0u);
}

TEST(BoundaryLoops, PinchVertexIsWalkedFanByFan)
{
  // Squares (0,0) and (1,1) removed from a 3 x 3 block: vertex (1,1) has two fans,
  // the hole of square (1,1) touches the notch of square (0,0) there.
  const TriangleMesh mesh = squareGrid(
      3, [](int i, int j) { return !((i == 0 && j == 0) || (i == 1 && j == 1)); });
  EXPECT_EQ(test::pinchVertexCount(mesh), 1u);
  BoundaryLoops loops;
  ASSERT_TRUE(findBoundaryLoops(mesh, loops).ok());
  expectLoopInvariants(mesh, loops);
  EXPECT_EQ(loops.componentCount(), 1u);
  std::size_t repeated = 0;
  for (const BoundaryLoop& loop : loops.loops)
    repeated += loop.has_repeated_vertex ? 1 : 0;
  // Walking fan by fan, the notch and the hole form one loop through (1,1) twice.
  EXPECT_EQ(loops.loops.size(), 1u);
  EXPECT_EQ(repeated, 1u);
}

TEST(BoundaryLoops, TwoTrianglesTouchingAtAVertexAreTwoPieces)
{
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}};
  mesh.z.assign(5, 0.0);
  mesh.triangles = {0, 1, 2, 2, 3, 4};
  ASSERT_TRUE(mesh.rebuildHalfedges());
  BoundaryLoops loops;
  ASSERT_TRUE(findBoundaryLoops(mesh, loops).ok());
  expectLoopInvariants(mesh, loops);
  EXPECT_EQ(loops.componentCount(), 2u);
  EXPECT_EQ(loops.loops.size(), 2u);
}

TEST(BoundaryLoops, EmptyMeshHasNoLoop)
{
  BoundaryLoops loops;
  ASSERT_TRUE(findBoundaryLoops(TriangleMesh{}, loops).ok());
  EXPECT_TRUE(loops.loops.empty());
  EXPECT_EQ(loops.componentCount(), 0u);
}

TEST(BoundaryLoops, MismatchedHalfedgesAreRejected)
{
  TriangleMesh mesh = squareGrid(2, [](int, int) { return true; });
  mesh.halfedges.pop_back();
  BoundaryLoops loops;
  const Status status = findBoundaryLoops(mesh, loops);
  EXPECT_EQ(status.code, StatusCode::INVALID_PARAMETER);
  EXPECT_NE(status.message.find("halfedges"), std::string::npos) << status.message;
}

TEST(BoundaryLoops, CheckerCatchesAPinchVertexAndADuplicateTriangle)
{
  TriangleMesh pinch = squareGrid(
      3, [](int i, int j) { return !((i == 0 && j == 0) || (i == 1 && j == 1)); });
  ::testing::TestPartResultArray failures;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD,
        &failures);
    EXPECT_FALSE(test::expectValidSurfaceMesh(pinch));
  }
  EXPECT_GE(failures.size(), 1);
  const TriangleMesh good = squareGrid(3, [](int, int) { return true; });
  EXPECT_TRUE(test::expectValidSurfaceMesh(good));
}

} // namespace
} // namespace pcl_vts
