// The canonical order of the tiled path, applied to an in-memory mesh (tiled_mesh.h).
#include <pcl_vts/tiling/tiled_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace pcl_vts {

TileFrame frameOfMesh(const TriangleMesh& mesh,
                      const std::vector<std::uint8_t>* inserted)
{
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    if (inserted != nullptr && (*inserted)[v] != 0)
      continue;
    x0 = std::min(x0, mesh.xy[v].x);
    y0 = std::min(y0, mesh.xy[v].y);
    x1 = std::max(x1, mesh.xy[v].x);
    y1 = std::max(y1, mesh.xy[v].y);
  }
  return TileFrame::fromBounds(x0, y0, x1, y1);
}

void canonicalMesh(TriangleMesh& mesh, std::vector<std::uint8_t>* inserted)
{
  const TileFrame frame = frameOfMesh(mesh, inserted);
  const std::size_t nv = mesh.vertexCount();
  std::vector<std::uint32_t> code(nv);
  for (std::size_t v = 0; v < nv; ++v)
    code[v] = frame.code(mesh.xy[v]);
  std::vector<VertexId> order(nv);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](VertexId a, VertexId b) {
    return canonicalLess(code[a], mesh.xy[a], code[b], mesh.xy[b]);
  });
  std::vector<VertexId> rank(nv);
  TriangleMesh out;
  out.xy.resize(nv);
  out.z.resize(nv);
  std::vector<std::uint8_t> flags;
  for (std::size_t k = 0; k < nv; ++k) {
    rank[order[k]] = static_cast<VertexId>(k);
    out.xy[k] = mesh.xy[order[k]];
    out.z[k] = mesh.z[order[k]];
    if (inserted != nullptr)
      flags.push_back((*inserted)[order[k]]);
  }
  std::vector<std::array<VertexId, 3>> tris(mesh.triangleCount());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    std::array<VertexId, 3> g = {rank[mesh.triangles[3 * t]],
                                 rank[mesh.triangles[3 * t + 1]],
                                 rank[mesh.triangles[3 * t + 2]]};
    const int k = g[0] < g[1] ? (g[0] < g[2] ? 0 : 2) : (g[1] < g[2] ? 1 : 2);
    std::rotate(g.begin(), g.begin() + k, g.end());
    tris[t] = g;
  }
  std::sort(tris.begin(), tris.end());
  for (const auto& g : tris)
    out.triangles.insert(out.triangles.end(), g.begin(), g.end());
  out.rebuildHalfedges();
  mesh = std::move(out);
  if (inserted != nullptr)
    inserted->swap(flags);
}

} // namespace pcl_vts
