// Method names and parameters derived from the point spacing (methods.h).
#include "methods.h"

#include <algorithm>
#include <cmath>

namespace pcl_vts {
namespace compare {

const std::vector<std::string>& allMethodNames()
{
  static const std::vector<std::string> names = {"vts-raw", "vts", "gp3", "poisson",
                                                 "bpa"};
  return names;
}

std::string methodTitle(const std::string& name)
{
  if (name == "vts-raw")
    return "VTS, Delaunay only";
  if (name == "vts")
    return "VTS + trim + fill";
  if (name == "gp3")
    return "PCL GreedyProjection";
  if (name == "poisson")
    return "PCL Poisson (trimmed)";
  if (name == "bpa")
    return "Open3D Ball-Pivoting";
  return name;
}

double gp3Radius(const MethodParameters& p)
{
  return p.gp3_radius > 0.0 ? p.gp3_radius : 8.0 * p.spacing;
}

int poissonDepth(const MethodParameters& p)
{
  if (p.poisson_depth > 0)
    return p.poisson_depth;
  // Octree cells about one spacing wide over the 1.1x bounding cube, but at most
  // depth 9: depth 10 took 153 s on 1e6 points here (2 cores), too long for the
  // 20-minute `make compare`; --poisson-depth sets it.
  const double cells = 1.1 * p.extent / std::max(p.spacing, 1e-12);
  const int depth = static_cast<int>(std::ceil(std::log2(std::max(cells, 2.0))));
  return std::clamp(depth, 6, 9);
}

std::vector<double> bpaRadii(const MethodParameters& p)
{
  return {p.spacing, 2.0 * p.spacing, 4.0 * p.spacing};
}

} // namespace compare
} // namespace pcl_vts
