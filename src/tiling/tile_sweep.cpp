// See tile_sweep.h.
#include "tile_sweep.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <type_traits>
#include <unistd.h>

namespace pcl_vts {

Status sweepIoFailure(const char* what, const std::string& path, int err)
{
  std::string why = std::strerror(err);
  if (err == ENOSPC || err == EDQUOT || err == EFBIG)
    why += " (the temporary folder is full: free space there or choose another folder)";
  return Status::error(StatusCode::IO_ERROR,
                       std::string("cannot ") + what + " '" + path + "': " + why);
}

VertexRecords::~VertexRecords()
{
  if (fd_ >= 0)
    ::close(fd_);
}

Status VertexRecords::create()
{
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  return fd_ < 0 ? sweepIoFailure("create", path_, errno) : Status::success();
}

Status VertexRecords::open()
{
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  return fd_ < 0 ? sweepIoFailure("open", path_, errno) : Status::success();
}

Status VertexRecords::openForWriting()
{
  fd_ = ::open(path_.c_str(), O_RDWR | O_CLOEXEC);
  return fd_ < 0 ? sweepIoFailure("open", path_, errno) : Status::success();
}

Status VertexRecords::write(std::uint64_t first,
                            const std::vector<double>& values) const
{
  return transfer(first, reinterpret_cast<const char*>(values.data()),
                  values.size() * sizeof(double));
}

Status VertexRecords::read(std::uint64_t first, std::size_t count, double* out) const
{
  return transfer(first, reinterpret_cast<char*>(out), count * bytes_);
}

/// pwrite from const bytes, pread into the others, to the last byte.
template <typename Byte>
Status VertexRecords::transfer(std::uint64_t first, Byte* bytes, std::size_t size) const
{
  constexpr bool writing = std::is_const_v<Byte>;
  const auto offset = static_cast<off_t>(first * bytes_);
  for (std::size_t done = 0; done < size;) {
    ssize_t n;
    if constexpr (writing)
      n = ::pwrite(fd_, bytes + done, size - done, offset + static_cast<off_t>(done));
    else
      n = ::pread(fd_, bytes + done, size - done, offset + static_cast<off_t>(done));
    if (n < 0 && errno == EINTR)
      continue;
    if (n <= 0)
      return writing ? sweepIoFailure("write", path_, n < 0 ? errno : ENOSPC)
                     : Status::error(StatusCode::IO_ERROR,
                                     "cannot read back '" + path_ + "'");
    done += static_cast<std::size_t>(n);
  }
  return Status::success();
}

Status appendWords(const std::string& path, const std::vector<std::uint32_t>& ids)
{
  std::FILE* file = std::fopen(path.c_str(), "ab");
  if (file == nullptr)
    return sweepIoFailure("create", path, errno);
  const bool ok =
      std::fwrite(ids.data(), sizeof(std::uint32_t), ids.size(), file) == ids.size();
  const int err = errno;
  if (std::fclose(file) != 0 || !ok)
    return sweepIoFailure("write", path, ok ? errno : err);
  return Status::success();
}

Status readWords(const std::string& path, std::vector<std::uint32_t>& ids,
                 std::size_t unit)
{
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr)
    return errno == ENOENT ? Status::success() : sweepIoFailure("open", path, errno);
  std::uint32_t buffer[3 * 1024];
  std::size_t n;
  while ((n = std::fread(buffer, sizeof(std::uint32_t), 3 * 1024, file)) > 0)
    ids.insert(ids.end(), buffer, buffer + n);
  const bool failed = std::ferror(file) != 0 || ids.size() % unit != 0;
  std::fclose(file);
  return failed ? Status::error(StatusCode::IO_ERROR, "cannot read back '" + path + "'")
                : Status::success();
}

Status loadPart(const VertexRecords& positions, const std::vector<std::uint32_t>& ids,
                const std::vector<TriangleKey>& triangles, TriangleMesh& part)
{
  part = TriangleMesh{};
  part.xy.resize(ids.size());
  part.z.resize(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    double p[3] = {0.0, 0.0, 0.0};
    if (Status s = positions.read(ids[i], 1, p); !s.ok())
      return s;
    part.xy[i] = Point2{p[0], p[1]};
    part.z[i] = p[2];
  }
  part.triangles.reserve(3 * triangles.size());
  for (const TriangleKey& key : triangles)
    for (const std::uint32_t v : key)
      part.triangles.push_back(localIdOf(ids, v));
  return Status::success();
}

void broadcastIds(JobComm& comm, std::vector<std::uint32_t>& ids)
{
  if (comm.size() == 1)
    return;
  std::string bytes;
  if (comm.rank() == 0)
    bytes.assign(reinterpret_cast<const char*>(ids.data()),
                 ids.size() * sizeof(std::uint32_t));
  comm.broadcast(bytes, 0);
  ids.resize(bytes.size() / sizeof(std::uint32_t));
  std::memcpy(ids.data(), bytes.data(), bytes.size());
}

} // namespace pcl_vts
