// Splits an index range into one contiguous chunk per thread. Each index is handled
// by exactly one thread, so loops whose iterations write distinct slots give the same
// result for any thread count. Small ranges stay on the calling thread.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace pcl_vts {
namespace detail {

template <typename Body>
void parallelFor(unsigned threads, std::size_t n, const Body& body)
{
  constexpr std::size_t MIN_PER_THREAD = 1u << 16; // below this, threads cost more
  const std::size_t useful = std::max<std::size_t>(1, n / MIN_PER_THREAD);
  const auto count = static_cast<unsigned>(std::min<std::size_t>(threads, useful));
  if (count <= 1) {
    for (std::size_t k = 0; k < n; ++k)
      body(k);
    return;
  }
  const auto run = [&](unsigned t) {
    const std::size_t first = n * t / count, last = n * (t + 1) / count;
    for (std::size_t k = first; k < last; ++k)
      body(k);
  };
  std::vector<std::thread> team;
  for (unsigned t = 1; t < count; ++t)
    team.emplace_back(run, t);
  run(0);
  for (std::thread& t : team)
    t.join();
}

} // namespace detail
} // namespace pcl_vts
