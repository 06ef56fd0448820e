// Small synthetic TINs for the GIS tests: a grid of vertices split into CCW
// triangles, with a chosen z(x, y) and optional cells left out (L shapes, holes).
#pragma once

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/gis/mesh_stream.h>

#include <functional>

namespace pcl_vts::test {

/// (nx+1) x (ny+1) vertices at x0 + i*dx, y0 + j*dy; cell (i, j) is split along the
/// diagonal that alternates by parity unless keep(i, j) is false (cell left out).
inline TriangleMesh gridMesh(int nx, int ny, double x0, double y0, double dx, double dy,
                             const std::function<double(double, double)>& z,
                             const std::function<bool(int, int)>& keep = nullptr)
{
  TriangleMesh m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double x = x0 + i * dx, y = y0 + j * dy;
      m.xy.push_back({x, y});
      m.z.push_back(z(x, y));
    }
  auto id = [&](int i, int j) { return static_cast<VertexId>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (keep && !keep(i, j))
        continue;
      const VertexId a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1),
                     d = id(i, j + 1);
      if ((i + j) % 2 == 0)
        m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
      else
        m.triangles.insert(m.triangles.end(), {a, b, d, b, c, d});
    }
  m.rebuildHalfedges();
  return m;
}

/// The mesh as the tiled path hands it over: streamed, vertices then triangles (the
/// mesh must outlive the stream).
inline MeshStream streamOf(const TriangleMesh& mesh)
{
  MeshStream stream;
  stream.vertices = [&mesh](const std::function<void(double, double, double)>& visit) {
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
      visit(mesh.xy[v].x, mesh.xy[v].y, mesh.z[v]);
    return Status::success();
  };
  stream.triangles =
      [&mesh](const std::function<void(VertexId, VertexId, VertexId)>& visit) {
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
          visit(mesh.triangles[3 * t], mesh.triangles[3 * t + 1],
                mesh.triangles[3 * t + 2]);
        return Status::success();
      };
  return stream;
}

} // namespace pcl_vts::test
