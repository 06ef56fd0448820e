// The tiled job's collectives over MPI (job_comm.h): one rank per process, every
// rank runs runTiledMesh with the same arguments and a temporary folder on a file
// system they all share. MPI types stay out of this header.
#pragma once
#include <pcl_vts/mpi/export.h>
#include <pcl_vts/tiling/job_comm.h>

namespace pcl_vts {

class PCL_VTS_MPI_EXPORT MpiComm : public JobComm {
 public:
  /// Over MPI_COMM_WORLD; MPI must be initialised (MPI_Init) and stay so.
  MpiComm();
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void sum(std::vector<std::uint64_t>& values) override;
  void min(std::vector<double>& values) override;
  void max(std::vector<double>& values) override;
  void broadcast(std::string& bytes, int root) override;
  void barrier() override;

 private:
  int rank_ = 0;
  int size_ = 1;
};

/// MPI_Init / MPI_Finalize as a scope (the tool's main holds one).
class PCL_VTS_MPI_EXPORT MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

} // namespace pcl_vts
