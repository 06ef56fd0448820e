// What the post-passes over tile results share (tiled_trim.h, tiled_fill.h): files of
// fixed-size records indexed by global vertex id, triangle lists on disk, and a sweep
// over the tiles on worker threads.
#pragma once
#include "job_agreement.h"
#include "tile_results.h"

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/tiling/job_comm.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace pcl_vts {

/// "cannot <what> '<path>': <reason>", with a hint when the temporary folder is full.
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
  Status create();         ///< empty, for writing and reading
  Status open();           ///< as written by an earlier sweep, for reading
  Status openForWriting(); ///< made by another rank, to write and read
  Status write(std::uint64_t first, const std::vector<double>& values) const;
  Status read(std::uint64_t first, std::size_t count, double* out) const;

 private:
  template <typename Byte>
  Status transfer(std::uint64_t first, Byte* bytes, std::size_t size) const;

  std::string path_;
  std::size_t bytes_;
  int fd_ = -1;
};

/// Appends 32-bit words (triangles: 3 ids each) to a file.
Status appendWords(const std::string& path, const std::vector<std::uint32_t>& ids);

/// Appends the words of a file (none when it does not exist) to ids, which must then
/// hold whole items of `unit` words.
Status readWords(const std::string& path, std::vector<std::uint32_t>& ids,
                 std::size_t unit);

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

/// Where the sweeps of a pass run: every rank of the job, `workers` threads each.
struct SweepTeam {
  JobComm& comm;
  unsigned workers;
  SweepProgress& progress;

  /// Collective: visit(k) for every k in [0, tiles), each once, on whichever rank's
  /// worker takes it from the job-wide counter (so what a visit leaves for later
  /// goes to files); the first failure stops this rank's workers, and every rank
  /// returns the same status.
  template <typename Visit>
  Status forEachTile(std::size_t tiles, const Visit& visit) const
  {
    comm.startTasks();
    std::mutex mutex;
    Status failure;
    const auto work = [&]() {
      for (;;) {
        {
          const std::lock_guard<std::mutex> lock(mutex);
          if (!failure.ok())
            return;
        }
        const std::uint64_t k = comm.nextTask();
        if (k >= tiles)
          return;
        Status s = visit(static_cast<std::size_t>(k));
        if (s.ok()) {
          progress.tileDone();
          continue;
        }
        const std::lock_guard<std::mutex> lock(mutex);
        if (failure.ok())
          failure = s;
        return;
      }
    };
    runTeam(static_cast<unsigned>(
                std::max<std::size_t>(1, std::min<std::size_t>(workers, tiles))),
            [&](unsigned) { work(); });
    return agree(comm, failure);
  }
};

/// Writes a tile's findings (fixed-size items) for rank 0 to read after the sweep;
/// nothing when there are none.
template <typename Item>
Status writeFindings(const std::string& path, const std::vector<Item>& items)
{
  if (items.empty())
    return Status::success();
  std::vector<std::uint32_t> words(items.size() * sizeof(Item) / sizeof(std::uint32_t));
  std::memcpy(words.data(), items.data(), items.size() * sizeof(Item));
  return appendWords(path, words);
}

/// Reads a tile's findings back into items, replacing what it held (none when the
/// file does not exist).
template <typename Item>
Status readFindings(const std::string& path, std::vector<Item>& items)
{
  std::vector<std::uint32_t> words;
  if (Status s = readWords(path, words, sizeof(Item) / sizeof(std::uint32_t)); !s.ok())
    return s;
  items.resize(words.size() * sizeof(std::uint32_t) / sizeof(Item));
  std::memcpy(items.data(), words.data(), items.size() * sizeof(Item));
  return Status::success();
}

/// The local id of global id `id` in `ids` (sorted): its rank there.
inline VertexId localIdOf(const std::vector<std::uint32_t>& ids, std::uint32_t id)
{
  return static_cast<VertexId>(std::lower_bound(ids.begin(), ids.end(), id) -
                               ids.begin());
}

/// A part of the tiled mesh in memory: `triangles` (global ids) over the vertices
/// `ids` (sorted global ids, each at its localIdOf), positions read back. Halfedges
/// are left to the caller.
Status loadPart(const VertexRecords& positions, const std::vector<std::uint32_t>& ids,
                const std::vector<TriangleKey>& triangles, TriangleMesh& part);

/// Sends ids from rank 0 to every rank (collective).
void broadcastIds(JobComm& comm, std::vector<std::uint32_t>& ids);

} // namespace pcl_vts
