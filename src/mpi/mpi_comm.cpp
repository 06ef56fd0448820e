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
  MPI_Init(argc, argv);
}

MpiSession::~MpiSession()
{
  MPI_Finalize();
}

} // namespace pcl_vts
