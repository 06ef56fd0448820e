// compare_methods' command line (compare_options.h).
#include "compare_options.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <sstream>

namespace pcl_vts {
namespace compare {
namespace {

bool parseNumber(const std::string& name, const std::string& text, double lo, double hi,
                 double& value, std::string& error)
{
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0])) ||
      *end != '\0' || errno == ERANGE || !std::isfinite(value) || value < lo ||
      value > hi) {
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

} // namespace

void printCompareHelp()
{
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
      "Options:\n"
      "  -h, --help               print this help and exit\n"
      "  --synthetic N            synthetic terrain of N points (known surface) "
      "instead\n"
      "                           of INPUT, 100 <= N <= 1e8\n"
      "  --classes LIST           LAS only: classification codes to keep, e.g. 2\n"
      "  --name NAME              label of the data set: file names and TSV (default:\n"
      "                           the input's file name, or synthetic_N)\n"
      "  --title TEXT             heading of the Markdown section (default: NAME)\n"
      "  --methods LIST           comma-separated subset of "
      "vts-raw,vts,gp3,poisson,bpa\n"
      "                           (default: all)\n"
      "  --time-limit S           seconds per method before it is killed and reported\n"
      "                           as timed out, S > 0 (default: %g)\n"
      "  --poisson-depth D        octree depth 1..16; 0 = from extent / spacing,\n"
      "                           clamped to 6..9 (default: 0)\n"
      "  --poisson-trim K         keep Poisson triangles whose XY centroid is within\n"
      "                           K x spacing of an input point, K > 0 (default: %g)\n"
      "  --samples-per-triangle S Metro samples per triangle on average, S > 0\n"
      "                           (default: %g)\n"
      "  --max-samples N          cap on the samples per mesh; 0 = none (default: 0)\n"
      "  --threads N              threads for the metrics (methods always run on "
      "one);\n"
      "                           0 = all cores (default: 0)\n"
      "  --report FILE.md         write the Markdown section here (default: print it)\n"
      "  --tsv FILE               write one tab-separated row per method here\n"
      "  --pictures DIR           write DIR/NAME_top.png and DIR/NAME_oblique.png\n"
      "  --picture-link PATH      folder of the pictures as the Markdown links it\n"
      "                           (default: DIR)\n"
      "  --picture-width W        pixels per method, 64..4000 (default: %d)\n"
      "  --work-dir DIR           folder for the exchanged files (default: a new\n"
      "                           folder under $TMPDIR or /tmp, removed at the end)\n"
      "  --keep-work              keep the exchanged files and logs\n"
      "\n"
      "Exit status: 0 done (a method that failed or timed out is a row, not an "
      "error);\n"
      "1 usage; 2 input file missing or unreadable; 3 fewer than 3 finite points;\n"
      "4 report, TSV or pictures not writable; 5 internal error. Errors print one "
      "line\n"
      "on stderr starting with \"compare_methods: error: \".\n",
      DEFAULT_TIME_LIMIT, DEFAULT_POISSON_TRIM, DEFAULT_SAMPLES_PER_TRIANGLE,
      DEFAULT_PICTURE_WIDTH);
}

