// compare_methods: VTS against PCL's GreedyProjection and Poisson and Open3D's
// Ball-Pivoting on the same input and machine, one method at a time, each in its own
// process (peak memory, time limit, crashes become rows); the parent loads every mesh
// and measures it with the same code (mesh_metrics.h), then writes a Markdown section,
// TSV rows for the time plot and picture strips. tools/compare/run_compare.sh drives
// it for docs/comparison.md (`make compare`).
#include "compare_files.h"
#include "compare_options.h"
#include "compare_pictures.h"
#include "compare_report.h"
#include "mesh_metrics.h"
#include "method_runner.h"
#include "methods.h"
#include "poisson_footprint.h"
#include "synthetic_terrain.h"

#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/io/point_cloud_loader.h>

#include <pcl/console/print.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace {

using namespace pcl_vts::compare;
using pcl_vts::PictureFrame;
using pcl_vts::Status;
using pcl_vts::StatusCode;

constexpr int EXIT_USAGE = 1;    // bad option or value
constexpr int EXIT_INPUT = 2;    // input missing, unreadable, unknown format
constexpr int EXIT_DATA = 3;     // input read but fewer than 3 finite points
constexpr int EXIT_OUTPUT = 4;   // report, TSV or pictures could not be written
constexpr int EXIT_INTERNAL = 5; // a bug or out of memory

/// Method-process mode: read points, run one method, write its mesh and report.
int runMethodProcess(const CompareOptions& opt)
{
  PointSet points;
  if (Status s = readPointSet(opt.points_file, points); !s.ok()) {
    std::fprintf(stderr, "compare_methods: error: %s\n", s.toString().c_str());
    return EXIT_INPUT;
  }
  if (opt.run_method == "idle") // baseline memory: the binary with the points loaded
    return 0;
  CompareMesh mesh;
  MethodReport report;
  Status status;
  if (opt.run_method == "vts-raw" || opt.run_method == "vts")
    status = runVtsMethod(opt.run_method, points, mesh, report);
  else if (opt.run_method == "gp3" || opt.run_method == "poisson")
    status = runPclMethod(opt.run_method, points, opt.parameters, mesh, report);
  else
    status = Status::error(StatusCode::INVALID_PARAMETER,
                           "no in-process method '" + opt.run_method + "'");
  if (!status.ok()) {
    std::fprintf(stderr, "compare_methods: error: %s: %s\n", opt.run_method.c_str(),
                 status.toString().c_str());
    return EXIT_DATA;
  }
  if (Status s = writeMeshPly(opt.mesh_file, mesh); !s.ok()) {
    std::fprintf(stderr, "compare_methods: error: %s\n", s.toString().c_str());
    return EXIT_OUTPUT;
  }
  if (Status s = writeMethodReport(opt.report_file, report); !s.ok()) {
    std::fprintf(stderr, "compare_methods: error: %s\n", s.toString().c_str());
    return EXIT_OUTPUT;
  }
  return 0;
}

std::string fileStem(const std::string& path)
{
  const std::size_t slash = path.rfind('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::size_t dot = name.find('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

/// Loads INPUT (or generates the synthetic set) into the local frame.
int loadInput(const CompareOptions& opt, PointSet& points, DatasetInfo& info)
{
  if (opt.synthetic) {
    points = syntheticTerrain(opt.synthetic, 1);
    const double side = syntheticSide(opt.synthetic);
    std::ostringstream text;
    text
        << "synthetic terrain (tools/compare/synthetic_terrain.cpp), uniform random XY "
           "in a "
        << side << " m square, z = f(x, y) exactly";
    info.input = text.str();
    info.has_truth = true;
    info.truth_description =
        "mesh -> truth: |z - f(x, y)| at the samples; truth -> mesh: exact distance "
        "from a jittered lattice of points on the true surface over the square";
    return 0;
  }
  std::vector<double> xyz;
  pcl_vts::CloudDescription description;
  if (Status s = pcl_vts::loadPointCloud(opt.input, opt.load, xyz, description);
      !s.ok()) {
    std::fprintf(stderr, "compare_methods: error: %s\n", s.toString().c_str());
    return s.code == StatusCode::EMPTY_INPUT         ? EXIT_DATA
           : s.code == StatusCode::INVALID_PARAMETER ? EXIT_USAGE
                                                     : EXIT_INPUT;
  }
  double lo[3] = {INFINITY, INFINITY, INFINITY};
  std::size_t dropped = 0;
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3) {
    if (!std::isfinite(xyz[i]) || !std::isfinite(xyz[i + 1]) ||
        !std::isfinite(xyz[i + 2])) {
      ++dropped;
      continue;
    }
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], xyz[i + k]);
    points.xyz.insert(points.xyz.end(), {xyz[i], xyz[i + 1], xyz[i + 2]});
  }
  // Whole-unit offset of the lower corner: float coordinates stay small for PCL.
  if (points.size() > 0)
    for (int k = 0; k < 2; ++k)
      points.offset[k] = std::floor(lo[k]);
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 2; ++k)
      points.xyz[3 * i + k] -= points.offset[k];
  info.input = "`" + opt.input + "` (" + description.details + ")";
  if (!opt.load.classes.empty())
    info.input_notes.push_back(
        "classes kept: " + std::to_string(description.points_kept) + " of " +
        std::to_string(description.points_read));
  if (dropped)
    info.input_notes.push_back(std::to_string(dropped) + " non-finite points dropped");
  return 0;
}

