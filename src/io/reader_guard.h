// Private to the file readers (LAS, ASCII grid, XYZ text, PLY): what they all share.
// ioError is their error shape; guardedParse resets the info, turns bad_alloc into a
// one-line IO_ERROR and leaves xyz empty on any failure; readMappedFile maps the file
// and hands its bytes to the reader's in-memory parser (the one the fuzzers drive);
// PointOutput and readMappedFileInChunks are the streaming reads.
#pragma once

#include <pcl_vts/core/mapped_file.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <new>
#include <string>
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

/// Where a reader's points go: the whole array (no sink), or chunks of at most
/// chunk_points handed to a sink as the parse goes, with the whole pages of the mapped
/// file behind the reader dropped from memory: a streaming reader then stays bounded
/// by its chunk whatever the file's size. One for the LAS, ASCII grid, XYZ and PLY
/// readers.
class PointOutput {
 public:
  using Sink = std::function<Status(const double* xyz, std::size_t n)>;

  PointOutput() = default;
  PointOutput(const Sink& sink, std::size_t chunk_points)
      : sink_(&sink)
      , chunk_points_(chunk_points == 0 ? 1 : chunk_points)
  {}

  bool streaming() const { return sink_ != nullptr; }
  /// Points to reserve: one chunk when streaming, else all `total`.
  std::size_t reserve(std::size_t total) const { return sink_ ? chunk_points_ : total; }
  /// The parse starts at `data` (the first page that may be dropped).
  void begin(const void* data) { released_ = static_cast<const std::uint8_t*>(data); }
  /// xyz holds a full chunk: time to hand it over.
  bool full(const std::vector<double>& xyz) const
  {
    return sink_ && xyz.size() >= 3 * chunk_points_;
  }
  /// Hands xyz to the sink and empties it; the file up to `consumed` is parsed.
  Status handOver(std::vector<double>& xyz, const void* consumed)
  {
    handed_ += xyz.size() / 3;
    const Status s =
        xyz.empty() ? Status::success() : (*sink_)(xyz.data(), xyz.size() / 3);
    xyz.clear();
    dropMappedPages(released_, consumed);
    released_ = static_cast<const std::uint8_t*>(consumed);
    return s;
  }
  /// At the end of the parse: hands the rest over when streaming. Out: the points
  /// delivered in all (handed over, or held in xyz).
  Status finish(std::vector<double>& xyz, const void* consumed, std::size_t& points)
  {
    Status s = sink_ ? handOver(xyz, consumed) : Status::success();
    points = sink_ ? handed_ : xyz.size() / 3;
    return s;
  }

 private:
  const Sink* sink_ = nullptr;
  std::size_t chunk_points_ = 0;
  std::size_t handed_ = 0;
  const std::uint8_t* released_ = nullptr;
};

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

/// readMappedFile for a streaming read: parse(data, size, chunk, output) fills and
/// hands over `chunk` through `output` (sink, chunk_points), guarded as guardedParse.
template <typename Info, typename Parse>
Status readMappedFileInChunks(const std::string& path, const PointOutput::Sink& sink,
                              std::size_t chunk_points, Info& info, Parse&& parse)
{
  std::vector<double> chunk;
  PointOutput output(sink, chunk_points);
  return readMappedFile(
      path, chunk, info, [&](const std::uint8_t* data, std::size_t size) {
        return guardedParse(path, chunk, info,
                            [&] { return parse(data, size, chunk, output); });
      });
}

} // namespace pcl_vts
