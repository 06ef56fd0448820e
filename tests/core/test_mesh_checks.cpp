// The mesh checkers accept a correct mesh and catch each kind of damage: a flipped
// (non-Delaunay) edge, a broken twin, a clockwise triangle, a non-manifold edge, an
// unused vertex. A checker that cannot fail proves nothing.
#include "support/asc_reader.h"
#include "support/generators.h"
#include "support/synthetic_terrain.h"

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/predicates.h>
#include <pcl_vts/core/reconstruct_surface.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

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

TEST(HalfedgesConsistent, FlagsMutualTwinsEndingAtAnotherVertex)
{
  // 0 -> 1 (halfedge 0) and 1 -> 2 (halfedge 3) as mutual twins: the twin of 0 -> 1
  // starts where it ends, but ends at 2, not 0 (only halfedge 3's own test sees it).
  TriangleMesh mesh = fanMesh();
  mesh.halfedges[0] = 3;
  mesh.halfedges[3] = 0;
  for (const unsigned threads : {1u, 2u}) {
    std::string why;
    EXPECT_FALSE(halfedgesConsistent(mesh, &why, threads));
    EXPECT_NE(why.find("other way"), std::string::npos) << why;
    EXPECT_FALSE(isValidSurfaceMesh(mesh, &why, threads));
    EXPECT_NE(why.find("other way"), std::string::npos) << why;
  }
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

/// isValidSurfaceMesh against the three checks one by one (isEdgeManifold sorts
/// every edge: the independent oracle of the fans' proof), verdict and message, on
/// 1, 2 and 3 threads.
void expectSameVerdict(const TriangleMesh& mesh, bool expected_verdict,
                       const std::string& label)
{
  std::string expected_why;
  const bool expected = isEdgeManifold(mesh, &expected_why) &&
                        halfedgesConsistent(mesh, &expected_why) &&
                        allTrianglesCcw(mesh, &expected_why);
  EXPECT_EQ(expected, expected_verdict) << label << ": " << expected_why;
  for (const unsigned threads : {1u, 2u, 3u}) {
    std::string why;
    EXPECT_EQ(isValidSurfaceMesh(mesh, &why, threads), expected)
        << label << ", threads " << threads;
    EXPECT_EQ(why, expected_why) << label << ", threads " << threads;
  }
}

/// A closed fan around vertex 0 at the origin: ring vertices 1..m at radius 10 and
/// angles 2 pi turns k / m, triangles (0, k, k + 1) with twins around the centre
/// (each corner turns 2 pi turns / m < pi); `ring[k]` renames ring vertices.
TriangleMesh windingFan(int m, int turns, const std::vector<VertexId>& ring = {})
{
  TriangleMesh mesh;
  mesh.xy.push_back({0, 0});
  const double pi = std::acos(-1.0);
  for (int k = 0; k < m; ++k) {
    const double angle = 2 * pi * turns * k / m;
    mesh.xy.push_back({10 * std::cos(angle), 10 * std::sin(angle)});
  }
  mesh.z.assign(mesh.xy.size(), 0.0);
  auto vertex = [&](int k) {
    return ring.empty() ? static_cast<VertexId>(1 + k % m) : ring[k % m];
  };
  for (int k = 0; k < m; ++k)
    mesh.triangles.insert(mesh.triangles.end(), {0, vertex(k), vertex(k + 1)});
  mesh.halfedges.assign(mesh.triangles.size(), INVALID_ID);
  for (int k = 0; k < m; ++k) { // (k + 1 -> 0) of triangle k, (0 -> k + 1) of k + 1
    const auto from = static_cast<HalfedgeId>(3 * k + 2);
    const auto to = static_cast<HalfedgeId>(3 * ((k + 1) % m));
    mesh.halfedges[from] = to;
    mesh.halfedges[to] = from;
  }
  return mesh;
}

TEST(IsValidSurfaceMesh, SameDirectedEdgeInTwoTrianglesWithoutTwinsIsRejected)
{
  // Both corners at 0 lie in one quadrant (no crossing): 0's byte is 4 + 4, two
  // halfedges without twin. Nothing else repeats: only the bound 7 rejects it.
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {10, 1}, {10, 3}, {10, 5}};
  mesh.z.assign(4, 0.0);
  mesh.triangles = {0, 1, 2, 0, 1, 3};
  mesh.halfedges.assign(6, INVALID_ID);
  expectSameVerdict(mesh, false, "0 -> 1 twice");
  mesh.triangles = {0, 1, 2, 0, 2, 3}; // the same fan, one edge shared
  ASSERT_TRUE(mesh.rebuildHalfedges());
  expectSameVerdict(mesh, true, "a fan of two");
}

