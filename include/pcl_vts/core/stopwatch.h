// The one clock pcl_vts times its stages with (the diagnostics' seconds_*, the
// preprocessing milliseconds, compare_methods' and the benchmarks' timings): steady,
// so that a clock change never yields a negative time. Header-only.
#pragma once

#include <chrono>

namespace pcl_vts {

/// Time since construction or the last restart().
class Stopwatch {
 public:
  void restart() { start_ = Clock::now(); }
  double seconds() const
  {
    return std::chrono::duration<double>(Clock::now() - start_).count();
  }
  double milliseconds() const { return 1e3 * seconds(); }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_ = Clock::now();
};

} // namespace pcl_vts
