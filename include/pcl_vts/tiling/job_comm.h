// What the tiled job needs from its peers: the few collectives that make every rank
// agree on the frame, the block index and success. One process is LocalComm; MPI
// ranks are pcl_vts::mpi's MpiComm. The tiles themselves never talk: the one rule
// (known_space.h) lets any rank mesh any tile from the shared temporary files.
#pragma once
#include <pcl_vts/tiling/export.h>

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {

class PCL_VTS_TILING_EXPORT JobComm {
 public:
  virtual ~JobComm() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// Element-wise sum / min / max over all ranks, in place.
  virtual void sum(std::vector<std::uint64_t>& values) = 0;
  virtual void min(std::vector<double>& values) = 0;
  virtual void max(std::vector<double>& values) = 0;
  /// Root's bytes to every rank.
  virtual void broadcast(std::string& bytes, int root) = 0;
  virtual void barrier() = 0;
  /// Collective: the shared task counter starts again from 0.
  virtual void startTasks() = 0;
  /// The next value of a counter shared by every rank and thread (0, 1, 2, ...):
  /// tiles go to whoever asks next, so a rank that finishes early takes more.
  /// Thread-safe.
  virtual std::uint64_t nextTask() = 0;
};

/// A job of one process: every collective is the identity.
class PCL_VTS_TILING_EXPORT LocalComm : public JobComm {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void sum(std::vector<std::uint64_t>&) override {}
  void min(std::vector<double>&) override {}
  void max(std::vector<double>&) override {}
  void broadcast(std::string&, int) override {}
  void barrier() override {}
  void startTasks() override { next_ = 0; }
  std::uint64_t nextTask() override { return next_.fetch_add(1); }

 private:
  std::atomic<std::uint64_t> next_{0};
};

} // namespace pcl_vts
