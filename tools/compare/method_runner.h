// Runs one method of a comparison in its own process (child_process.h): this
// executable again with --run-method for VTS, GP3 and Poisson, compare_bpa for
// Ball-Pivoting, and turns what comes back (exit, time limit, report, mesh) into a
// row. Also measures the memory floor of such a process.
#pragma once

#include "compare_mesh.h"
#include "compare_options.h"
#include "compare_report.h"
#include "methods.h"

#include <string>

namespace pcl_vts {
namespace compare {

/// Runs method on work/points.bin; mesh receives its output when the row has no
/// failure (an empty mesh is a failure: "no triangles").
MethodRow runOneMethod(const std::string& method, const CompareOptions& opt,
                       const std::string& work, const MethodParameters& parameters,
                       CompareMesh& mesh);

/// "an idle method process ... peaks at N MiB": the peak memory of a method process
/// that only reads the points, the floor under every peak MiB figure.
std::string idleBaseline(const CompareOptions& opt, const std::string& work);

} // namespace compare
} // namespace pcl_vts