bool parseCompareArgs(int argc, char** argv, CompareOptions& opt, std::string& error)
{
  static const char* const WITH_VALUE[] = {
      "--synthetic",     "--classes",      "--name",
      "--title",         "--methods",      "--time-limit",
      "--poisson-depth", "--poisson-trim", "--samples-per-triangle",
      "--max-samples",   "--threads",      "--report",
      "--tsv",           "--pictures",     "--picture-link",
      "--picture-width", "--work-dir",     "--run-method",
      "--points",        "--out",          "--method-report",
      "--spacing",       "--extent",       "--normal-k",
      "--gp3-mu"};
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.size() < 2 || arg[0] != '-') {
      positional.push_back(arg);
      continue;
    }
    const bool takes_value = std::any_of(std::begin(WITH_VALUE), std::end(WITH_VALUE),
                                         [&](const char* name) { return arg == name; });
    std::string value;
    if (takes_value) {
      if (i + 1 >= argc) {
        error = "option '" + arg + "' needs a value";
        return false;
      }
      value = argv[++i];
    }
    double number = 0.0;
    if (arg == "-h" || arg == "--help")
      opt.help = true;
    else if (arg == "--keep-work")
      opt.keep_work = true;
    else if (arg == "--synthetic") {
      if (!parseWhole(arg, value, 100, 1e8, number, error))
        return false;
      opt.synthetic = static_cast<std::size_t>(number);
    } else if (arg == "--classes") {
      if (Status s = pcl_vts::parseClassList(value, opt.load.classes); !s.ok()) {
        error = "--classes: " + s.message;
        return false;
      }
    } else if (arg == "--name")
      opt.name = value;
    else if (arg == "--title")
      opt.title = value;
    else if (arg == "--methods") {
      opt.methods.clear();
      std::stringstream in(value);
      std::string item;
      while (std::getline(in, item, ',')) {
        const auto& all = allMethodNames();
        if (std::find(all.begin(), all.end(), item) == all.end()) {
          error =
              "--methods: '" + item + "' is not one of vts-raw, vts, gp3, poisson, bpa";
          return false;
        }
        opt.methods.push_back(item);
      }
      if (opt.methods.empty()) {
        error = "--methods: empty list";
        return false;
      }
    } else if (arg == "--time-limit") {
      if (!parseNumber(arg, value, 1e-3, 1e6, opt.time_limit, error))
        return false;
    } else if (arg == "--poisson-depth") {
      if (!parseWhole(arg, value, 0, 16, number, error))
        return false;
      opt.poisson_depth = static_cast<int>(number);
    } else if (arg == "--poisson-trim") {
      if (!parseNumber(arg, value, 1e-6, 1e6, opt.poisson_trim, error))
        return false;
    } else if (arg == "--samples-per-triangle") {
      if (!parseNumber(arg, value, 1e-6, 1e4, opt.samples_per_triangle, error))
        return false;
    } else if (arg == "--max-samples") {
      if (!parseWhole(arg, value, 0, 1e10, number, error))
        return false;
      opt.max_samples = static_cast<std::size_t>(number);
    } else if (arg == "--threads") {
      if (!parseWhole(arg, value, 0, 4096, number, error))
        return false;
      opt.threads = static_cast<unsigned>(number);
    } else if (arg == "--report")
      opt.report = value;
    else if (arg == "--tsv")
      opt.tsv = value;
    else if (arg == "--pictures")
      opt.pictures = value;
    else if (arg == "--picture-link")
      opt.picture_link = value;
    else if (arg == "--picture-width") {
      if (!parseWhole(arg, value, 64, 4000, number, error))
        return false;
      opt.picture_width = static_cast<int>(number);
    } else if (arg == "--work-dir")
      opt.work_dir = value;
    // Method-process options (internal).
    else if (arg == "--run-method")
      opt.run_method = value;
    else if (arg == "--points")
      opt.points_file = value;
    else if (arg == "--out")
      opt.mesh_file = value;
    else if (arg == "--method-report")
      opt.report_file = value;
    else if (arg == "--spacing") {
      if (!parseNumber(arg, value, 1e-300, 1e300, opt.parameters.spacing, error))
        return false;
    } else if (arg == "--extent") {
      if (!parseNumber(arg, value, 0, 1e300, opt.parameters.extent, error))
        return false;
    } else if (arg == "--normal-k") {
      if (!parseWhole(arg, value, 3, 1000, number, error))
        return false;
      opt.parameters.normal_k = static_cast<int>(number);
    } else if (arg == "--gp3-mu") {
      if (!parseNumber(arg, value, 1e-3, 1e3, opt.parameters.gp3_mu, error))
        return false;
    } else {
      error = "unknown option '" + arg + "' (see --help)";
      return false;
    }
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
