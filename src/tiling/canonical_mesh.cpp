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

Status canonicalMesh(TriangleMesh& mesh, std::vector<std::uint8_t>* inserted)
{
  const TileFrame frame = frameOfMesh(mesh, inserted);
  const std::size_t nv = mesh.vertexCount();
  std::vector<std::uint32_t> code(nv);
  for (std::size_t v = 0; v < nv; ++v)
    code[v] = frame.code(mesh.xy[v]);
  // By code in two counting passes of 16 bits (linear), then each run of equal codes
  // (a few points) by x, then y.
  std::vector<VertexId> order(nv), scratch(nv);
  std::iota(scratch.begin(), scratch.end(), 0);
  for (const int shift : {0, 16}) {
    std::vector<std::size_t> start((1u << 16) + 1, 0);
    for (const VertexId v : scratch)
      ++start[((code[v] >> shift) & 0xffff) + 1];
    for (std::size_t d = 1; d < start.size(); ++d)
      start[d] += start[d - 1];
    for (const VertexId v : scratch)
      order[start[(code[v] >> shift) & 0xffff]++] = v;
    scratch.swap(order);
  }
  order.swap(scratch);
  for (std::size_t i = 0; i < nv;) {
    std::size_t j = i + 1;
    while (j < nv && code[order[j]] == code[order[i]])
      ++j;
    std::sort(order.begin() + static_cast<std::ptrdiff_t>(i),
              order.begin() + static_cast<std::ptrdiff_t>(j),
              [&](VertexId a, VertexId b) { return lexLess(mesh.xy[a], mesh.xy[b]); });
    i = j;
  }
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
  // By first (smallest) vertex in one counting pass, then each vertex's few triangles.
  std::vector<std::size_t> start(nv + 1, 0);
  for (const auto& g : tris)
    ++start[g[0] + std::size_t{1}];
  for (std::size_t v = 1; v <= nv; ++v)
    start[v] += start[v - 1];
  std::vector<std::array<VertexId, 3>> sorted(tris.size());
  for (const auto& g : tris)
    sorted[start[g[0]]++] = g;
  tris.clear();
  tris.shrink_to_fit();
  for (std::size_t v = nv; v > 0; --v) // start[v - 1] is now where row v begins
    start[v] = start[v - 1];
  start[0] = 0;
  for (std::size_t v = 0; v < nv; ++v)
    std::sort(sorted.begin() + static_cast<std::ptrdiff_t>(start[v]),
              sorted.begin() + static_cast<std::ptrdiff_t>(start[v + 1]));
  out.triangles.reserve(3 * sorted.size());
  for (const auto& g : sorted)
    out.triangles.insert(out.triangles.end(), g.begin(), g.end());
  // The vertices are renumbered one to one, so this fails only when the input is
  // not an oriented 2-manifold.
  if (!out.rebuildHalfedges())
    return Status::error(StatusCode::INTERNAL_ERROR,
                         "canonical order: the mesh is not an oriented 2-manifold (an "
                         "edge in more than two triangles or twice in one direction)");
  mesh = std::move(out);
  if (inserted != nullptr)
    inserted->swap(flags);
  return Status::success();
}

} // namespace pcl_vts
