// mmap of a whole regular file; failures name the file and the system's reason.
#include "release_memory.h"

#include <pcl_vts/core/mapped_file.h>

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace pcl_vts {

void MappedFile::close()
{
  if (data_ != nullptr)
    ::munmap(const_cast<std::uint8_t*>(data_), size_);
  data_ = nullptr;
  size_ = 0;
}

void MappedFile::dropPages() const
{
  if (data_ != nullptr)
    ::madvise(const_cast<std::uint8_t*>(data_), size_, MADV_DONTNEED);
}

void dropMappedPages(const void* begin, const void* end)
{
  if (begin != nullptr) // a private file mapping reads its pages back from the file
    detail::releasePages(begin, end);
}

Status MappedFile::open(const std::string& path)
{
  close();
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    return Status::error(StatusCode::IO_ERROR,
                         "'" + path + "': cannot open: " + std::strerror(errno));
  Status s = open(fd, path);
  ::close(fd);
  return s;
}

Status MappedFile::open(int fd, const std::string& path)
{
  close();
  const auto fail = [&](const std::string& what) {
    return Status::error(StatusCode::IO_ERROR, "'" + path + "': " + what);
  };
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    return fail(std::string("cannot stat: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode))
    return fail("not a regular file");
  size_ = static_cast<std::size_t>(st.st_size);
  if (size_ == 0)
    return Status::success();
  void* map = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
  if (map == MAP_FAILED) {
    size_ = 0;
    return fail(std::string("cannot map: ") + std::strerror(errno));
  }
  data_ = static_cast<const std::uint8_t*>(map);
  return Status::success();
}

} // namespace pcl_vts
