// The core without PCL: the corners and the centre of a square give 4 triangles
// (2n - h - 2 with n = 5 points, h = 4 on the hull). Exit 1 otherwise.
#include <pcl_vts/core/vts_pipeline.h>

#include <iostream>

int main()
{
  const double xyz[] = {0, 0, 1, 2, 0, 2, 2, 2, 3, 0, 2, 4, 1, 1, 5};
  pcl_vts::VtsResult result;
  const pcl_vts::Status status = pcl_vts::runVtsPipeline(xyz, 5, {}, result);
  std::cout << status.toString() << ", triangles " << result.mesh.triangleCount()
            << "\n";
  return status.ok() && result.mesh.triangleCount() == 4 ? 0 : 1;
}
