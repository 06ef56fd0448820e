// Explicit instantiations of pcl::VTSGridTriangulation for PCL's xyz point types, so
// users of the header do not compile the template (PCL's precompile scheme).
#include <pcl_vts/impl/vts_grid_triangulation.hpp>
#include <pcl_vts/vts_grid_triangulation.h>

#include <pcl/impl/instantiate.hpp>
#include <pcl/point_types.h>

// With PCL_NO_PRECOMPILE, PCL_INSTANTIATE expands to nothing and the header
// includes the template bodies instead.
PCL_INSTANTIATE(
    VTSGridTriangulation,
    (pcl::PointXYZ)(pcl::PointXYZI)(pcl::PointXYZRGB)(pcl::PointXYZRGBA)(
        pcl::PointNormal)(pcl::PointXYZINormal)(pcl::PointXYZRGBNormal)(pcl::PointDEM))
