// One measurement per process, so that peak RSS belongs to one method and one input:
//   bench_triangulation METHOD DIST N [SEED [THREADS]]
//   bench_triangulation METHOD file PATH [--classes LIST] [--name NAME] [THREADS]
//   METHOD: vts | vts-grid | vts-search | cgal
//   DIST: jittered | uniform | clustered | grid | raster
//   vts runs the core's defaults, as pcd_to_mesh does; vts-search is vts with the
//   cache blocks off (VtsOptions::cache_blocks, docs/scaling.md: the mediatrix search
//   alone, as --no-cache-blocks); vts-grid is vts with the lattice fast path off
//   (VtsOptions::lattice), the grid path on every input, as --no-lattice; raster is a
//   square DEM-like lattice (N cells, spacing 1, rows from the top) with NODATA
//   ellipses (one per 20000 cells, radii 0.5 to 12.5 cells) and 0.1 % single-cell
//   dropouts. bench_triangulation write-pcd DIST N FILE [SEED]: the same input as a
//   binary PCD with float64 x y z, shifted to UTM-like coordinates (+5e5 east, +5e6
//   north).
// Prints one JSON line ("seconds": wall clock; "cpu_s": the process's user + system
// CPU time over the same span; "wall_us" and "cpu_us" the same in microseconds, for
// inputs of a millisecond or less). The input is generated or read
// (pcl_vts::loadPointCloud, any file pcd_to_mesh reads) before the clock starts.
// "input_rss_mib" is the resident set once the input is in memory (after malloc_trim);
// the high-water mark is reset there (/proc/self/clear_refs), so "peak_rss_mib" is the
// peak while the method ran (input included) and bytes_per_point_above_input counts the
// method alone (null where the mark could not be reset). It counts pages freed but kept
// resident by malloc, as the system does: the pipeline hands them back between stages
// (src/core/release_memory.h). Both methods get the same points: VTS merges identical
// XY positions itself (its duplicate rule, timed), CGAL's insertion keeps the first
// vertex at an XY position (timed too); "distinct" lets the two vertex counts be
// compared. "hash" (vts, computed after the clock): meshHash of the output, equal for
// every thread count; "set_hash": meshSetHash, the same for any order of the same
// triangles.
#include "bench_inputs.h"
#include "cli_words.h"

#include <pcl_vts/core/stopwatch.h>
#include <pcl_vts/core/vts_pipeline.h>
#include <pcl_vts/io/point_cloud_loader.h>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Projection_traits_xy_3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <malloc.h>
#include <random>
#include <string>
#include <sys/resource.h>
#include <vector>

