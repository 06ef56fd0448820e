// pcl::HoleFilling: convert, fill, append inserted points, write back.
#include <pcl_vts/hole_filling.h>

namespace pcl {

pcl_vts::Status HoleFilling::performProcessing(pcl_vts::TriangleMesh& mesh,
                                               pcl::PolygonMesh& output)
{
  result_ = pcl_vts::FillResult{};
  pcl_vts::FillOptions options = options_;
  options.snap_to_float = vts_detail::xyIsFloat(output.cloud);
  const std::size_t input_points = mesh.vertexCount();
  const pcl_vts::Status status = pcl_vts::fillHoles(mesh, options, result_);
  if (!status.ok())
    return status;
  vts_detail::appendVertices(mesh, input_points, output.cloud);
  vts_detail::arraysToPolygons(mesh, output.polygons);
  return status;
}

} // namespace pcl