TEST(IsValidSurfaceMesh, EdgeInThreeTrianglesIsRejected)
{
  // 0-1 in (0, 1, 2) and (1, 0, 3) as twins, and in (0, 1, 4) again.
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {4, 0}, {2, 2}, {2, -2}, {3, 5}};
  mesh.z.assign(5, 0.0);
  mesh.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  mesh.halfedges.assign(9, INVALID_ID);
  mesh.halfedges[0] = 3;
  mesh.halfedges[3] = 0;
  expectSameVerdict(mesh, false, "0-1 in three triangles");
}

TEST(IsValidSurfaceMesh, BowtieVertexIsAcceptedAsTheEdgeTestDoes)
{
  // Two triangles meet at vertex 0 only (two open fans there): no edge repeats, so
  // the edge test accepts it, and so must the fans' proof (0 is a suspect, listed).
  TriangleMesh mesh;
  mesh.xy = {{0, 0}, {2, 1}, {1, 2}, {-2, -1}, {-1, -2}};
  mesh.z.assign(5, 0.0);
  mesh.triangles = {0, 1, 2, 0, 3, 4};
  ASSERT_TRUE(mesh.rebuildHalfedges());
  expectSameVerdict(mesh, true, "bowtie");
  // A third triangle repeating 0 -> 1 on the other fan's side of it.
  mesh.xy.push_back({3, 3});
  mesh.z.push_back(0.0);
  mesh.triangles.insert(mesh.triangles.end(), {0, 1, 5});
  mesh.halfedges.assign(mesh.triangles.size(), INVALID_ID);
  expectSameVerdict(mesh, false, "bowtie with 0 -> 1 twice");
}

TEST(IsValidSurfaceMesh, FanOfTwoTurnsIsDecidedByItsNeighbours)
{
  // Seven triangles turning twice around 0 (angles 4 pi k / 7): every neighbour once,
  // no edge repeats, so the mesh is valid though it overlaps itself (0's byte is 8).
  expectSameVerdict(windingFan(7, 2), true, "two turns, 7 neighbours");
  // Six triangles turning twice through neighbours 1, 2, 3, 1, 2, 3: 0 -> 1 twice.
  const TriangleMesh twice = windingFan(6, 2, {1, 2, 3, 1, 2, 3});
  expectSameVerdict(twice, false, "two turns, 3 neighbours");
  // One turn: each neighbour's fan is open (one triangle side each), 0's closed.
  expectSameVerdict(windingFan(5, 1), true, "one turn");
}

TEST(IsValidSurfaceMesh, BoundaryCornerSweepingNearlyAFullTurnIsAccepted)
{
  // The fan around 0 without one triangle: an open fan turning 2 pi - 2 pi / 9 (its
  // quadrant crossings can reach 4, a suspect), and with one more triangle gone.
  for (int removed = 1; removed <= 2; ++removed) {
    TriangleMesh mesh = windingFan(9, 1);
    mesh.triangles.resize(mesh.triangles.size() - 3 * removed);
    ASSERT_TRUE(mesh.rebuildHalfedges());
    expectSameVerdict(mesh, true, "open fan");
  }
}

TEST(IsValidSurfaceMesh, NonFiniteCoordinatesGiveTheThreeChecksVerdict)
{
  // No angles to argue with: a corner at +-inf or NaN sends the edge test to the
  // counting sort of every edge; whatever orient2d says there, the verdict and message
  // are the three checks' (with and without a repeated triangle).
  const double inf = std::numeric_limits<double>::infinity();
  for (const Point2 moved : {Point2{inf, 0.5}, Point2{-inf, 0.5}, Point2{1, inf},
                             Point2{std::nan(""), 0.5}, Point2{inf, inf}})
    for (const bool repeat : {false, true}) {
      TriangleMesh mesh = fanMesh();
      mesh.xy[1] = moved;
      if (repeat) {
        mesh.triangles.insert(mesh.triangles.end(), {3, 0, 4});
        mesh.halfedges.resize(mesh.triangles.size(), INVALID_ID);
      }
      std::string expected_why;
      const bool expected = isEdgeManifold(mesh, &expected_why) &&
                            halfedgesConsistent(mesh, &expected_why) &&
                            allTrianglesCcw(mesh, &expected_why);
      expectSameVerdict(mesh, expected, "moved vertex 1");
    }
}