namespace {

using pcl_vts::bench::generate;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Traits = CGAL::Projection_traits_xy_3<Kernel>;
using Delaunay = CGAL::Delaunay_triangulation_2<Traits>;

struct Measure {
  std::string method, dist, input;
  std::size_t n = 0;
  unsigned threads = 1;
  double load_seconds = -1.0;
  double load_peak_mib = 0.0;
};

double statusMiB(const char* key)
{
  std::ifstream status("/proc/self/status");
  std::string line;
  const std::size_t length = std::strlen(key);
  while (std::getline(status, line))
    if (line.compare(0, length, key) == 0)
      return std::atof(line.c_str() + length) / 1024.0;
  return 0.0;
}

/// CPU seconds (user + system) of this process so far: robust to other work on the
/// machine, where the wall clock is not.
double cpuSeconds()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

/// Sets the high-water mark of the resident set to the current resident set (Linux
/// >= 4.0). False where that is not allowed: the peak is then the process's.
bool resetPeakRss()
{
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.close();
  return !clear.fail();
}

int writePcd(const std::vector<double>& xyz, const char* path)
{
  const std::size_t n = xyz.size() / 3;
  std::FILE* f = std::fopen(path, "wb");
  if (f == nullptr) {
    std::perror(path);
    return 1;
  }
  std::fprintf(f,
               "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\n"
               "SIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH %zu\nHEIGHT 1\n"
               "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS %zu\nDATA binary\n",
               n, n);
  std::vector<double> shifted(xyz);
  for (std::size_t k = 0; k < n; ++k) {
    shifted[3 * k] += 500000.0;
    shifted[3 * k + 1] += 5000000.0;
  }
  const bool ok =
      std::fwrite(shifted.data(), sizeof(double), shifted.size(), f) == shifted.size();
  return (std::fclose(f) == 0 && ok) ? 0 : 1;
}

std::string baseName(const std::string& path)
{
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// JSON string contents: the few characters a file name may hold that need escaping.
std::string jsonText(const std::string& text)
{
  std::string out;
  for (const char c : text) {
    if (c == '"' || c == '\\')
      out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20)
      out += c;
  }
  return out;
}

int usage(const char* self)
{
  std::fprintf(
      stderr,
      "usage: %s vts|vts-grid|vts-search|cgal jittered|uniform|clustered|grid|raster N "
      "[SEED [THREADS]]\n"
      "       %s vts|vts-grid|vts-search|cgal file PATH [--classes LIST] [--name NAME] "
      "[THREADS]\n"
      "       %s write-pcd jittered|uniform|clustered|grid N FILE [SEED]\n",
      self, self, self);
  return 1;
}

/// Reads the file mode's arguments (after "METHOD file") and the file itself.
int loadFile(int argc, char** argv, Measure& m, std::vector<double>& xyz)
{
  if (argc < 4)
    return usage(argv[0]);
  const std::string path = argv[3];
  pcl_vts::CloudLoadOptions options;
  m.input = baseName(path);
  for (int k = 4; k < argc; ++k) {
    const std::string arg = argv[k];
    if ((arg == "--classes" || arg == "--name") && k + 1 < argc) {
      const std::string value = argv[++k];
      if (arg == "--name") {
        m.input = value;
      } else if (std::string error;
                 !pcl_vts::tools::parseClassList(value, options.classes, error)) {
        std::fprintf(stderr, "bench_triangulation: --classes: %s\n", error.c_str());
        return 1;
      }
    } else if (!arg.empty() && arg[0] != '-') {
      m.threads = static_cast<unsigned>(std::atoi(arg.c_str()));
    } else {
      std::fprintf(stderr, "bench_triangulation: unknown argument '%s'\n", arg.c_str());
      return usage(argv[0]);
    }
  }
  const pcl_vts::Stopwatch watch;
  pcl_vts::CloudDescription description;
  const pcl_vts::Status status =
      pcl_vts::loadPointCloud(path, options, xyz, description);
  if (!status.ok()) {
    std::fprintf(stderr, "bench_triangulation: cannot read '%s': %s\n", path.c_str(),
                 status.toString().c_str());
    return 2;
  }
  m.load_seconds = watch.seconds();
  m.n = xyz.size() / 3;
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  if (argc >= 5 && std::strcmp(argv[1], "write-pcd") == 0) {
    const auto count = static_cast<std::size_t>(std::atof(argv[3]));
    const unsigned s = argc > 5 ? static_cast<unsigned>(std::atoi(argv[5])) : 1u;
    return writePcd(generate(argv[2], count, s), argv[4]);
  }
  if (argc < 4)
    return usage(argv[0]);
  Measure m;
  m.method = argv[1];
  m.dist = argv[2];
  if (m.method != "vts" && m.method != "vts-grid" && m.method != "vts-search" &&
      m.method != "cgal") {
    std::fprintf(stderr, "unknown method '%s'\n", m.method.c_str());
    return usage(argv[0]);
  }
  std::vector<double> xyz;
  if (m.dist == "file") {
    if (int code = loadFile(argc, argv, m, xyz); code != 0)
      return code;
  } else {
    m.input = m.dist;
    m.n = static_cast<std::size_t>(std::atof(argv[3]));
    const unsigned seed = argc > 4 ? static_cast<unsigned>(std::atoi(argv[4])) : 1u;
    m.threads = argc > 5 ? static_cast<unsigned>(std::atoi(argv[5])) : 1u;
    xyz = generate(m.dist, m.n, seed);
    m.n = xyz.size() / 3; // raster: the N cells less the NODATA ones
  }
  const std::size_t n = m.n;
  std::vector<Traits::Point_2> cgal_points;
  if (m.method == "cgal") {
    // Non-finite points (VTS drops and counts them) would break CGAL: left out.
    cgal_points.reserve(n);
    for (std::size_t k = 0; k < n; ++k)
      if (std::isfinite(xyz[3 * k]) && std::isfinite(xyz[3 * k + 1]) &&
          std::isfinite(xyz[3 * k + 2]))
        cgal_points.emplace_back(xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]);
    std::vector<double>().swap(xyz);
  }
  m.load_peak_mib = statusMiB("VmHWM:");
  ::malloc_trim(0);
  const double baseline = statusMiB("VmRSS:");
  const bool peak_reset = resetPeakRss();
  const pcl_vts::Stopwatch watch;
  const double cpu_start = cpuSeconds();
  std::size_t triangles = 0, distinct = 0;
  std::string stages;
  pcl_vts::VtsResult result;
  if (m.method != "cgal") {
    pcl_vts::VtsOptions options;
    options.lattice = m.method != "vts-grid";
    options.cache_blocks = m.method != "vts-search";
    options.check_output = false;
    options.input_map = false; // as pcd_to_mesh runs it: no per-input vertex map
    options.threads = m.threads;
    const pcl_vts::Status status =
        pcl_vts::runVtsPipeline(xyz.data(), n, options, result);
    if (!status.ok()) {
      std::fprintf(stderr, "%s\n", status.toString().c_str());
      return 2;
    }
    triangles = result.mesh.triangleCount();
    const pcl_vts::Diagnostics& d = result.diagnostics;
    distinct = d.distinct_points;
    const double searches =
        std::max(1.0, static_cast<double>(d.local_searches + d.widened_searches));
    char buffer[384];
    std::snprintf(buffer, sizeof buffer,
                  ",\"grid_s\":%.4f,\"hull_s\":%.4f,\"triangulate_s\":%.4f,"
                  "\"cells_per_search\":%.2f,\"points_per_search\":%.2f,"
                  "\"widened_share\":%.5f,\"lattice\":%s,\"fringe_points\":%zu,"
                  "\"fringe_rounds\":%zu",
                  d.seconds_grid, d.seconds_hull, d.seconds_triangulate,
                  static_cast<double>(d.cells_visited) / searches,
                  static_cast<double>(d.points_tested) / searches,
                  static_cast<double>(d.widened_searches) / searches,
                  d.lattice_columns > 0 ? "true" : "false", d.lattice_fringe_points,
                  d.lattice_fringe_rounds);
    stages = buffer;
  } else {
    // Range insertion: CGAL spatially sorts first, its fastest use.
    Delaunay dt(cgal_points.begin(), cgal_points.end());
    triangles = dt.number_of_faces();
    distinct = dt.number_of_vertices();
  }
  const double seconds = watch.seconds();
  const double cpu = cpuSeconds() - cpu_start;
  const double peak = statusMiB("VmHWM:");
  if (m.method != "cgal") { // after the clock: the same output for every thread count
    char hash[96];
    std::snprintf(
        hash, sizeof hash, ",\"hash\":\"%016llx\",\"set_hash\":\"%016llx\"",
        static_cast<unsigned long long>(pcl_vts::bench::meshHash(result.mesh)),
        static_cast<unsigned long long>(pcl_vts::bench::meshSetHash(result.mesh)));
    stages += hash;
  }
  // Without the reset the high-water mark may be the input's load: no figure then.
  char above[48] = "null";
  if (peak_reset)
    std::snprintf(above, sizeof above, "%.1f",
                  (peak - baseline) * 1024.0 * 1024.0 / static_cast<double>(n));
  char load[96] = "";
  if (m.load_seconds >= 0.0)
    std::snprintf(load, sizeof load, ",\"load_s\":%.4f", m.load_seconds);
  std::printf("{\"method\":\"%s\",\"dist\":\"%s\",\"input\":\"%s\",\"n\":%zu,"
              "\"distinct\":%zu,\"threads\":%u,\"seconds\":%.4f,\"cpu_s\":%.4f,"
              "\"wall_us\":%.1f,\"cpu_us\":%.1f,\"ns_per_point\":%.1f,\"triangles\":%"
              "zu,\"peak_rss_mib\":%.1f,"
              "\"input_rss_mib\":%.1f,\"load_peak_mib\":%.1f,\"peak_reset\":%s,"
              "\"bytes_per_point_above_input\":%s%s%s}\n",
              m.method.c_str(), m.dist.c_str(), jsonText(m.input).c_str(), n, distinct,
              m.method == "cgal" ? 1u : m.threads, seconds, cpu, 1e6 * seconds,
              1e6 * cpu, 1e9 * seconds / static_cast<double>(n), triangles, peak,
              baseline, m.load_peak_mib, peak_reset ? "true" : "false", above, load,
              stages.c_str());
  return 0;
}
