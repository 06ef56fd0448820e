// pcl::OutwardTriangleRemoval: convert, trim, write back.
#include <pcl_vts/outward_triangle_removal.h>

namespace pcl {

pcl_vts::Status OutwardTriangleRemoval::performProcessing(pcl_vts::TriangleMesh& mesh,
                                                          pcl::PolygonMesh& output)
{
  result_ = pcl_vts::TrimResult{};
  const pcl_vts::Status status = pcl_vts::trimOutwardTriangles(mesh, options_, result_);
  if (status.ok())
    vts_detail::arraysToPolygons(mesh, output.polygons);
  return status;
}

} // namespace pcl
