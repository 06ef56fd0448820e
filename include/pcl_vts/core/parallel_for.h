// The one way pcl_vts runs work on several threads: a team of workers, worker 0 on
// the calling thread, joined before returning. Two loops are built on it: contiguous
// chunks with the worker's number (for per-thread sums, compare_methods' metrics) and
// one call per index (core stages whose iterations write distinct slots, so the
// result is the same for any thread count). Header-only: no symbol to export.
#pragma once

#include <algorithm>
#include <cstddef>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace pcl_vts {

/// Threads meaning "all cores": the hardware's concurrency, at least 1.
inline unsigned allCores()
{
  return std::max(1u, std::thread::hardware_concurrency());
}

namespace detail {

/// runTeam with the thread start given: start(w, task) returns a started
/// std::thread or throws std::system_error (tests inject a failing one).
template <typename Work, typename Start>
void runTeamWith(unsigned workers, const Work& work, const Start& start)
{
  std::vector<std::thread> team;
  unsigned started = 1;
  try {
    for (; started < workers; ++started) {
      const unsigned w = started;
      team.push_back(start(w, [&work, w] { work(w); }));
    }
  } catch (const std::system_error&) {
    // No thread left to start (a process or memory limit): the workers that did not
    // start run on the calling thread below. Every caller's workers are independent
    // (they take tasks from counters or own a chunk), so only the time changes.
  }
  work(0u);
  for (unsigned w = started; w < workers; ++w)
    work(w);
  for (std::thread& t : team)
    t.join();
}

} // namespace detail

/// Runs work(w) for w = 0 .. workers - 1, each on its own thread (worker 0 on the
/// calling one), and returns when all are done. workers 0 counts as 1. A worker whose
/// thread cannot start runs on the calling thread after worker 0, so work(w) must not
/// wait for another worker.
template <typename Work>
void runTeam(unsigned workers, const Work& work)
{
  detail::runTeamWith(workers, work, [](unsigned, auto&& task) {
    return std::thread(std::forward<decltype(task)>(task));
  });
}

/// Splits [0, n) into one contiguous chunk per thread, at most `threads` (0 counts
/// as 1) and at most n: chunk(begin, end, thread) with chunks of ceil(n / count)
/// indices in thread order; chunk must write only its range or its thread's slot.
template <typename Chunk>
void parallelChunks(unsigned threads, std::size_t n, const Chunk& chunk)
{
  const auto count = static_cast<unsigned>(std::max<std::size_t>(
      1, std::min<std::size_t>(threads, std::max<std::size_t>(1, n))));
  if (count == 1) {
    chunk(std::size_t{0}, n, 0u);
    return;
  }
  const std::size_t size = (n + count - 1) / count;
  runTeam(count, [&](unsigned t) {
    const std::size_t begin = std::min(n, t * size), end = std::min(n, begin + size);
    chunk(begin, end, t);
  });
}

/// The threads worth running on n indices: at most `threads` (0 counts as 1), each
/// with 65536 indices or more (below that, threads cost more than they save), and
/// at least one.
inline unsigned usefulThreads(unsigned threads, std::size_t n)
{
  constexpr std::size_t MIN_PER_THREAD = std::size_t{1} << 16;
  return static_cast<unsigned>(std::min<std::size_t>(
      std::max(1u, threads), std::max<std::size_t>(1, n / MIN_PER_THREAD)));
}

/// chunk(begin, end) over contiguous ranges covering [0, n), each by one thread;
/// ranges too small to pay for threads (usefulThreads) stay on the calling thread.
/// For loops that reuse a buffer across a range's indices.
template <typename Chunk>
void parallelRanges(unsigned threads, std::size_t n, const Chunk& chunk)
{
  parallelChunks(
      usefulThreads(threads, n), n,
      [&](std::size_t begin, std::size_t end, unsigned) { chunk(begin, end); });
}

/// body(k) for every k in [0, n), each index by exactly one thread, split as
/// parallelRanges splits.
template <typename Body>
void parallelFor(unsigned threads, std::size_t n, const Body& body)
{
  parallelRanges(threads, n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
      body(k);
  });
}

} // namespace pcl_vts
