// Thread scaling of the core pipeline, PCL-free and linked statically (glibc and
// libstdc++ included) so that it runs on a bare x86-64 machine:
//   bench_threads [--n N] [--threads 1,2,4,8,16] [--runs 3] [--dist jittered,uniform]
// For each input (the generators of bench_triangulation, tools/bench/bench_inputs.h)
// and each thread count, runs runVtsPipeline (grid, hull, triangulation; no output
// check) and the same followed by reconstructSurface with pcd_to_mesh's defaults (trim
// and fill, output checks on), RUNS times each, and keeps the minimum wall clock.
// Prints a markdown table: wall time, speed-up over the first thread count, and a hash
// of the output mesh (triangles, twins, vertices); exits with 3 when an output differs
// between thread counts (the pipeline promises the same output for every count).
#include "bench_inputs.h"

#include <pcl_vts/core/reconstruct_surface.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace pcl_vts;

std::vector<std::string> splitList(const std::string& text)
{
  std::vector<std::string> items;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    if (comma > start)
      items.push_back(text.substr(start, comma - start));
    start = comma + 1;
  }
  return items;
}

bool parseCount(const std::string& text, double& value)
{
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && value >= 1.0 && value <= 4e9;
}

int usage()
{
  std::fprintf(stderr, "usage: bench_threads [--n N] [--threads 1,2,4,8,16] [--runs 3] "
                       "[--dist jittered,uniform]\n");
  return 2;
}

struct Run {
  double seconds = 0.0;
  std::uint64_t hash = 0;
  std::size_t triangles = 0;
};

/// One run: the pipeline, then (post = true) trim and fill as pcd_to_mesh runs them.
bool runOnce(const std::vector<double>& xyz, unsigned threads, bool post, Run& run)
{
  VtsOptions options;
  options.threads = threads;
  options.check_output = false;
  VtsResult result;
  const auto start = std::chrono::steady_clock::now();
  Status status = runVtsPipeline(xyz.data(), xyz.size() / 3, options, result);
  if (status.ok() && post) {
    ReconstructionDiagnostics diagnostics;
    ReconstructionOptions passes; // pcd_to_mesh's defaults, on the pipeline's threads
    passes.threads = threads;
    status = reconstructSurface(result.mesh, passes, diagnostics);
  }
  run.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!status.ok()) {
    std::fprintf(stderr, "bench_threads: %s\n", status.toString().c_str());
    return false;
  }
  run.hash = bench::meshHash(result.mesh);
  run.triangles = result.mesh.triangleCount();
  return true;
}

} // namespace

int main(int argc, char** argv)
{
  double n = 1e7;
  std::vector<unsigned> thread_counts{1, 2, 4, 8, 16};
  int runs = 3;
  std::vector<std::string> dists{"jittered", "uniform"};
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--help" || arg == "-h") {
      usage();
      return 0;
    }
    if (k + 1 >= argc)
      return usage();
    const std::string value = argv[++k];
    double number = 0.0;
    if (arg == "--n" && parseCount(value, number)) {
      n = number;
    } else if (arg == "--runs" && parseCount(value, number) && number <= 100) {
      runs = static_cast<int>(number);
    } else if (arg == "--threads") {
      thread_counts.clear();
      for (const std::string& item : splitList(value)) {
        if (!parseCount(item, number) || number > 1024)
          return usage();
        thread_counts.push_back(static_cast<unsigned>(number));
      }
      if (thread_counts.empty())
        return usage();
    } else if (arg == "--dist") {
      dists = splitList(value);
      for (const std::string& dist : dists)
        if (dist != "jittered" && dist != "uniform" && dist != "clustered" &&
            dist != "grid" && dist != "raster") {
          std::fprintf(stderr, "bench_threads: unknown distribution '%s'\n",
                       dist.c_str());
          return 2;
        }
      if (dists.empty())
        return usage();
    } else {
      return usage();
    }
  }
  std::printf("bench_threads: %u hardware threads, n = %.0f, minimum of %d runs, wall "
              "clock; speed-up over %u thread(s)\n\n",
              std::thread::hardware_concurrency(), n, runs, thread_counts.front());
  std::printf(
      "| input | n | pipeline | threads | wall s | speed-up | triangles | output "
      "hash | same as %u thread(s) |\n",
      thread_counts.front());
  std::printf("| --- | ---: | --- | ---: | ---: | ---: | ---: | --- | --- |\n");
  std::fflush(stdout);
  bool all_same = true;
  for (const std::string& dist : dists) {
    const std::vector<double> xyz =
        bench::generate(dist, static_cast<std::size_t>(n), 1u);
    for (const bool post : {false, true}) {
      Run first;
      for (std::size_t t = 0; t < thread_counts.size(); ++t) {
        Run best;
        best.seconds = 1e300;
        for (int r = 0; r < runs; ++r) {
          Run run;
          if (!runOnce(xyz, thread_counts[t], post, run))
            return 1;
          if (r > 0 && (run.hash != best.hash || run.triangles != best.triangles)) {
            std::fprintf(stderr, "bench_threads: two runs on %u threads differ\n",
                         thread_counts[t]);
            all_same = false;
          }
          if (run.seconds < best.seconds)
            best = run;
        }
        if (t == 0)
          first = best;
        const bool same = best.hash == first.hash && best.triangles == first.triangles;
        all_same = all_same && same;
        std::printf("| %s | %zu | %s | %u | %.3f | %.2fx | %zu | %016llx | %s |\n",
                    dist.c_str(), xyz.size() / 3,
                    post ? "triangulation + trim + fill" : "triangulation",
                    thread_counts[t], best.seconds, first.seconds / best.seconds,
                    best.triangles, static_cast<unsigned long long>(best.hash),
                    same ? "yes" : "**NO**");
        std::fflush(stdout);
      }
    }
  }
  if (!all_same) {
    std::fprintf(stderr, "bench_threads: the output differs between thread counts\n");
    return 3;
  }
  return 0;
}
