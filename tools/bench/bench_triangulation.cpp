// One measurement per process, so that peak RSS belongs to one method and one input:
//   bench_triangulation METHOD DIST N [SEED [THREADS]]
//   METHOD: vts | cgal      DIST: jittered | uniform | clustered | grid
//   bench_triangulation write-pcd DIST N FILE [SEED]: the same input as a binary PCD
//   with float64 x y z, shifted to UTM-like coordinates (+5e5 east, +5e6 north).
// Prints one JSON line. The input is generated before the clock starts; "baseline"
// is the resident set after generation, so bytes_per_point counts the method alone.
#include <pcl_vts/core/vts_pipeline.h>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Projection_traits_xy_3.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <sys/resource.h>
#include <vector>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Traits = CGAL::Projection_traits_xy_3<Kernel>;
using Delaunay = CGAL::Delaunay_triangulation_2<Traits>;

double currentRssMiB()
{
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0)
      return std::atof(line.c_str() + 6) / 1024.0;
  return 0.0;
}

double peakRssMiB()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

/// Terrain-like heights so the inputs are 2.5D surfaces.
double terrain(double x, double y)
{
  return 50.0 * std::sin(x * 0.01) * std::cos(y * 0.013) + 0.02 * x;
}

std::vector<double> generate(const std::string& dist, std::size_t n, unsigned seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> xyz;
  xyz.reserve(3 * n);
  const auto side =
      static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
  const auto push = [&xyz](double x, double y) {
    xyz.push_back(x);
    xyz.push_back(y);
    xyz.push_back(terrain(x, y));
  };
  if (dist == "jittered" || dist == "grid") {
    const double jitter = dist == "grid" ? 0.0 : 0.4;
    for (std::size_t k = 0; k < n; ++k) {
      const double i = static_cast<double>(k % side), j = static_cast<double>(k / side);
      push(i + jitter * (unit(rng) - 0.5), j + jitter * (unit(rng) - 0.5));
    }
  } else if (dist == "uniform") {
    for (std::size_t k = 0; k < n; ++k)
      push(unit(rng) * static_cast<double>(side),
           unit(rng) * static_cast<double>(side));
  } else if (dist == "clustered") {
    // Dense gaussian clusters separated by large empty voids.
    const std::size_t clusters = 64;
    std::vector<double> centres;
    for (std::size_t c = 0; c < clusters; ++c) {
      centres.push_back(unit(rng) * static_cast<double>(side) * 4.0);
      centres.push_back(unit(rng) * static_cast<double>(side) * 4.0);
    }
    std::normal_distribution<double> gauss(0.0, static_cast<double>(side) * 0.05);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t c = k % clusters;
      push(centres[2 * c] + gauss(rng), centres[2 * c + 1] + gauss(rng));
    }
  } else {
    std::fprintf(stderr, "unknown distribution '%s'\n", dist.c_str());
    std::exit(1);
  }
  return xyz;
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

} // namespace

int main(int argc, char** argv)
{
  if (argc >= 5 && std::strcmp(argv[1], "write-pcd") == 0) {
    const auto count = static_cast<std::size_t>(std::atof(argv[3]));
    const unsigned s = argc > 5 ? static_cast<unsigned>(std::atoi(argv[5])) : 1u;
    return writePcd(generate(argv[2], count, s), argv[4]);
  }
  if (argc < 4) {
    std::fprintf(stderr,
                 "usage: %s vts|cgal jittered|uniform|clustered|grid N [SEED]\n"
                 "       %s write-pcd jittered|uniform|clustered|grid N FILE [SEED]\n",
                 argv[0], argv[0]);
    return 1;
  }
  const std::string method = argv[1], dist = argv[2];
  const auto n = static_cast<std::size_t>(std::atof(argv[3]));
  const unsigned seed = argc > 4 ? static_cast<unsigned>(std::atoi(argv[4])) : 1u;
  const unsigned threads = argc > 5 ? static_cast<unsigned>(std::atoi(argv[5])) : 1u;
  std::vector<double> xyz = generate(dist, n, seed);
  std::vector<Traits::Point_2> cgal_points;
  if (method == "cgal") {
    cgal_points.reserve(n);
    for (std::size_t k = 0; k < n; ++k)
      cgal_points.emplace_back(xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]);
    std::vector<double>().swap(xyz);
  }
  const double baseline = currentRssMiB();
  const auto start = std::chrono::steady_clock::now();
  std::size_t triangles = 0;
  std::string stages;
  if (method == "vts") {
    pcl_vts::VtsOptions options;
    options.check_output = false;
    options.threads = threads;
    pcl_vts::VtsResult result;
    const pcl_vts::Status status =
        pcl_vts::runVtsPipeline(xyz.data(), n, options, result);
    if (!status.ok()) {
      std::fprintf(stderr, "%s\n", status.toString().c_str());
      return 2;
    }
    triangles = result.mesh.triangleCount();
    const pcl_vts::Diagnostics& d = result.diagnostics;
    const double searches = static_cast<double>(d.local_searches + d.widened_searches);
    char buffer[256];
    std::snprintf(buffer, sizeof buffer,
                  ",\"grid_s\":%.4f,\"hull_s\":%.4f,\"triangulate_s\":%.4f,"
                  "\"cells_per_search\":%.2f,\"points_per_search\":%.2f,"
                  "\"widened_share\":%.5f",
                  d.seconds_grid, d.seconds_hull, d.seconds_triangulate,
                  static_cast<double>(d.cells_visited) / searches,
                  static_cast<double>(d.points_tested) / searches,
                  static_cast<double>(d.widened_searches) / searches);
    stages = buffer;
  } else if (method == "cgal") {
    // Range insertion: CGAL spatially sorts first, its fastest use.
    Delaunay dt(cgal_points.begin(), cgal_points.end());
    triangles = dt.number_of_faces();
  } else {
    std::fprintf(stderr, "unknown method '%s'\n", method.c_str());
    return 1;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double peak = peakRssMiB();
  std::printf("{\"method\":\"%s\",\"dist\":\"%s\",\"n\":%zu,\"threads\":%u,"
              "\"seconds\":%.4f,"
              "\"ns_per_point\":%.1f,\"triangles\":%zu,\"peak_rss_mib\":%.1f,"
              "\"input_rss_mib\":%.1f,\"bytes_per_point_above_input\":%.1f%s}\n",
              method.c_str(), dist.c_str(), n, method == "vts" ? threads : 1u, seconds,
              1e9 * seconds / static_cast<double>(n), triangles, peak, baseline,
              (peak - baseline) * 1024.0 * 1024.0 / static_cast<double>(n), stages.c_str());
  return 0;
}