TEST(IsValidSurfaceMesh, FanByteOverflowFallsBackToTheEdgeTest)
{
  // 127 triangles turning 62 times around 0 (each corner 2 pi 62 / 127 < pi): 248
  // quadrant crossings; two triangles (0, 128, 129) and (0, 128, 130) add 8 for
  // their halfedges without twin: 0's sum reaches 256 or more and its byte wraps to
  // a small value. The bytes' sum then differs from the addends', and the edge test
  // decides: 0 -> 128 twice (rejected), or once (accepted).
  TriangleMesh mesh = windingFan(127, 62);
  mesh.xy.insert(mesh.xy.end(), {{20, 0.5}, {20, 2}, {20, 3}});
  mesh.z.resize(mesh.xy.size(), 0.0);
  mesh.triangles.insert(mesh.triangles.end(), {0, 128, 129, 0, 128, 130});
  mesh.halfedges.resize(mesh.triangles.size(), INVALID_ID);
  expectSameVerdict(mesh, false, "0 -> 128 twice, byte wrapped");
  mesh.triangles[mesh.triangles.size() - 2] = 129; // (0, 129, 130): 0's sum is 256
  expectSameVerdict(mesh, true, "byte wrapped, no edge repeated");
}

/// An exact lattice of w x h unit squares, each split by a diagonal chosen at random:
/// every edge axis-aligned or diagonal (the quadrants' borders).
TriangleMesh latticeMesh(int w, int h, std::mt19937& rng)
{
  TriangleMesh mesh;
  for (int j = 0; j <= h; ++j)
    for (int i = 0; i <= w; ++i)
      mesh.xy.push_back({static_cast<double>(i), static_cast<double>(j)});
  mesh.z.assign(mesh.xy.size(), 0.0);
  auto id = [&](int i, int j) { return static_cast<VertexId>(j * (w + 1) + i); };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const VertexId a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1),
                     d = id(i, j + 1);
      if (rng() % 2 == 0)
        mesh.triangles.insert(mesh.triangles.end(), {a, b, c, a, c, d});
      else
        mesh.triangles.insert(mesh.triangles.end(), {a, b, d, b, c, d});
    }
  EXPECT_TRUE(mesh.rebuildHalfedges());
  return mesh;
}

/// The triangles reached from `seed` across twins, breadth first, at most `limit`.
std::vector<TriangleId> patchAround(const TriangleMesh& mesh, TriangleId seed,
                                    std::size_t limit)
{
  std::vector<TriangleId> patch{seed};
  std::vector<bool> in(mesh.triangleCount(), false);
  in[seed] = true;
  for (std::size_t k = 0; k < patch.size() && patch.size() < limit; ++k)
    for (HalfedgeId e = 3 * patch[k]; e < 3 * patch[k] + 3; ++e) {
      const HalfedgeId twin = mesh.halfedges[e];
      if (twin != INVALID_ID && !in[triangleOf(twin)] && patch.size() < limit) {
        in[triangleOf(twin)] = true;
        patch.push_back(triangleOf(twin));
      }
    }
  return patch;
}

