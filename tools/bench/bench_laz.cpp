// bench_laz: the LAZ decode rate against reading the same points from uncompressed
// LAS, in the same run. Each LAZ file is paired with its LAS twin; every reading is
// repeated and the best time kept (the files are in the page cache after the first).
// Usage: bench_laz [--repeat N] LAZ=LAS ...   prints a Markdown table row per pair.
#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/stopwatch.h>
#include <pcl_vts/io/las_reader.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

namespace {

/// Best wall time of `repeat` whole reads, in seconds; negative on a read error.
double bestRead(const std::string& path, unsigned threads, int repeat,
                std::uint64_t& points)
{
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeat; ++r) {
    pcl_vts::LasReadOptions options;
    options.threads = threads;
    std::vector<double> xyz;
    pcl_vts::LasInfo info;
    pcl_vts::Stopwatch clock;
    const pcl_vts::Status s = pcl_vts::readLasCloud(path, options, xyz, info);
    const double seconds = clock.seconds();
    if (!s.ok()) {
      std::fprintf(stderr, "bench_laz: %s\n", s.message.c_str());
      return -1.0;
    }
    points = info.points_read;
    best = std::min(best, seconds);
  }
  return best;
}

} // namespace

int main(int argc, char** argv)
{
  int repeat = 5;
  std::vector<std::string> pairs;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--repeat" && i + 1 < argc)
      repeat = std::max(1, std::atoi(argv[++i]));
    else
      pairs.push_back(a);
  }
  if (pairs.empty()) {
    std::fprintf(stderr, "usage: bench_laz [--repeat N] LAZ=LAS ...\n");
    return 1;
  }
  const unsigned cores = pcl_vts::allCores();
  std::printf(
      "| file | points | LAS read (Mpt/s) | LAZ 1 thread (Mpt/s) | LAZ %u threads "
      "(Mpt/s) | LAZ / LAS time, 1 thread | speed-up "
      "|\n|---|---|---|---|---|---|---|\n",
      cores);
  for (const std::string& pair : pairs) {
    const std::size_t eq = pair.find('=');
    if (eq == std::string::npos) {
      std::fprintf(stderr, "bench_laz: '%s' is not LAZ=LAS\n", pair.c_str());
      return 1;
    }
    const std::string laz = pair.substr(0, eq), las = pair.substr(eq + 1);
    std::uint64_t n = 0, n_las = 0;
    const double t_las = bestRead(las, 1, repeat, n_las);
    const double t1 = bestRead(laz, 1, repeat, n);
    const double tn = bestRead(laz, cores, repeat, n);
    if (t_las < 0 || t1 < 0 || tn < 0 || n != n_las)
      return 2;
    const double mpt = static_cast<double>(n) / 1e6;
    std::printf("| %s | %llu | %.1f | %.1f | %.1f | %.1fx | %.2fx |\n",
                laz.substr(laz.find_last_of('/') + 1).c_str(),
                static_cast<unsigned long long>(n), mpt / t_las, mpt / t1, mpt / tn,
                t1 / t_las, t1 / tn);
  }
  return 0;
}
