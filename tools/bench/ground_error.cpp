// ground_error: Type I, Type II and total error of pcd_to_mesh's --ground pmf on the
// ISPRS filter-test samples (each sampNN-utm.pcd beside its reference
// sampNN-utm-ground.pcd), as Sithole & Vosselman (2004) define them:
//   Type I  = bare-earth points rejected / reference bare-earth points
//   Type II = object points accepted / reference object points
//   total   = misclassified points / all points
// Usage: ground_error DIR [--pmf-cell C --pmf-window W --pmf-slope S --pmf-initial D0
//        --pmf-max DMAX --pmf-base B]; prints a Markdown table row per sample.
#include "cli_words.h"
#include "command_line.h"

#include <pcl_vts/io/point_cloud_loader.h>
#include <pcl_vts/preprocess_cloud.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace {

using Key = std::array<double, 3>;

bool load(const std::string& path, std::vector<double>& xyz)
{
  pcl_vts::CloudDescription d;
  const pcl_vts::Status s = pcl_vts::loadPointCloud(path, {}, xyz, d);
  if (!s.ok())
    std::fprintf(stderr, "ground_error: %s\n", s.toString().c_str());
  return s.ok();
}

std::map<Key, long> counts(const std::vector<double>& xyz)
{
  std::map<Key, long> m;
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
    ++m[{xyz[i], xyz[i + 1], xyz[i + 2]}];
  return m;
}

} // namespace

int main(int argc, char** argv)
{
  pcl_vts::PreprocessOptions options;
  options.ground_pmf = true;
  // The knob into its field; the combination is validatePreprocessOptions' to judge.
  const auto knob = [](const char* name, double& field) {
    return [name, &field](const std::string& value, std::string& error) {
      if (pcl_vts::tools::parseFiniteNumber(value, field))
        return true;
      error = std::string("--") + name + ": '" + value + "' is not a number";
      return false;
    };
  };
  double window = options.pmf_max_window;
  bool help = false;
  pcl_vts::tools::CommandLine cli;
  cli.group("ground_error DIR [options]: the filter's errors on DIR's ISPRS samples")
      .value("pmf-cell", "C", "grid cell edge", knob("pmf-cell", options.pmf_cell))
      .value("pmf-window", "W", "largest window, cells", knob("pmf-window", window))
      .value("pmf-slope", "S", "terrain slope", knob("pmf-slope", options.pmf_slope))
      .value("pmf-initial", "D0", "first height threshold",
             knob("pmf-initial", options.pmf_initial_distance))
      .value("pmf-max", "DMAX", "height threshold cap",
             knob("pmf-max", options.pmf_max_distance))
      .value("pmf-base", "B", "window growth base", knob("pmf-base", options.pmf_base))
      .flag("help,h", "this help", [&help] { help = true; });
  std::vector<std::string> positional;
  std::string error;
  if (!cli.parse(argc, argv, positional, error) || (!help && positional.size() != 1)) {
    std::fprintf(stderr, "ground_error: %s\n%s",
                 error.empty() ? "one folder expected" : error.c_str(),
                 cli.help().c_str());
    return 1;
  }
  if (help) {
    std::printf("%s", cli.help().c_str());
    return 0;
  }
  if (window != std::floor(window) || window < 1.0 || window > 4096.0) {
    std::fprintf(stderr, "ground_error: --pmf-window: %g is not a whole 1..4096\n",
                 window);
    return 1;
  }
  options.pmf_max_window = static_cast<int>(window);
  if (pcl_vts::Status s = pcl_vts::validatePreprocessOptions(options); !s.ok()) {
    std::fprintf(stderr, "ground_error: %s\n", s.message.c_str());
    return 1;
  }
  std::vector<std::string> samples;
  std::error_code failed;
  for (std::filesystem::directory_iterator it(positional[0], failed), end;
       !failed && it != end; it.increment(failed)) {
    const std::string name = it->path().filename().string();
    if (name.rfind("samp", 0) == 0 && name.size() > 8 &&
        name.substr(name.size() - 8) == "-utm.pcd")
      samples.push_back(it->path().string());
  }
  if (failed) {
    std::fprintf(stderr, "ground_error: cannot list '%s': %s\n", positional[0].c_str(),
                 failed.message().c_str());
    return 2;
  }
  std::sort(samples.begin(), samples.end());
  std::printf(
      "| sample | points | ground (ref) | Type I %% | Type II %% | total %% | ms |\n"
      "|---|---:|---:|---:|---:|---:|---:|\n");
  double sum1 = 0, sum2 = 0, sumt = 0;
  for (const std::string& path : samples) {
    std::vector<double> all, ref;
    const std::string ref_path = path.substr(0, path.size() - 4) + "-ground.pcd";
    if (!load(path, all) || !load(ref_path, ref))
      return 2;
    std::vector<double> kept = all;
    std::vector<pcl_vts::PreprocessStep> steps;
    const auto t0 = std::chrono::steady_clock::now();
    if (pcl_vts::Status s = pcl_vts::preprocessCloud(kept, options, steps); !s.ok()) {
      std::fprintf(stderr, "ground_error: %s: %s\n", path.c_str(),
                   s.toString().c_str());
      return 3;
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
            .count();
    std::map<Key, long> is_ground = counts(ref), accepted = counts(kept);
    // Each point: reference ground while the reference has copies of it left.
    long a = 0, b = 0, c = 0, d = 0;
    for (std::size_t i = 0; i + 2 < all.size(); i += 3) {
      const Key k{all[i], all[i + 1], all[i + 2]};
      long& g = is_ground[k];
      long& acc = accepted[k];
      const bool ground = g > 0, kept_it = acc > 0;
      g -= ground;
      acc -= kept_it;
      (ground ? (kept_it ? a : b) : (kept_it ? c : d)) += 1;
    }
    const double n = static_cast<double>(a + b + c + d);
    const double t1 = 100.0 * b / std::max<long>(1, a + b);
    const double t2 = 100.0 * c / std::max<long>(1, c + d);
    const double tt = 100.0 * (b + c) / n;
    sum1 += t1;
    sum2 += t2;
    sumt += tt;
    const std::string name = std::filesystem::path(path).stem().string();
    std::printf("| %s | %.0f | %ld | %.2f | %.2f | %.2f | %.0f |\n",
                name.substr(0, name.size() - 4).c_str(), n, a + b, t1, t2, tt, ms);
  }
  const double m = static_cast<double>(std::max<std::size_t>(1, samples.size()));
  std::printf("| mean | | | %.2f | %.2f | %.2f | |\n", sum1 / m, sum2 / m, sumt / m);
  return 0;
}
