// runTeam and the loops built on it: every worker runs exactly once, and a worker
// whose thread cannot start (a process or memory limit) runs on the calling thread
// instead of leaving the started ones unjoined (std::terminate).
#include <pcl_vts/core/parallel_for.h>

#include <gtest/gtest.h>

#include <atomic>
#include <system_error>
#include <thread>
#include <vector>

namespace {

using pcl_vts::detail::runTeamWith;

TEST(ParallelFor, TeamRunsEveryWorkerOnce)
{
  for (unsigned workers : {0u, 1u, 2u, 5u}) {
    std::vector<std::atomic<int>> runs(std::max(1u, workers));
    pcl_vts::runTeam(workers, [&](unsigned w) { ++runs[w]; });
    for (const auto& r : runs)
      EXPECT_EQ(r.load(), 1) << workers << " workers";
  }
}

TEST(ParallelFor, WorkersThatCannotStartRunOnTheCallingThread)
{
  for (unsigned fail_from : {1u, 2u, 4u}) {
    const unsigned workers = 6;
    std::vector<std::atomic<int>> runs(workers);
    std::atomic<unsigned> on_caller{0};
    const std::thread::id caller = std::this_thread::get_id();
    runTeamWith(
        workers,
        [&](unsigned w) {
          ++runs[w];
          if (std::this_thread::get_id() == caller)
            ++on_caller;
        },
        [&](unsigned w, auto&& task) {
          if (w >= fail_from)
            throw std::system_error(
                std::make_error_code(std::errc::resource_unavailable_try_again));
          return std::thread(std::forward<decltype(task)>(task));
        });
    for (unsigned w = 0; w < workers; ++w)
      EXPECT_EQ(runs[w].load(), 1)
          << "worker " << w << ", threads fail from " << fail_from;
    // Worker 0 and the ones that could not start.
    EXPECT_EQ(on_caller.load(), 1 + workers - fail_from);
  }
}

TEST(ParallelFor, RangesCoverEveryIndexOnce)
{
  const std::size_t n = 300000;
  for (unsigned threads : {1u, 2u, 3u, 8u}) {
    std::vector<std::atomic<int>> seen(n);
    pcl_vts::parallelFor(threads, n, [&](std::size_t k) { ++seen[k]; });
    std::size_t once = 0;
    for (const auto& s : seen)
      once += s.load() == 1 ? 1 : 0;
    EXPECT_EQ(once, n) << threads << " threads";
  }
}

} // namespace
