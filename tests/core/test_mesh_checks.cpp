// The mesh checkers accept a correct mesh and catch each kind of damage: a flipped
// (non-Delaunay) edge, a broken twin, a clockwise triangle, a non-manifold edge, an
// unused vertex. A checker that cannot fail proves nothing.
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/predicates.h>

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <string>
#include <utility>

namespace pcl_vts {
namespace {

//   3 ------- 2        A 2 x 1 rectangle split into 4 triangles around the
//   | \     / |        centre 4 = (1, 0.5): Delaunay (the centre is inside every
//   |   \ /   |        circumcircle only as a vertex), every edge from 4 interior.
//   |    4    |
//   |   / \   |
//   | /     \ |
//   0 ------- 1
TriangleMesh fanMesh()
{
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {2, 0}, {2, 1}, {0, 1}, {1, 0.5}};
  mesh.z = {0, 0, 0, 0, 1};
  mesh.triangles = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
  EXPECT_TRUE(mesh.rebuildHalfedges());
  return mesh;
}

//  3 ------ 2          A trapezoid (0,0) (4,0) (3,1) (0,1): 2 lies inside the
//  |        \          circle through 0, 1, 3 (centre (2, 0.5), r^2 = 4.25;
//  |          \        |2 - centre|^2 = 1.25), so diagonal 0-2 is the Delaunay one
//  0 ---------- 1      and diagonal 1-3 is a flipped edge.
TriangleMesh quadMesh(bool delaunay_diagonal)
{
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {4, 0}, {3, 1}, {0, 1}};
  mesh.z = {0, 0, 0, 0};
  if (delaunay_diagonal)
    mesh.triangles = {0, 1, 2, 0, 2, 3}; // diagonal 0-2
  else
    mesh.triangles = {0, 1, 3, 1, 2, 3}; // diagonal 1-3
  EXPECT_TRUE(mesh.rebuildHalfedges());
  return mesh;
}

TEST(MeshChecks, AcceptCorrectMesh)
{
  const TriangleMesh mesh = fanMesh();
  std::string why;
  EXPECT_TRUE(allTrianglesCcw(mesh, &why)) << why;
  EXPECT_TRUE(halfedgesConsistent(mesh, &why)) << why;
  EXPECT_TRUE(isEdgeManifold(mesh, &why)) << why;
  EXPECT_TRUE(isDelaunay(mesh, &why)) << why;
  EXPECT_TRUE(allVerticesUsed(mesh, &why)) << why;
  EXPECT_EQ(eulerCharacteristic(mesh), 1); // a disc
  EXPECT_EQ(boundaryEdgeCount(mesh), 4u);
  EXPECT_DOUBLE_EQ(twiceArea(mesh), 4.0);
}

TEST(MeshChecks, EmptyMeshPassesTrivially)
{
  const TriangleMesh mesh;
  EXPECT_TRUE(allTrianglesCcw(mesh));
  EXPECT_TRUE(halfedgesConsistent(mesh));
  EXPECT_TRUE(isEdgeManifold(mesh));
  EXPECT_TRUE(isDelaunay(mesh));
  EXPECT_EQ(eulerCharacteristic(mesh), 0);
}

TEST(RebuildHalfedges, MatchesTwinsAndLeavesBoundaryInvalid)
{
  TriangleMesh mesh = fanMesh();
  // Halfedge 1 (1 -> 4) of triangle 0 pairs with halfedge 5 (4 -> 1) of triangle 1.
  EXPECT_EQ(mesh.halfedges[1], 5u);
  EXPECT_EQ(mesh.halfedges[5], 1u);
  EXPECT_EQ(mesh.halfedges[0], INVALID_ID);               // 0 -> 1 is on the boundary
  mesh.triangles.insert(mesh.triangles.end(), {0, 1, 4}); // a third use of 0-1, 1-4
  EXPECT_FALSE(mesh.rebuildHalfedges());
}

TEST(RebuildHalfedges, RejectsEdgeUsedTwiceInOneDirection)
{
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {1, 0}, {0, 1}, {1, -1}};
  mesh.z = {0, 0, 0, 0};
  mesh.triangles = {0, 1, 2, 0, 1, 3}; // second triangle is CW, edge 0 -> 1 twice
  EXPECT_FALSE(mesh.rebuildHalfedges());
}

TEST(IsDelaunay, AcceptsTheDelaunayDiagonal)
{
  std::string why;
  EXPECT_TRUE(isDelaunay(quadMesh(true), &why)) << why;
}

