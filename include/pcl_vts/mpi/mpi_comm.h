// The tiled job's collectives over MPI (job_comm.h): one rank per process, every
// rank runs runTiledMesh with the same arguments and a temporary folder on a file
// system they all share. MPI types stay out of this header.
#pragma once
#include <pcl_vts/mpi/export.h>
#include <pcl_vts/tiling/job_comm.h>

#include <mutex>

namespace pcl_vts {

class PCL_VTS_MPI_EXPORT MpiComm : public JobComm {
 public:
  /// Over MPI_COMM_WORLD; MPI must be initialised (MpiSession) and stay so.
  /// Collective (it creates the window of the task counter on rank 0).
  MpiComm();
  /// Collective (frees the window).
  ~MpiComm() override;
  MpiComm(const MpiComm&) = delete;
  MpiComm& operator=(const MpiComm&) = delete;
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void sum(std::vector<std::uint64_t>& values) override;
  void min(std::vector<double>& values) override;
  void max(std::vector<double>& values) override;
  void broadcast(std::string& bytes, int root) override;
  void barrier() override;
  void startTasks() override;
  /// MPI_Fetch_and_op on rank 0's counter (passive target), one call at a time.
  std::uint64_t nextTask() override;

 private:
  int rank_ = 0;
  int size_ = 1;
  void* window_ = nullptr;           ///< MPI_Win, kept opaque here
  std::uint64_t* counter_ = nullptr; ///< rank 0's counter (the window's memory)
  std::mutex mutex_;                 ///< worker threads take turns in MPI
};

/// MPI_Init_thread (serialized calls: the tiled job's worker threads take turns) /
/// MPI_Finalize as a scope (the tool's main holds one).
class PCL_VTS_MPI_EXPORT MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  /// False when MPI cannot give serialized thread support (then run nothing).
  bool threadsSupported() const { return threads_supported_; }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

 private:
  bool threads_supported_ = false;
};

} // namespace pcl_vts
