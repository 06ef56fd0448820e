// The post-passes against the triangulation, in CPU time of this process (on a
// shared machine the CPU time moves far less than the wall clock; with THREADS > 1
// the wall clock of the post-passes is printed too):
//   bench_post_passes DIST N [THREADS]
//   DIST: jittered (a jittered lattice: no hole after the trim) | holes (the same
//   with round voids of radius 4 to 22 on a 200-unit pattern: holes to fill and holes
//   left open) | uniform
// Prints one line: the core pipeline without post-passes (grid, hull, triangulation),
// the triangulation's output check, then reconstructSurface with the defaults as
// pcd_to_mesh runs it: trim alone, trim + fill, and trim + fill + output check (each
// on a copy of the same mesh, min of 3), and a hash of the final mesh (arrays and
// inserted flags) to compare builds and thread counts (THREADS: the pipeline's and
// the post-passes', default 1).
#include <pcl_vts/core/mesh_checks.h>
#include <pcl_vts/core/reconstruct_surface.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace pcl_vts;

double cpuSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double wallSeconds()
{
  return std::chrono::duration<double>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double terrain(double x, double y)
{
  return 50.0 * std::sin(x * 0.01) * std::cos(y * 0.013) + 0.02 * x;
}

std::vector<double> generate(const std::string& dist, std::size_t n)
{
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto side =
      static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
  std::vector<double> xyz;
  xyz.reserve(3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const double i = static_cast<double>(k % side), j = static_cast<double>(k / side);
    if (dist == "holes") {
      const double ci = std::fmod(i, 200.0) - 100.0, cj = std::fmod(j, 200.0) - 100.0;
      const double r =
          4.0 + 6.0 * std::fmod(std::floor(i / 200) * 3 + std::floor(j / 200) * 5, 4.0);
      if (ci * ci + cj * cj < r * r)
        continue;
    }
    double x = i + 0.4 * (unit(rng) - 0.5), y = j + 0.4 * (unit(rng) - 0.5);
    if (dist == "uniform") {
      x = unit(rng) * static_cast<double>(side);
      y = unit(rng) * static_cast<double>(side);
    }
    xyz.insert(xyz.end(), {x, y, terrain(x, y)});
  }
  return xyz;
}

std::uint64_t fnv(const void* data, std::size_t bytes, std::uint64_t h)
{
  const auto* b = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i)
    h = (h ^ b[i]) * 1099511628211ull;
  return h;
}

} // namespace

int main(int argc, char** argv)
{
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr,
                 "usage: bench_post_passes jittered|holes|uniform N [THREADS]\n");
    return 2;
  }
  const std::string dist = argv[1];
  if (dist != "jittered" && dist != "holes" && dist != "uniform") {
    std::fprintf(stderr, "unknown distribution '%s'\n", dist.c_str());
    return 2;
  }
  const std::vector<double> xyz = generate(dist, std::strtoull(argv[2], nullptr, 10));
  const std::size_t n = xyz.size() / 3;
  const auto threads =
      argc == 4 ? static_cast<unsigned>(std::strtoul(argv[3], nullptr, 10)) : 1u;
  VtsOptions options;
  options.threads = threads;
  options.check_output = false;
  VtsResult result;
  double start = cpuSeconds();
  if (const Status s = runVtsPipeline(xyz.data(), n, options, result); !s.ok()) {
    std::fprintf(stderr, "%s\n", s.toString().c_str());
    return 1;
  }
  const double pipeline = cpuSeconds() - start;
  const TriangleMesh triangulated = result.mesh;
  start = cpuSeconds();
  std::string why;
  if (!halfedgesConsistent(triangulated, &why) ||
      !allTrianglesCcw(triangulated, &why)) {
    std::fprintf(stderr, "%s\n", why.c_str());
    return 1;
  }
  const double check = cpuSeconds() - start;
  double trim = 1e300, trim_fill = 1e300, post = 1e300;
  double wall_trim = 1e300, wall_trim_fill = 1e300, wall_post = 1e300;
  TriangleMesh mesh;
  ReconstructionDiagnostics diagnostics;
  for (int round = 0; round < 3; ++round)
    for (int what = 0; what < 3; ++what) {
      mesh = triangulated;
      ReconstructionOptions post_options; // the defaults, as pcd_to_mesh
      post_options.fill = what > 0;
      post_options.check_output = what == 2;
      post_options.threads = threads;
      start = cpuSeconds();
      const double wall_start = wallSeconds();
      if (const Status s = reconstructSurface(mesh, post_options, diagnostics);
          !s.ok()) {
        std::fprintf(stderr, "%s\n", s.toString().c_str());
        return 1;
      }
      double& best = what == 0 ? trim : what == 1 ? trim_fill : post;
      best = std::min(best, cpuSeconds() - start);
      double& wall_best = what == 0   ? wall_trim
                          : what == 1 ? wall_trim_fill
                                      : wall_post;
      wall_best = std::min(wall_best, wallSeconds() - wall_start);
    }
  std::uint64_t h = 1469598103934665603ull;
  h = fnv(mesh.triangles.data(), mesh.triangles.size() * sizeof(VertexId), h);
  h = fnv(mesh.halfedges.data(), mesh.halfedges.size() * sizeof(HalfedgeId), h);
  h = fnv(mesh.xy.data(), mesh.xy.size() * sizeof(Point2), h);
  h = fnv(mesh.z.data(), mesh.z.size() * sizeof(double), h);
  h = fnv(diagnostics.fill.inserted.data(), diagnostics.fill.inserted.size(), h);
  std::printf(
      "%s n=%zu threads=%u cpu_s: grid+hull+triangulate %.3f, its check %.3f, "
      "trim %.3f, trim+fill %.3f, trim+fill+check %.3f; (trim+fill)/(grid+hull+tri) "
      "%.2f; wall_s: trim %.3f, trim+fill %.3f, trim+fill+check %.3f; holes %zu "
      "found %zu filled; hash %016llx\n",
      dist.c_str(), n, threads, pipeline, check, trim, trim_fill, post,
      trim_fill / pipeline, wall_trim, wall_trim_fill, wall_post,
      diagnostics.fill.holes_found, diagnostics.fill.holes_filled,
      static_cast<unsigned long long>(h));
  return 0;
}
