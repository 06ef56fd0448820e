// Command line of compare_methods: the options of a comparison and the internal ones
// of a method process (--run-method), validated strictly (a typo or a value out of
// range is a usage error naming the option, never a silent default).
#pragma once

#include "methods.h"

#include <pcl_vts/io/point_cloud_loader.h>

#include <cstddef>
#include <string>
#include <vector>

namespace pcl_vts {
namespace compare {

constexpr double DEFAULT_TIME_LIMIT = 300.0;
constexpr double DEFAULT_SAMPLES_PER_TRIANGLE = 10.0;
constexpr double DEFAULT_POISSON_TRIM = 4.0;
constexpr int DEFAULT_PICTURE_WIDTH = 400;

struct CompareOptions {
  std::string input;
  std::size_t synthetic = 0;
  pcl_vts::CloudLoadOptions load;
  std::string name, title;
  std::vector<std::string> methods = allMethodNames();
  double time_limit = DEFAULT_TIME_LIMIT;
  int poisson_depth = 0;
  double poisson_trim = DEFAULT_POISSON_TRIM;
  double samples_per_triangle = DEFAULT_SAMPLES_PER_TRIANGLE;
  std::size_t max_samples = 0;
  unsigned threads = 0;
  std::string report, tsv, pictures, picture_link;
  int picture_width = DEFAULT_PICTURE_WIDTH;
  std::string work_dir;
  bool keep_work = false;
  bool help = false;
  // Method-process mode (--run-method), set by the parent only.
  std::string run_method, points_file, mesh_file, report_file;
  MethodParameters parameters;
};

/// --help text (every option with its default, the exit codes).
void printCompareHelp();

/// Parses argv into opt; false with a one-line reason in error.
bool parseCompareArgs(int argc, char** argv, CompareOptions& opt, std::string& error);

} // namespace compare
} // namespace pcl_vts
