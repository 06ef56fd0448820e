// What the post-passes over tile results share (tiled_trim.h, tiled_fill.h): files of
// fixed-size records indexed by global vertex id, triangle lists on disk, and a sweep
// over the tiles on worker threads.
#pragma once
#include <pcl_vts/core/status.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace pcl_vts {

/// "cannot <what> '<path>': <reason>", with the --temp-dir hint when the disk is full.
Status sweepIoFailure(const char* what, const std::string& path, int err);

/// Fixed-size records of doubles indexed by global vertex id, in one scratch file:
/// each tile writes its range; neighbours in other tiles are read back one by one.
class VertexRecords {
 public:
  VertexRecords(std::string path, std::size_t doubles)
      : path_(std::move(path))
      , bytes_(doubles * sizeof(double))
  {}
  VertexRecords(const VertexRecords&) = delete;
  VertexRecords& operator=(const VertexRecords&) = delete;
  ~VertexRecords();
  Status create(); ///< empty, for writing and reading
  Status open();   ///< as written by an earlier sweep, for reading
  Status write(std::uint64_t first, const std::vector<double>& values) const;
  Status read(std::uint64_t first, std::size_t count, double* out) const;

 private:
  template <typename Byte>
  Status transfer(std::uint64_t first, Byte* bytes, std::size_t size) const;

  std::string path_;
  std::size_t bytes_;
  int fd_ = -1;
};

/// Appends triangles (3 ids each) to a file.
Status appendTriangles(const std::string& path, const std::vector<std::uint32_t>& ids);

/// Appends the triangles of a file (none when it does not exist) to ids.
Status readTriangles(const std::string& path, std::vector<std::uint32_t>& ids);

/// The tiles visited by a pass, over all its sweeps, for the progress line.
class SweepProgress {
 public:
  using Report = std::function<void(std::uint64_t done, std::uint64_t total)>;
  SweepProgress(Report report, std::uint64_t total)
      : report_(std::move(report))
      , total_(total)
  {}
  /// One more tile done (any thread).
  void tileDone()
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    ++done_;
    if (report_)
      report_(done_, total_);
  }

 private:
  Report report_;
  std::uint64_t total_, done_ = 0;
  std::mutex mutex_;
};

/// Runs visit(k) for k in [0, tiles) on `workers` threads; the first failure wins and
/// stops the others at their next tile. Each tile done is told to `progress`.
template <typename Visit>
Status forEachTile(std::size_t tiles, unsigned workers, SweepProgress& progress,
                   const Visit& visit)
{
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  Status failure;
  const auto work = [&]() {
    for (std::size_t k; (k = next++) < tiles;) {
      Status s = visit(k);
      if (s.ok()) {
        progress.tileDone();
        continue;
      }
      const std::lock_guard<std::mutex> lock(mutex);
      if (failure.ok())
        failure = s;
      next = tiles;
    }
  };
  std::vector<std::thread> pool;
  for (unsigned w = 1; w < std::min<std::size_t>(workers, tiles); ++w)
    pool.emplace_back(work);
  work();
  for (std::thread& thread : pool)
    thread.join();
  return failure;
}

} // namespace pcl_vts
