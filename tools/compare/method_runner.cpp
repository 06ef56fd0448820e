// One method process per row (method_runner.h).
#include "child_process.h"
#include "compare_files.h"
#include "method_runner.h"

#include <cstdio>
#include <cstring>
#include <sstream>
#include <unistd.h>
#include <vector>

namespace pcl_vts {
namespace compare {
namespace {

[[maybe_unused]] std::string dirOf(const std::string& path)
{
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

std::string number(double value)
{
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

} // namespace

MethodRow runOneMethod(const std::string& method, const CompareOptions& opt,
                       const std::string& work, const MethodParameters& parameters,
                       CompareMesh& mesh)
{
  MethodRow row;
  row.name = method;
  const std::string mesh_file = work + "/" + method + ".ply";
  const std::string report_file = work + "/" + method + ".txt";
  const std::string log_file = work + "/" + method + ".log";
  const std::string self = selfExecutablePath();
  std::vector<std::string> argv;
  if (method == "bpa") {
#ifdef PCL_VTS_HAVE_OPEN3D
    const std::string bpa = dirOf(self) + "/compare_bpa";
    std::string radii;
    for (double r : bpaRadii(parameters))
      radii += (radii.empty() ? "" : ",") + number(r);
    argv = {bpa,
            work + "/points.bin",
            mesh_file,
            report_file,
            std::to_string(parameters.normal_k),
            radii};
    if (::access(bpa.c_str(), X_OK) != 0) {
      row.failure = "compare_bpa is missing next to compare_methods (" + bpa + ")";
      return row;
    }
#else
    row.failure = "not built: Open3D (Debian libopen3d-dev) was not found when "
                  "compare_methods was configured";
    return row;
#endif
  } else {
    argv = {self,
            "--run-method",
            method,
            "--points",
            work + "/points.bin",
            "--out",
            mesh_file,
            "--method-report",
            report_file,
            "--spacing",
            number(parameters.spacing),
            "--extent",
            number(parameters.extent),
            "--normal-k",
            std::to_string(parameters.normal_k),
            "--gp3-mu",
            number(parameters.gp3_mu),
            "--poisson-depth",
            std::to_string(parameters.poisson_depth)};
  }
  row.outcome = runChild(argv, opt.time_limit, log_file);
  if (!row.outcome.finished) {
    row.failure = row.outcome.failure;
    // The method's own last line says more than an exit status.
    if (FILE* log = std::fopen(log_file.c_str(), "r")) {
      char line[512], last[512] = "";
      while (std::fgets(line, sizeof(line), log))
        if (std::strstr(line, "error"))
          std::snprintf(last, sizeof(last), "%s", line);
      std::fclose(log);
      std::string text = last;
      while (!text.empty() && (text.back() == '\n' || text.back() == '\r'))
        text.pop_back();
      if (!text.empty() && !row.outcome.timed_out)
        row.failure += ": " + text;
    }
    return row;
  }
  if (Status s = readMethodReport(report_file, row.report); !s.ok()) {
    row.failure = s.message;
    return row;
  }
  if (Status s = readMeshPly(mesh_file, mesh); !s.ok()) {
    row.failure = s.message;
    return row;
  }
  if (!opt.keep_work)
    std::remove(mesh_file.c_str());
  if (mesh.triangleCount() == 0)
    row.failure = "no triangles";
  return row;
}

std::string idleBaseline(const CompareOptions& opt, const std::string& work)
{
  const std::string self = selfExecutablePath();
  const std::string points = work + "/points.bin";
  auto peak = [&](const std::vector<std::string>& argv) {
    const ChildOutcome idle = runChild(argv, opt.time_limit, work + "/idle.log");
    char text[32];
    std::snprintf(text, sizeof(text), "%.0f MiB",
                  static_cast<double>(idle.peak_rss_kib) / 1024.0);
    return idle.finished ? std::string(text) : "? (" + idle.failure + ")";
  };
  std::string text =
      "an idle method process (libraries loaded, points read) peaks at " +
      peak({self, "--run-method", "idle", "--points", points, "--out", "-",
            "--method-report", "-"});
#ifdef PCL_VTS_HAVE_OPEN3D
  text += " (compare_methods), " +
          peak({dirOf(self) + "/compare_bpa", "--idle", points}) + " (compare_bpa)";
#endif
  std::remove((work + "/idle.log").c_str());
  return text;
}

} // namespace compare
} // namespace pcl_vts
