// MPI collectives for the tiled job (mpi_comm.h). Vectors go in slices of at most
// 2^30 elements: MPI counts are int.
#include <pcl_vts/mpi/mpi_comm.h>

#define OMPI_SKIP_MPICXX 1 // the C API only: no deprecated C++ bindings
#include <algorithm>
#include <cstdint>
#include <mpi.h>

namespace pcl_vts {
namespace {

constexpr std::size_t SLICE = std::size_t{1} << 30;

template <typename T>
void allreduce(std::vector<T>& values, MPI_Datatype type, MPI_Op op)
{
  for (std::size_t at = 0; at < values.size(); at += SLICE) {
    const int n = static_cast<int>(std::min(SLICE, values.size() - at));
    MPI_Allreduce(MPI_IN_PLACE, values.data() + at, n, type, op, MPI_COMM_WORLD);
  }
}

} // namespace

MpiComm::MpiComm()
{
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Win* window = new MPI_Win;
  const MPI_Aint bytes = rank_ == 0 ? sizeof(std::uint64_t) : 0;
  MPI_Win_allocate(bytes, sizeof(std::uint64_t), MPI_INFO_NULL, MPI_COMM_WORLD,
                   &counter_, window);
  window_ = window;
  if (rank_ == 0)
    *counter_ = 0;
  MPI_Barrier(MPI_COMM_WORLD);
}

MpiComm::~MpiComm()
{
  auto* window = static_cast<MPI_Win*>(window_);
  MPI_Win_free(window);
  delete window;
}

void MpiComm::startTasks()
{
  MPI_Barrier(MPI_COMM_WORLD); // nobody still counts the last round
  auto* window = static_cast<MPI_Win*>(window_);
  if (rank_ == 0) {
    MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, *window);
    *counter_ = 0;
    MPI_Win_unlock(0, *window);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

std::uint64_t MpiComm::nextTask()
{
  const std::lock_guard<std::mutex> lock(mutex_);
  auto* window = static_cast<MPI_Win*>(window_);
  const std::uint64_t one = 1;
  std::uint64_t value = 0;
  MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, *window);
  MPI_Fetch_and_op(&one, &value, MPI_UINT64_T, 0, 0, MPI_SUM, *window);
  MPI_Win_unlock(0, *window);
  return value;
}

void MpiComm::sum(std::vector<std::uint64_t>& values)
{
  allreduce(values, MPI_UINT64_T, MPI_SUM);
}

void MpiComm::min(std::vector<double>& values)
{
  allreduce(values, MPI_DOUBLE, MPI_MIN);
}

void MpiComm::max(std::vector<double>& values)
{
  allreduce(values, MPI_DOUBLE, MPI_MAX);
}

void MpiComm::broadcast(std::string& bytes, int root)
{
  std::uint64_t size = bytes.size();
  MPI_Bcast(&size, 1, MPI_UINT64_T, root, MPI_COMM_WORLD);
  bytes.resize(size);
  for (std::size_t at = 0; at < size; at += SLICE) {
    const int n = static_cast<int>(std::min<std::size_t>(SLICE, size - at));
    MPI_Bcast(&bytes[at], n, MPI_CHAR, root, MPI_COMM_WORLD);
  }
}

void MpiComm::barrier()
{
  MPI_Barrier(MPI_COMM_WORLD);
}

MpiSession::MpiSession(int* argc, char*** argv)
{
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided);
  threads_supported_ = provided >= MPI_THREAD_SERIALIZED;
}

MpiSession::~MpiSession()
{
  MPI_Finalize();
}

} // namespace pcl_vts
