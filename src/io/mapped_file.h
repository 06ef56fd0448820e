// A whole input file as read-only bytes (mmap), so every reader parses one
// [data, data + size) range, the same code the fuzzers drive from memory. The range
// is never written; an empty file is size 0 with data == nullptr. PCL-free.
#pragma once

#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace pcl_vts {

class MappedFile {
 public:
  MappedFile() = default;
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile();

  /// Maps path; IO_ERROR "'path': cannot open: <reason>" (or "not a regular file").
  Status open(const std::string& path);

  const std::uint8_t* data() const { return data_; }
  std::size_t size() const { return size_; }

 private:
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
};

} // namespace pcl_vts
