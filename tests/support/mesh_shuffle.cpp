// See mesh_shuffle.h.
#include "support/mesh_shuffle.h"

#include <algorithm>
#include <numeric>
#include <random>

namespace pcl_vts {
namespace test {

TriangleMesh shuffledIds(const TriangleMesh& mesh, std::uint32_t seed)
{
  std::mt19937 random(seed);
  std::vector<VertexId> id(mesh.vertexCount());
  std::iota(id.begin(), id.end(), 0);
  std::shuffle(id.begin(), id.end(), random);
  TriangleMesh shuffled;
  shuffled.xy.resize(mesh.vertexCount());
  shuffled.z.resize(mesh.vertexCount());
  for (VertexId v = 0; v < mesh.vertexCount(); ++v) {
    shuffled.xy[id[v]] = mesh.xy[v];
    shuffled.z[id[v]] = mesh.z[v];
  }
  std::vector<TriangleId> order(mesh.triangleCount());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), random);
  for (const TriangleId t : order) {
    const auto r = static_cast<int>(random() % 3);
    for (int k = 0; k < 3; ++k)
      shuffled.triangles.push_back(id[mesh.triangles[3 * t + (k + r) % 3]]);
  }
  shuffled.rebuildHalfedges();
  return shuffled;
}

std::vector<std::array<double, 3>> verticesByPosition(const TriangleMesh& mesh)
{
  std::vector<std::array<double, 3>> vertices;
  for (VertexId v = 0; v < mesh.vertexCount(); ++v)
    vertices.push_back({mesh.xy[v].x, mesh.xy[v].y, mesh.z[v]});
  std::sort(vertices.begin(), vertices.end());
  return vertices;
}

} // namespace test
} // namespace pcl_vts