TEST(IsDelaunay, FlagsAFlippedEdge)
{
  const TriangleMesh mesh = quadMesh(false);
  std::string why;
  ASSERT_TRUE(allTrianglesCcw(mesh, &why)) << why; // only the diagonal is wrong
  ASSERT_TRUE(halfedgesConsistent(mesh, &why)) << why;
  EXPECT_FALSE(isDelaunay(mesh, &why));
  EXPECT_NE(why.find("edge"), std::string::npos) << why;
  EXPECT_NE(why.find("not Delaunay"), std::string::npos) << why;
}

TEST(IsDelaunay, CocircularDiagonalsAreBothAccepted)
{
  // The unit square: both diagonals are Delaunay (d on the circle, not inside).
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.z = {0, 0, 0, 0};
  mesh.triangles = {0, 1, 2, 0, 2, 3};
  ASSERT_TRUE(mesh.rebuildHalfedges());
  EXPECT_TRUE(isDelaunay(mesh));
  mesh.triangles = {0, 1, 3, 1, 2, 3};
  ASSERT_TRUE(mesh.rebuildHalfedges());
  EXPECT_TRUE(isDelaunay(mesh));
}

TEST(IsDelaunay, DecidesExactlyAFewUlpsInside)
{
  // d one ulp inside the circle through a, b, c: not Delaunay; on it: Delaunay.
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.z = {0, 0, 0, 0};
  mesh.triangles = {0, 1, 2, 0, 2, 3};
  ASSERT_TRUE(mesh.rebuildHalfedges());
  mesh.xy[3] = {0x1p-60, 1.0}; // pulled right by 2^-60: strictly inside
  EXPECT_FALSE(isDelaunay(mesh));
  mesh.xy[3] = {-0x1p-60, 1.0}; // pushed out
  EXPECT_TRUE(isDelaunay(mesh));
}

TEST(HalfedgesConsistent, FlagsABrokenTwin)
{
  TriangleMesh mesh = fanMesh();
  std::string why;
  mesh.halfedges[1] = 8; // 1 -> 4 claims 2 -> 3 as its twin
  EXPECT_FALSE(halfedgesConsistent(mesh, &why));
  EXPECT_NE(why.find("halfedge 1"), std::string::npos) << why;

  mesh = fanMesh();
  std::swap(mesh.halfedges[1], mesh.halfedges[2]); // asymmetric twins
  EXPECT_FALSE(halfedgesConsistent(mesh, &why));

  mesh = fanMesh();
  mesh.halfedges[4] = 1000; // out of range
  EXPECT_FALSE(halfedgesConsistent(mesh, &why));
  EXPECT_NE(why.find("out of range"), std::string::npos) << why;

  mesh = fanMesh();
  mesh.halfedges.pop_back(); // wrong size
  EXPECT_FALSE(halfedgesConsistent(mesh, &why));
  EXPECT_FALSE(isDelaunay(mesh, &why)); // and isDelaunay does not read past it

  mesh = fanMesh();
  mesh.halfedges[1] = 1; // own twin
  EXPECT_FALSE(halfedgesConsistent(mesh, &why));
}

TEST(HalfedgesConsistent, FlagsTwinRunningTheSameWay)
{
  // Two triangles glued along 0 -> 1 in the same direction (one of them CW): the
  // twin pointers are symmetric but the vertices do not match up.
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {1, 0}, {0, 1}, {1, -1}};
  mesh.z = {0, 0, 0, 0};
  mesh.triangles = {0, 1, 2, 0, 1, 3};
  mesh.halfedges = {3, INVALID_ID, INVALID_ID, 0, INVALID_ID, INVALID_ID};
  std::string why;
  EXPECT_FALSE(halfedgesConsistent(mesh, &why));
  EXPECT_NE(why.find("other way"), std::string::npos) << why;
}

TEST(AllTrianglesCcw, FlagsAClockwiseTriangle)
{
  TriangleMesh mesh = fanMesh();
  std::swap(mesh.triangles[6], mesh.triangles[7]); // triangle 2 becomes 3, 2, 4
  std::string why;
  EXPECT_FALSE(allTrianglesCcw(mesh, &why));
  EXPECT_NE(why.find("triangle 2"), std::string::npos) << why;
  EXPECT_NE(why.find("clockwise"), std::string::npos) << why;
}

