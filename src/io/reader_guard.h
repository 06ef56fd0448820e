// Private to the file readers (LAS, ASCII grid, XYZ text, PLY): the two wrappers they
// all share. guardedParse resets the info, turns bad_alloc into a one-line IO_ERROR
// and leaves xyz empty on any failure; readMappedFile maps the file and hands its
// bytes to the reader's in-memory parser (the one the fuzzers drive).
#pragma once

#include "mapped_file.h"

#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <new>
#include <string>
#include <vector>

namespace pcl_vts {

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
