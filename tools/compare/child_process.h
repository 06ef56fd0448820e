// Runs one method in its own process, so that its peak memory is its own (ru_maxrss of
// the child from wait4) and a method that runs too long or crashes becomes a row with
// a reason instead of taking compare_methods down. POSIX only.
#pragma once

#include <string>
#include <vector>

namespace pcl_vts {
namespace compare {

struct ChildOutcome {
  bool finished = false;     ///< exited normally with status 0
  bool timed_out = false;    ///< killed (SIGKILL to its process group) at the limit
  int exit_code = -1;        ///< exit status when it exited, else -1
  int signal = 0;            ///< terminating signal, else 0
  double wall_seconds = 0.0; ///< fork to reap
  long peak_rss_kib = 0;     ///< ru_maxrss of the child
  /// Empty when finished, else one line: "timed out after 300 s", "killed by
  /// signal 11 (Segmentation fault)", "exit status 3", "cannot start: ...".
  std::string failure;
};

/// Starts argv[0] with argv (no shell, OMP_NUM_THREADS=1), stdout and stderr appended
/// to log_path, waits at most time_limit_seconds (> 0), then kills it.
ChildOutcome runChild(const std::vector<std::string>& argv, double time_limit_seconds,
                      const std::string& log_path);

/// Path of the running executable (/proc/self/exe), for re-executing ourselves.
std::string selfExecutablePath();

} // namespace compare
} // namespace pcl_vts