TEST(AllTrianglesCcw, FlagsADegenerateTriangleAndBadIds)
{
  TriangleMesh mesh = fanMesh();
  mesh.xy[4] = {1, 0}; // centre moved onto edge 0-1: triangle 0 is flat
  std::string why;
  EXPECT_FALSE(allTrianglesCcw(mesh, &why));
  EXPECT_NE(why.find("triangle 0"), std::string::npos) << why;
  EXPECT_NE(why.find("degenerate"), std::string::npos) << why;

  mesh = fanMesh();
  mesh.triangles[5] = 17; // no such vertex
  EXPECT_FALSE(allTrianglesCcw(mesh, &why));
  EXPECT_NE(why.find("vertex 17"), std::string::npos) << why;
  EXPECT_FALSE(allVerticesUsed(mesh, &why));
  EXPECT_FALSE(isEdgeManifold(mesh, &why));
}

TEST(IsEdgeManifold, FlagsAnEdgeUsedByThreeTriangles)
{
  TriangleMesh mesh = fanMesh();
  mesh.xy.push_back({1, -1});
  mesh.z.push_back(0);
  mesh.triangles.insert(mesh.triangles.end(), {1, 0, 5}); // 0-1 now has 3 triangles
  mesh.triangles.insert(mesh.triangles.end(), {0, 1, 5}); // ... counting this CW one
  std::string why;
  EXPECT_FALSE(isEdgeManifold(mesh, &why));
  EXPECT_NE(why.find("edge 0-1"), std::string::npos) << why;
  EXPECT_NE(why.find("3 triangles"), std::string::npos) << why;
}

TEST(IsEdgeManifold, FlagsAnEdgeUsedTwiceInOneDirection)
{
  TriangleMesh mesh = fanMesh();
  mesh.xy.push_back({1, -1});
  mesh.z.push_back(0);
  mesh.triangles.insert(mesh.triangles.end(), {0, 1, 5}); // 0 -> 1 again (CW)
  std::string why;
  EXPECT_FALSE(isEdgeManifold(mesh, &why));
  EXPECT_NE(why.find("same direction"), std::string::npos) << why;
  EXPECT_TRUE(isEdgeManifold(fanMesh(), &why)) << why;
}

TEST(IsEdgeManifold, FlagsADegenerateEdge)
{
  TriangleMesh mesh = fanMesh();
  mesh.triangles[1] = 0; // triangle 0 becomes 0, 0, 4
  std::string why;
  EXPECT_FALSE(isEdgeManifold(mesh, &why));
  EXPECT_NE(why.find("itself"), std::string::npos) << why;
}

/// Appends count random triangles over the mesh's vertices (three distinct ids each,
/// any edge may repeat); turned CCW in XY when ccw (vertices in general position).
void addRandomTriangles(TriangleMesh& mesh, int count, bool ccw, std::mt19937& rng)
{
  std::uniform_int_distribution<VertexId> pick(
      0, static_cast<VertexId>(mesh.vertexCount() - 1));
  for (int t = 0; t < count; ++t) {
    VertexId a = pick(rng), b = pick(rng), c = pick(rng);
    while (b == a)
      b = pick(rng);
    while (c == a || c == b)
      c = pick(rng);
    if (ccw && orient2d(mesh.xy[a], mesh.xy[b], mesh.xy[c]) == Sign::NEGATIVE)
      std::swap(b, c);
    mesh.triangles.insert(mesh.triangles.end(), {a, b, c});
  }
}

TEST(IsEdgeManifold, AgreesWithCountingEveryEdgeOnRandomTriangleSoups)
{
  // Random triangles over few vertices: runs of 1 to 4 uses of an edge, in either
  // direction, in buckets of every length; the verdict is the edge count's.
  std::mt19937 rng(7);
  int accepted = 0, rejected = 0;
  for (int round = 0; round < 400; ++round) {
    TriangleMesh mesh;
    const auto vertices = static_cast<VertexId>(4 + round % 9);
    mesh.xy.assign(vertices, Point2{0, 0});
    mesh.z.assign(vertices, 0.0);
    addRandomTriangles(mesh, 1 + round % 7, false, rng);
    std::map<std::pair<VertexId, VertexId>, int> directed, undirected;
    bool manifold = true;
    for (HalfedgeId e = 0; e < mesh.triangles.size(); ++e) {
      const VertexId from = mesh.triangles[e], to = mesh.triangles[nextHalfedge(e)];
      manifold = ++directed[{from, to}] <= 1 && manifold;
      manifold =
          ++undirected[{std::min(from, to), std::max(from, to)}] <= 2 && manifold;
    }
    std::string why;
    EXPECT_EQ(isEdgeManifold(mesh, &why), manifold) << "round " << round;
    EXPECT_EQ(why.empty(), manifold) << why;
    (manifold ? accepted : rejected) += 1;
  }
  EXPECT_GT(accepted, 50);
  EXPECT_GT(rejected, 50);
}

