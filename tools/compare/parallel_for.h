// Splits [0, n) into one contiguous chunk per thread; fn(begin, end, thread) must only
// write to its own chunk or its own thread slot. The metrics are the only parallel
// part of compare_methods (methods themselves run single-threaded, one at a time).
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace pcl_vts {
namespace compare {

/// Threads the metrics use: hardware concurrency, at least 1.
inline unsigned metricThreads()
{
  return std::max(1u, std::thread::hardware_concurrency());
}

template <class Fn>
void parallelFor(std::size_t n, unsigned threads, Fn fn)
{
  threads = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(
                                                         std::max<std::size_t>(1, n))));
  if (threads == 1) {
    fn(std::size_t{0}, n, 0u);
    return;
  }
  std::vector<std::thread> pool;
  const std::size_t chunk = (n + threads - 1) / threads;
  for (unsigned t = 0; t < threads; ++t) {
    const std::size_t begin = std::min(n, t * chunk), end = std::min(n, begin + chunk);
    pool.emplace_back([=] { fn(begin, end, t); });
  }
  for (std::thread& thread : pool)
    thread.join();
}

} // namespace compare
} // namespace pcl_vts
