// AtomicFile (atomic_file.h): POSIX open(O_EXCL) / write / fsync / rename, with a
// 1 MiB buffer so that writers may append a few bytes at a time.
#include <pcl_vts/core/atomic_file.h>

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>
#include <utility>

namespace pcl_vts {
namespace {

constexpr std::size_t BUFFER_BYTES = 1 << 20;

std::string quoted(const std::string& path)
{
  return "'" + path + "'";
}

/// The folder part of path with its trailing slash ("" for a bare file name).
std::string folderOf(const std::string& path)
{
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

} // namespace

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path))
{}

AtomicFile::~AtomicFile()
{
  discard();
}

Status AtomicFile::open()
{
  const std::string folder = folderOf(path_);
  const std::string base =
      "." + path_.substr(folder.size()) + ".tmp." + std::to_string(::getpid());
  for (int attempt = 0; attempt < 100; ++attempt) {
    temp_path_ = folder + base + (attempt ? "." + std::to_string(attempt) : "");
    fd_ = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ >= 0 || errno != EEXIST)
      break;
  }
  if (fd_ < 0) {
    const int err = errno;
    temp_path_.clear();
    if (err == ENOENT)
      return Status::error(StatusCode::IO_ERROR,
                           "cannot write " + quoted(path_) + ": folder " +
                               quoted(folder.empty() ? "." : folder) +
                               " does not exist");
    return failure("cannot create a temporary file in the folder of", err);
  }
  buffer_.reserve(BUFFER_BYTES);
  return Status::success();
}

void AtomicFile::write(const void* data, std::size_t n)
{
  if (error_ != 0)
    return;
  const char* p = static_cast<const char*>(data);
  if (buffer_.size() + n > BUFFER_BYTES && !flushBuffer())
    return;
  if (n >= BUFFER_BYTES) {
    writeAll(p, n);
    return;
  }
  buffer_.insert(buffer_.end(), p, p + n);
}

Status AtomicFile::commit()
{
  if (fd_ < 0)
    return Status::error(StatusCode::IO_ERROR,
                         "cannot write " + quoted(path_) + ": not open");
  if (error_ == 0)
    flushBuffer();
  if (error_ == 0 && ::fsync(fd_) != 0)
    error_ = errno;
  if (::close(fd_) != 0 && error_ == 0)
    error_ = errno;
  fd_ = -1;
  if (error_ != 0)
    return failure("cannot write", error_);
  if (::rename(temp_path_.c_str(), path_.c_str()) != 0)
    return failure("cannot rename the temporary file onto", errno);
  temp_path_.clear();
  syncFolder();
  return Status::success();
}

Status AtomicFile::failure(const std::string& what, int err)
{
  discard();
  return Status::error(StatusCode::IO_ERROR,
                       what + " " + quoted(path_) + ": " + std::strerror(err));
}

void AtomicFile::discard()
{
  if (fd_ >= 0)
    ::close(fd_);
  fd_ = -1;
  if (!temp_path_.empty())
    ::unlink(temp_path_.c_str());
  temp_path_.clear();
}

bool AtomicFile::flushBuffer()
{
  if (!buffer_.empty())
    writeAll(buffer_.data(), buffer_.size());
  buffer_.clear();
  return error_ == 0;
}

void AtomicFile::writeAll(const char* p, std::size_t n)
{
  while (n > 0 && error_ == 0) {
    const ssize_t w = ::write(fd_, p, n);
    if (w < 0) {
      if (errno != EINTR)
        error_ = errno;
      continue;
    }
    if (w == 0) {
      error_ = EIO;
      continue;
    }
    p += w;
    n -= static_cast<std::size_t>(w);
    bytes_ += static_cast<std::uint64_t>(w);
  }
}

/// Makes the rename durable; best effort (some file systems refuse).
void AtomicFile::syncFolder() const
{
  const std::string folder = folderOf(path_);
  const int dfd =
      ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    (void)::fsync(dfd);
    ::close(dfd);
  }
}

Status writeFileAtomically(const std::string& path, const void* data, std::size_t n)
{
  AtomicFile file(path);
  Status status = file.open();
  if (!status.ok())
    return status;
  file.write(data, n);
  return file.commit();
}

} // namespace pcl_vts