TEST(IsValidSurfaceMesh, AgreesWithTheThreeChecksAndTheirFirstMessage)
{
  // Random triangles over a few vertices in general position, turned CCW, twins
  // rebuilt (consistent, even where the edges are not manifold), then sometimes
  // damaged: the verdict and message are those of isEdgeManifold, then
  // halfedgesConsistent, then allTrianglesCcw.
  std::mt19937 rng(11);
  int valid = 0, invalid = 0;
  for (int round = 0; round < 600; ++round) {
    TriangleMesh mesh;
    const auto vertices = static_cast<VertexId>(5 + round % 7);
    std::uniform_real_distribution<double> coordinate(0.0, 100.0);
    for (VertexId v = 0; v < vertices; ++v) {
      mesh.xy.push_back({coordinate(rng), coordinate(rng)});
      mesh.z.push_back(0.0);
    }
    addRandomTriangles(mesh, 1 + round % 6, true, rng);
    (void)mesh.rebuildHalfedges();
    switch (round % 5) {
    case 1: // one twin link broken on one side
      for (HalfedgeId& twin : mesh.halfedges)
        if (twin != INVALID_ID) {
          twin = INVALID_ID;
          break;
        }
      break;
    case 2: // a clockwise triangle
      std::swap(mesh.triangles[1], mesh.triangles[2]);
      (void)mesh.rebuildHalfedges();
      break;
    case 3: // a self-loop
      mesh.triangles[1] = mesh.triangles[0];
      break;
    default:
      break;
    }
    std::string expected_why, why;
    const bool expected = isEdgeManifold(mesh, &expected_why) &&
                          halfedgesConsistent(mesh, &expected_why) &&
                          allTrianglesCcw(mesh, &expected_why);
    ASSERT_EQ(isValidSurfaceMesh(mesh, &why), expected) << "round " << round;
    EXPECT_EQ(why, expected_why) << "round " << round;
    (expected ? valid : invalid) += 1;
  }
  EXPECT_GT(valid, 50);
  EXPECT_GT(invalid, 200);
  EXPECT_TRUE(isValidSurfaceMesh(fanMesh()));
}

TEST(AllVerticesUsed, FlagsAnUnusedVertex)
{
  TriangleMesh mesh = fanMesh();
  mesh.xy.push_back({5, 5});
  mesh.z.push_back(0);
  std::string why;
  EXPECT_FALSE(allVerticesUsed(mesh, &why));
  EXPECT_NE(why.find("vertex 5"), std::string::npos) << why;
  EXPECT_EQ(eulerCharacteristic(mesh), 1); // isolated vertices are not counted
}

TEST(EulerCharacteristic, DiscSphereLikeAndTwoComponents)
{
  EXPECT_EQ(eulerCharacteristic(quadMesh(true)), 1);
  // Two disjoint triangles: two discs.
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {1, 0}, {0, 1}, {5, 0}, {6, 0}, {5, 1}};
  mesh.z.assign(6, 0.0);
  mesh.triangles = {0, 1, 2, 3, 4, 5};
  EXPECT_EQ(eulerCharacteristic(mesh), 2);
  // An annulus (a square with a square hole, 8 triangles): 0.
  mesh.xy = {{0, 0}, {3, 0}, {3, 3}, {0, 3}, {1, 1}, {2, 1}, {2, 2}, {1, 2}};
  mesh.z.assign(8, 0.0);
  mesh.triangles = {0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5,
                    2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
  ASSERT_TRUE(mesh.rebuildHalfedges());
  EXPECT_TRUE(allTrianglesCcw(mesh));
  EXPECT_EQ(eulerCharacteristic(mesh), 0);
  EXPECT_EQ(boundaryEdgeCount(mesh), 8u);
  EXPECT_DOUBLE_EQ(twiceArea(mesh), 2.0 * (9.0 - 1.0));
}

} // namespace
} // namespace pcl_vts
