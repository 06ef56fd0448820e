// A mesh read from where it lies on disk (the tiled path's output, never held whole):
// the out-of-core DEM and contours read it in two passes.
#pragma once

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>

#include <functional>

namespace pcl_vts {

/// Its vertices in order, then its triangles as vertex ids (CCW, in the mesh's
/// order); each may be called more than once.
struct MeshStream {
  std::function<Status(const std::function<void(double x, double y, double z)>&)>
      vertices;
  std::function<Status(const std::function<void(VertexId a, VertexId b, VertexId c)>&)>
      triangles;
};

} // namespace pcl_vts