/// Trims a Poisson mesh to the data footprint and says what was cut and how far the
/// raw output reached.
std::string trimPoissonMesh(CompareMesh& mesh, const PointSet& points, double spacing,
                            double factor, const PictureFrame& frame)
{
  const FootprintTrim trim = trimToFootprint(mesh, points, spacing, factor);
  std::ostringstream note;
  note.precision(3);
  const double cut =
      trim.area_before > 0.0 ? 100.0 * trim.area_cut / trim.area_before : 0.0;
  note << "raw output " << trim.triangles_before << " triangles reaching x "
       << trim.box_min[0] << ".." << trim.box_max[0] << ", y " << trim.box_min[1]
       << ".." << trim.box_max[1] << " (data: x " << frame.min[0] << ".."
       << frame.max[0] << ", y " << frame.min[1] << ".." << frame.max[1] << "), up to "
       << trim.max_centroid_distance
       << " from the nearest input point in XY: it extrapolates past the data; " << cut
       << " % of its area (" << (trim.triangles_before - trim.triangles_after)
       << " triangles) lies farther than " << factor
       << " x spacing = " << trim.threshold
       << " in XY from every input point (triangle centroid to nearest point) and "
          "was cut before every figure above";
  return note.str();
}

/// Parent mode: every method in turn, metrics, pictures, report.
int runComparison(const CompareOptions& opt)
{
  PointSet points;
  DatasetInfo info;
  if (int code = loadInput(opt, points, info); code != 0)
    return code;
  if (points.size() < 3) {
    std::fprintf(stderr, "compare_methods: error: %s has %zu finite points (need 3)\n",
                 opt.input.c_str(), points.size());
    return EXIT_DATA;
  }
  info.name = !opt.name.empty() ? opt.name
              : opt.synthetic   ? "synthetic_" + std::to_string(opt.synthetic)
                                : fileStem(opt.input);
  info.title = opt.title.empty() ? info.name : opt.title;
  info.points = points.size();
  for (int k = 0; k < 3; ++k)
    info.offset[k] = points.offset[k];

  std::string work = opt.work_dir;
  if (work.empty()) {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern =
        std::string(tmp && *tmp ? tmp : "/tmp") + "/compare_methods.XXXXXX";
    if (!::mkdtemp(pattern.data())) {
      std::fprintf(stderr, "compare_methods: error: cannot create a work folder: %s\n",
                   std::strerror(errno));
      return EXIT_OUTPUT;
    }
    work = pattern;
  } else if (::mkdir(work.c_str(), 0755) != 0 && errno != EEXIST) {
    std::fprintf(stderr, "compare_methods: error: %s: %s\n", work.c_str(),
                 std::strerror(errno));
    return EXIT_OUTPUT;
  }
  if (Status s = writePointSet(work + "/points.bin", points); !s.ok()) {
    std::fprintf(stderr, "compare_methods: error: %s\n", s.toString().c_str());
    return EXIT_OUTPUT;
  }

  const unsigned threads = opt.threads ? opt.threads : pcl_vts::allCores();
  const PointReference reference(points, 10, threads);
  const PictureFrame frame = frameOfPoints(points);
  for (int k = 0; k < 3; ++k)
    info.extent[k] = frame.max[k] - frame.min[k];
  MethodParameters parameters;
  parameters.spacing =
      reference.medianSpacing() > 0.0 ? reference.medianSpacing() : 1.0;
  parameters.extent = std::max({info.extent[0], info.extent[1], info.extent[2]});
  parameters.poisson_depth = poissonDepth([&] {
    MethodParameters p = parameters;
    p.poisson_depth = opt.poisson_depth;
    return p;
  }());
  info.spacing = parameters.spacing;

  MetricsOptions metrics;
  metrics.samples_per_triangle = opt.samples_per_triangle;
  metrics.max_samples = opt.max_samples;
  metrics.threads = threads;
  if (info.has_truth) {
    metrics.truth = syntheticHeight;
    metrics.truth_side = syntheticSide(opt.synthetic);
    metrics.truth_samples = std::min<std::size_t>(points.size(), 1000000);
  }
  {
    std::ostringstream text;
    text << "about " << opt.samples_per_triangle
         << " samples per triangle, area-weighted";
    if (opt.max_samples)
      text << " (at most " << opt.max_samples << ")";
    text << ", tangent discs from k = 10 neighbours, " << threads
         << " threads; time limit " << opt.time_limit << " s per method";
    info.metric_description = text.str();
  }
  std::fprintf(stderr, "[compare] %s: %zu points, spacing %.4g, Poisson depth %d\n",
               info.name.c_str(), points.size(), parameters.spacing,
               parameters.poisson_depth);

  info.input_notes.push_back(idleBaseline(opt, work));

  std::vector<MethodRow> rows;
  std::vector<MethodPictures> pictures;
  for (const std::string& method : opt.methods) {
    CompareMesh mesh;
    MethodRow row = runOneMethod(method, opt, work, parameters, mesh);
    if (row.failure.empty() && method == "poisson") {
      row.notes.push_back(
          trimPoissonMesh(mesh, points, parameters.spacing, opt.poisson_trim, frame));
      if (mesh.triangleCount() == 0)
        row.failure = "nothing left after trimming to the data footprint";
    }
    std::string caption = methodTitle(method);
    if (row.failure.empty()) {
      row.metrics = computeMeshMetrics(mesh, reference, metrics);
      std::fprintf(
          stderr,
          "[compare] %s %s: %.2f s (+%.2f s normals), %.1f MiB, %zu triangles; "
          "metrics %.1f s (%s)\n",
          info.name.c_str(), method.c_str(), row.report.seconds,
          std::max(0.0, row.report.normal_seconds),
          static_cast<double>(row.outcome.peak_rss_kib) / 1024.0,
          row.metrics.topology.triangles, row.metrics.seconds,
          row.metrics.timing.c_str());
    } else {
      std::fprintf(stderr, "[compare] %s %s: failed: %s\n", info.name.c_str(),
                   method.c_str(), row.failure.c_str());
      caption += ": failed";
    }
    if (!opt.pictures.empty())
      pictures.push_back(
          renderMethod(row.failure.empty() ? &mesh : nullptr,
                       row.failure.empty() ? &row.metrics.topology : nullptr, frame,
                       opt.picture_width, caption));
    rows.push_back(std::move(row));
  }

  if (!opt.pictures.empty()) {
    info.picture_link = opt.picture_link.empty() ? opt.pictures : opt.picture_link;
    if (Status s = writePictureStrips(opt.pictures, info.name, pictures); !s.ok()) {
      std::fprintf(stderr, "compare_methods: error: %s\n", s.toString().c_str());
      return EXIT_OUTPUT;
    }
  }
  const std::string section = markdownSection(info, rows);
  if (opt.report.empty())
    std::fputs(section.c_str(), stdout);
  else if (Status s = writeTextFile(opt.report, section); !s.ok()) {
    std::fprintf(stderr, "compare_methods: error: %s\n", s.toString().c_str());
    return EXIT_OUTPUT;
  }
  if (!opt.tsv.empty())
    if (Status s = writeTextFile(opt.tsv, tsvRows(info, rows)); !s.ok()) {
      std::fprintf(stderr, "compare_methods: error: %s\n", s.toString().c_str());
      return EXIT_OUTPUT;
    }
  if (!opt.keep_work && opt.work_dir.empty()) {
    for (const std::string& method : opt.methods)
      for (const char* ext : {".ply", ".txt", ".log"})
        std::remove((work + "/" + method + ext).c_str());
    std::remove((work + "/points.bin").c_str());
    ::rmdir(work.c_str());
  }
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  try {
    CompareOptions opt;
    std::string error;
    if (!parseCompareArgs(argc, argv, opt, error)) {
      std::fprintf(stderr, "compare_methods: error: %s\n", error.c_str());
      return EXIT_USAGE;
    }
    if (opt.help) {
      printCompareHelp();
      return 0;
    }
    pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
    return opt.run_method.empty() ? runComparison(opt) : runMethodProcess(opt);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "compare_methods: error: out of memory\n");
    return EXIT_INTERNAL;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "compare_methods: error: %s\n", e.what());
    return EXIT_INTERNAL;
  }
}
