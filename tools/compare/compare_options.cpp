// compare_methods' command line (compare_options.h).
#include "cli_words.h"
#include "command_line.h"
#include "compare_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace pcl_vts {
namespace compare {
namespace {

using pcl_vts::tools::CommandLine;

std::string shown(double value)
{
  std::ostringstream out;
  out << value;
  return out.str();
}

bool parseNumber(const std::string& name, const std::string& text, double lo, double hi,
                 double& value, std::string& error)
{
  if (!pcl_vts::tools::parseFiniteNumber(text, value) || value < lo || value > hi) {
    std::ostringstream out;
    out << name << ": '" << text << "' is not a number in [" << lo << ", " << hi << "]";
    error = out.str();
    return false;
  }
  return true;
}

bool parseWhole(const std::string& name, const std::string& text, double lo, double hi,
                double& value, std::string& error)
{
  if (!parseNumber(name, text, lo, hi, value, error))
    return false;
  if (value != std::floor(value)) {
    error = name + ": '" + text + "' is not a whole number";
    return false;
  }
  return true;
}

/// A number in [lo, hi] (whole when whole) into target, converted to T.
template <typename T>
CommandLine::Apply number(const char* name, double lo, double hi, bool whole, T& target)
{
  return [name, lo, hi, whole, &target](const std::string& text, std::string& error) {
    double value = 0.0;
    if (!(whole ? parseWhole : parseNumber)(name, text, lo, hi, value, error))
      return false;
    target = static_cast<T>(value);
    return true;
  };
}

/// The options of compare_methods with their --help text and settings in opt.
CommandLine describeOptions(CompareOptions& opt)
{
  CommandLine cli;
  cli.group("Input")
      .value("synthetic", "N",
             "synthetic terrain of N points (known surface) instead of INPUT, 100 <= "
             "N <= 1e8",
             number("--synthetic", 100, 1e8, true, opt.synthetic))
      .value("classes", "LIST", "LAS only: classification codes to keep, e.g. 2",
             [&opt](const std::string& value, std::string& error) {
               if (pcl_vts::tools::parseClassList(value, opt.load.classes, error))
                 return true;
               error = "--classes: " + error;
               return false;
             })
      .value("name", "NAME",
             "label of the data set: file names and TSV (default: the input's file "
             "name, or synthetic_N)",
             CommandLine::text(opt.name))
      .value("title", "TEXT", "heading of the Markdown section (default: NAME)",
             CommandLine::text(opt.title));
  cli.group("Methods")
      .value("methods", "LIST",
             "vts-raw,vts,gp3,poisson,bpa or a comma-separated subset (default: all)",
             [&opt](const std::string& value, std::string& error) {
               opt.methods.clear();
               std::stringstream in(value);
               std::string item;
               while (std::getline(in, item, ',')) {
                 const auto& all = allMethodNames();
                 if (std::find(all.begin(), all.end(), item) == all.end()) {
                   error = "--methods: '" + item +
                           "' is not one of vts-raw, vts, gp3, poisson, bpa";
                   return false;
                 }
                 opt.methods.push_back(item);
               }
               if (opt.methods.empty()) {
                 error = "--methods: empty list";
                 return false;
               }
               return true;
             })
      .value("time-limit", "S",
             "seconds per method before it is killed and reported as timed out, S > 0 "
             "(default: " +
                 shown(DEFAULT_TIME_LIMIT) + ")",
             number("--time-limit", 1e-3, 1e6, false, opt.time_limit))
      .value("poisson-depth", "D",
             "octree depth 1..16; 0 = from extent / spacing, clamped to 6..9 "
             "(default: 0)",
             number("--poisson-depth", 0, 16, true, opt.poisson_depth))
      .value("poisson-trim", "K",
             "keep Poisson triangles whose XY centroid is within K x spacing of an "
             "input point, K > 0 (default: " +
                 shown(DEFAULT_POISSON_TRIM) + ")",
             number("--poisson-trim", 1e-6, 1e6, false, opt.poisson_trim));
  cli.group("Metrics")
      .value(
          "samples-per-triangle", "S",
          "Metro samples per triangle on average, S > 0 (default: " +
              shown(DEFAULT_SAMPLES_PER_TRIANGLE) + ")",
          number("--samples-per-triangle", 1e-6, 1e4, false, opt.samples_per_triangle))
      .value("max-samples", "N", "cap on the samples per mesh; 0 = none (default: 0)",
             number("--max-samples", 0, 1e10, true, opt.max_samples))
      .value("threads", "N",
             "threads for the metrics (methods always run on one); 0 = all cores "
             "(default: 0)",
             number("--threads", 0, 4096, true, opt.threads));
  cli.group("Output")
      .value("report", "FILE.md", "write the Markdown section here (default: print it)",
             CommandLine::text(opt.report))
      .value("tsv", "FILE", "write one tab-separated row per method here",
             CommandLine::text(opt.tsv))
      .value("pictures", "DIR", "write DIR/NAME_top.png and DIR/NAME_oblique.png",
             CommandLine::text(opt.pictures))
      .value("picture-link", "PATH",
             "folder of the pictures as the Markdown links it (default: DIR)",
             CommandLine::text(opt.picture_link))
      .value("picture-width", "W",
             "pixels per method, 64..4000 (default: " +
                 std::to_string(DEFAULT_PICTURE_WIDTH) + ")",
             number("--picture-width", 64, 4000, true, opt.picture_width))
      .value("work-dir", "DIR",
             "folder for the exchanged files (default: a new folder under $TMPDIR or "
             "/tmp, removed at the end)",
             CommandLine::text(opt.work_dir))
      .flag("keep-work", "keep the exchanged files and logs",
            [&opt] { opt.keep_work = true; });
  cli.group("General").flag("help,h", "print this help and exit",
                            [&opt] { opt.help = true; });
  // A method process (--run-method), started by the parent only.
  cli.hiddenValue("run-method", CommandLine::text(opt.run_method))
      .hiddenValue("points", CommandLine::text(opt.points_file))
      .hiddenValue("out", CommandLine::text(opt.mesh_file))
      .hiddenValue("method-report", CommandLine::text(opt.report_file))
      .hiddenValue("spacing",
                   number("--spacing", 1e-300, 1e300, false, opt.parameters.spacing))
      .hiddenValue("extent", number("--extent", 0, 1e300, false, opt.parameters.extent))
      .hiddenValue("normal-k",
                   number("--normal-k", 3, 1000, true, opt.parameters.normal_k))
      .hiddenValue("gp3-mu",
                   number("--gp3-mu", 1e-3, 1e3, false, opt.parameters.gp3_mu));
  return cli;
}

} // namespace

void printCompareHelp()
{
  CompareOptions unused;
  std::printf(
      "Usage: compare_methods INPUT [options]\n"
      "       compare_methods --synthetic N [options]\n"
      "\n"
      "Runs, one after another on the same input, each in its own process:\n"
      "  vts-raw  VTS exact Delaunay triangulation (pcd_to_mesh --no-trim --no-fill)\n"
      "  vts      VTS with trimming and hole filling (pcd_to_mesh's defaults)\n"
      "  gp3      pcl::GreedyProjectionTriangulation after pcl::NormalEstimation\n"
      "  poisson  pcl::Poisson after pcl::NormalEstimation, trimmed to the data\n"
      "           footprint for the figures\n"
      "  bpa      Open3D Ball-Pivoting (compare_bpa, built when Open3D was found)\n"
      "and reports wall time, peak memory, topology (boundary and non-manifold edges,\n"
      "unused input points, flipped and XY-overlapping triangles) and Metro-style\n"
      "error both ways against the input points (and the true surface for\n"
      "--synthetic). Parameters follow the measured point spacing.\n"
      "\n"
      "INPUT: any file pcd_to_mesh reads (.pcd .las .asc .tif .xyz .ply).\n"
      "\n"
      "%s"
      "\n"
      "Exit status: 0 done (a method that failed or timed out is a row, not an "
      "error);\n"
      "1 usage; 2 input file missing or unreadable; 3 fewer than 3 finite points;\n"
      "4 report, TSV or pictures not writable; 5 internal error. Errors print one "
      "line\n"
      "on stderr starting with \"compare_methods: error: \".\n",
      describeOptions(unused).help().c_str());
}

bool parseCompareArgs(int argc, char** argv, CompareOptions& opt, std::string& error)
{
  std::vector<std::string> positional;
  if (!describeOptions(opt).parse(argc, argv, positional, error)) {
    if (error.rfind("unknown option", 0) == 0)
      error += " (see --help)";
    return false;
  }
  opt.parameters.poisson_depth = opt.poisson_depth;
  if (opt.help)
    return true;
  if (!opt.run_method.empty()) {
    if (opt.points_file.empty() || opt.mesh_file.empty() || opt.report_file.empty()) {
      error = "--run-method needs --points, --out and --method-report";
      return false;
    }
    return true;
  }
  if (positional.size() + (opt.synthetic ? 1 : 0) != 1) {
    error = opt.synthetic ? "--synthetic takes no INPUT file"
                          : "expected exactly one INPUT (or --synthetic N)";
    return false;
  }
  if (!positional.empty())
    opt.input = positional[0];
  if (opt.synthetic && !opt.load.classes.empty()) {
    error = "--classes applies to LAS input, not --synthetic";
    return false;
  }
  return true;
}

} // namespace compare
} // namespace pcl_vts