/// One random damage of a valid mesh that keeps the twins reciprocal and reversed
/// and the triangles counter-clockwise (so the edge test alone decides), or breaks
/// one of them; returns its name.
std::string corrupt(TriangleMesh& mesh, std::mt19937& rng)
{
  std::uniform_int_distribution<TriangleId> pick(
      0, static_cast<TriangleId>(mesh.triangleCount() - 1));
  const auto kind = static_cast<unsigned>(rng() % 9); // 7 and 8: the valid kinds again
  switch (kind < 7 ? kind : kind - 6) {
  case 0: { // a patch of 1-40 triangles copied, twins inside the copy: edges repeated
    const std::vector<TriangleId> patch = patchAround(mesh, pick(rng), 1 + rng() % 40);
    std::vector<TriangleId> copy_of(mesh.triangleCount(), INVALID_ID);
    const auto first = static_cast<TriangleId>(mesh.triangleCount());
    for (std::size_t k = 0; k < patch.size(); ++k)
      copy_of[patch[k]] = first + static_cast<TriangleId>(k);
    for (const TriangleId t : patch)
      for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e) {
        mesh.triangles.push_back(mesh.triangles[e]);
        const HalfedgeId twin = mesh.halfedges[e];
        mesh.halfedges.push_back(twin != INVALID_ID &&
                                         copy_of[triangleOf(twin)] != INVALID_ID
                                     ? 3 * copy_of[triangleOf(twin)] + twin % 3
                                     : INVALID_ID);
      }
    return "patch copied";
  }
  case 1: { // triangles removed (holes, pinched vertices, notches): still valid
    std::vector<bool> removed(mesh.triangleCount(), false);
    for (int k = 0, count = 1 + static_cast<int>(rng() % 60); k < count; ++k)
      for (const TriangleId t : patchAround(mesh, pick(rng), 1 + rng() % 6))
        removed[t] = true;
    std::vector<VertexId> kept;
    for (TriangleId t = 0; t < mesh.triangleCount(); ++t)
      if (!removed[t])
        kept.insert(kept.end(), mesh.triangles.begin() + 3 * t,
                    mesh.triangles.begin() + 3 * t + 3);
    mesh.triangles = kept;
    (void)mesh.rebuildHalfedges(); // false after a copied patch: repeats stay twinless
    return "triangles removed";
  }
  case 2: { // interior edges cut (both twins invalid): still valid
    for (int k = 0, count = 1 + static_cast<int>(rng() % 50); k < count; ++k) {
      const HalfedgeId e = 3 * pick(rng) + static_cast<HalfedgeId>(rng() % 3);
      if (mesh.halfedges[e] != INVALID_ID) {
        mesh.halfedges[mesh.halfedges[e]] = INVALID_ID;
        mesh.halfedges[e] = INVALID_ID;
      }
    }
    return "edges cut";
  }
  case 3: { // one triangle repeated with its twins left invalid
    const TriangleId t = pick(rng);
    for (HalfedgeId e = 3 * t; e < 3 * t + 3; ++e)
      mesh.triangles.push_back(mesh.triangles[e]);
    mesh.halfedges.resize(mesh.triangles.size(), INVALID_ID);
    return "triangle repeated";
  }
  case 4: { // one twin broken on one side
    const HalfedgeId e = 3 * pick(rng) + static_cast<HalfedgeId>(rng() % 3);
    mesh.halfedges[e] = mesh.halfedges[e] == INVALID_ID ? e : INVALID_ID;
    return "twin broken";
  }
  case 5: { // one triangle turned clockwise, twins rebuilt where they still pair
    const TriangleId t = pick(rng);
    std::swap(mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]);
    (void)mesh.rebuildHalfedges();
    return "triangle flipped";
  }
  default: { // a vertex renamed as another in one triangle: bad twins or orientation
    const HalfedgeId e = 3 * pick(rng) + static_cast<HalfedgeId>(rng() % 3);
    mesh.triangles[e] = mesh.triangles[3 * pick(rng)];
    return "vertex renamed";
  }
  }
}

TEST(IsValidSurfaceMesh, AgreesWithTheEdgeTestOnDamagedRealMeshes)
{
  // Meshes as the pipeline makes them (trim and fill: notches, voids, filled holes,
  // pinches), a real DEM (lattice: edges on the quadrants' borders) and an exact
  // lattice, each damaged 1-3 times at random; the verdict and message are the three
  // checks', on 1-3 threads (the terrain's 250 thousand triangles give each thread
  // its own part and its own bytes).
  std::mt19937 rng(5);
  std::vector<std::pair<std::string, TriangleMesh>> meshes;
  auto pipeline = [](const std::vector<double>& xyz) {
    VtsOptions options;
    options.reconstruction = ReconstructionOptions{};
    VtsResult result;
    EXPECT_TRUE(runVtsPipeline(xyz.data(), xyz.size() / 3, options, result).ok());
    return result.mesh;
  };
  meshes.emplace_back("terrain", pipeline(test::makeSyntheticTerrain(3).xyz));
  meshes.emplace_back("clustered", pipeline(test::generatePoints(
                                       test::Distribution::CLUSTERED, 20000, 4)));
  const std::string dem =
      std::string(PCL_VTS_SHARED_DATA_DIR) + "/dem/landlab/pre_runout_DEM.asc";
  test::AsciiGrid grid;
  if (std::ifstream(dem).good() && test::readAsciiGrid(dem, grid))
    meshes.emplace_back("pre_runout_DEM", pipeline(grid.xyz));
  meshes.emplace_back("lattice", latticeMesh(60, 40, rng));
  int valid = 0, invalid = 0;
  for (const auto& [name, original] : meshes) {
    ASSERT_GT(original.triangleCount(), 1000u) << name;
    expectSameVerdict(original, true, name);
    const int rounds = original.triangleCount() > 200000 ? 6 : 30;
    for (int round = 0; round < rounds; ++round) {
      TriangleMesh mesh = original;
      std::string label = name + " round " + std::to_string(round) + ":";
      for (int k = 0, count = 1 + static_cast<int>(rng() % 3); k < count; ++k)
        label += " " + corrupt(mesh, rng);
      std::string why;
      const bool verdict = isEdgeManifold(mesh, &why) &&
                           halfedgesConsistent(mesh, &why) &&
                           allTrianglesCcw(mesh, &why);
      expectSameVerdict(mesh, verdict, label);
      (verdict ? valid : invalid) += 1;
    }
  }
  EXPECT_GT(valid, 20);
  EXPECT_GT(invalid, 40);
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
