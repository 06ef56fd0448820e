// Private to the file readers (LAS, ASCII grid, XYZ text, PLY): what they all share.
// ioError is their error shape; guardedParse resets the info, turns bad_alloc into a
// one-line IO_ERROR and leaves xyz empty on any failure; readMappedFile maps the file
// and hands its bytes to the reader's in-memory parser (the one the fuzzers drive);
// releaseReadPages drops the pages a streaming reader has passed.
#pragma once

#include "mapped_file.h"

#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <new>
#include <string>
#include <sys/mman.h>
#include <vector>

namespace pcl_vts {

/// The readers' one error shape: IO_ERROR, "'name': what".
inline Status ioError(const std::string& name, const std::string& what)
{
  return Status::error(StatusCode::IO_ERROR, "'" + name + "': " + what);
}

/// Runs parse() (which fills xyz and info) with the post-conditions above.
template <typename Info, typename Parse>
Status guardedParse(const std::string& name, std::vector<double>& xyz, Info& info,
                    Parse&& parse)
{
  info = Info();
  Status status;
  try {
    status = parse();
  } catch (const std::bad_alloc&) {
    status = Status::error(StatusCode::IO_ERROR,
                           "'" + name + "': out of memory while reading");
  }
  if (!status.ok()) {
    xyz.clear();
    xyz.shrink_to_fit();
  }
  return status;
}

/// Drops from memory the whole pages of a mapped file between `released` and
/// `consumed` (already parsed), and moves `released` to `consumed`: a streaming
/// reader's memory then stays bounded by its chunk whatever the file's size.
inline void releaseReadPages(const std::uint8_t*& released,
                             const std::uint8_t* consumed)
{
  const std::uintptr_t page = 4096;
  const auto end = reinterpret_cast<std::uintptr_t>(consumed) & ~(page - 1);
  const auto begin =
      (reinterpret_cast<std::uintptr_t>(released) + page - 1) & ~(page - 1);
  if (end > begin)
    ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_DONTNEED);
  released = consumed;
}

/// Maps path and returns parse_bytes(data, size); a file that cannot be opened or
/// mapped is an IO_ERROR naming it.
template <typename Info, typename ParseBytes>
Status readMappedFile(const std::string& path, std::vector<double>& xyz, Info& info,
                      ParseBytes&& parse_bytes)
{
  info = Info();
  xyz.clear();
  MappedFile file;
  if (Status s = file.open(path); !s.ok())
    return s;
  return parse_bytes(file.data(), file.size());
}

} // namespace pcl_vts
