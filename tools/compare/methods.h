// The methods compared, each run inside its own process (compare_methods
// --run-method NAME): input points in, a mesh and a MethodReport out. Parameters are
// derived once by the parent from the measured point spacing, so every method sees
// the same scale.
#pragma once

#include "compare_mesh.h"
#include "method_report.h"

#include <pcl_vts/core/status.h>

#include <string>
#include <vector>

namespace pcl_vts {
namespace compare {

struct MethodParameters {
  double spacing = 1.0;    ///< median nearest-neighbour distance (3D) of the input
  int normal_k = 10;       ///< neighbours of NormalEstimation (GP3, Poisson, BPA)
  double gp3_radius = 0.0; ///< search radius; 0 = 8 x spacing
  double gp3_mu = 5.0;
  int gp3_max_neighbours = 100;
  int poisson_depth =
      0;               ///< 0 = from the extent: ceil(log2(1.1 extent / spacing)), 6..9
  double extent = 0.0; ///< largest side of the input's box (for the depth)
};

/// The methods in report order: vts-raw, vts, gp3, poisson, bpa.
const std::vector<std::string>& allMethodNames();
/// Human name for tables: "VTS (Delaunay only)", "pcl::Poisson", ...
std::string methodTitle(const std::string& name);

double gp3Radius(const MethodParameters& p);
int poissonDepth(const MethodParameters& p);
/// Ball radii of BPA: {1, 2, 4} x spacing.
std::vector<double> bpaRadii(const MethodParameters& p);

/// VTS through the core pipeline: "vts-raw" = exact Delaunay of the convex hull,
/// "vts" = with trimming and hole filling (pcd_to_mesh's defaults), 1 thread.
Status runVtsMethod(const std::string& name, const PointSet& points, CompareMesh& mesh,
                    MethodReport& report);

/// "gp3" or "poisson", after pcl::NormalEstimation (k neighbours, oriented to +z).
Status runPclMethod(const std::string& name, const PointSet& points,
                    const MethodParameters& parameters, CompareMesh& mesh,
                    MethodReport& report);

} // namespace compare
} // namespace pcl_vts
