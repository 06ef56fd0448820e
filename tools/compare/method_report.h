// What a method process tells compare_methods besides its mesh: the method's own time
// (file reading and writing excluded), the normal-estimation time where normals are
// needed, the parameters it used and notes. One "key value" line each, so a person
// can read the file in the work folder too. PCL-free.
#pragma once

#include <pcl_vts/core/status.h>

#include <string>
#include <vector>

namespace pcl_vts {
namespace compare {

struct MethodReport {
  double seconds = 0.0;         ///< the method itself, normals excluded
  double normal_seconds = -1.0; ///< normal estimation; < 0 = the method needs none
  std::string parameters;       ///< "radius 8 m, mu 5, ..." as printed in the report
  std::vector<std::string> notes;
};

Status writeMethodReport(const std::string& path, const MethodReport& report);
Status readMethodReport(const std::string& path, MethodReport& report);

} // namespace compare
} // namespace pcl_vts
