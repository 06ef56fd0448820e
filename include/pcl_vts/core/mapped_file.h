// A whole file as read-only bytes (mmap, private), the one mapping wrapper: the file
// readers parse one [data, data + size) range (the code the fuzzers drive from
// memory), the out-of-core DEM and contours look vertices up by id in a temporary
// file. The range is never written; an empty file is size 0 with data == nullptr.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace pcl_vts {

class PCL_VTS_CORE_EXPORT MappedFile {
 public:
  MappedFile() = default;
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile() { close(); }

  /// Maps path (unmapping what was mapped); IO_ERROR "'path': cannot open: <reason>"
  /// (or "not a regular file", "cannot map: <reason>").
  Status open(const std::string& path);
  /// Maps the regular file open on fd (the caller keeps and closes fd); errors name
  /// `path` as open does.
  Status open(int fd, const std::string& path);
  /// Unmaps: data() nullptr, size() 0.
  void close();
  /// Drops the pages read so far from memory (read back from the file when touched).
  void dropPages() const;

  const std::uint8_t* data() const { return data_; }
  std::size_t size() const { return size_; }

 private:
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
};

/// Drops from memory the whole pages of a read-only mapping inside [begin, end) (a
/// parser's consumed prefix); they are read back from the file if touched again.
PCL_VTS_CORE_EXPORT void dropMappedPages(const void* begin, const void* end);

} // namespace pcl_vts
