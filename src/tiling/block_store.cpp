// Tile files and their block index (block_store.h).
#include "block_store.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <numeric>
#include <unistd.h>

namespace pcl_vts {
namespace {

constexpr std::size_t POINT_BYTES = 3 * sizeof(double);

Status writeAll(int fd, const void* data, std::size_t bytes, off_t offset, int& err)
{
  const char* p = static_cast<const char*>(data);
  while (bytes > 0) {
    const ssize_t w =
        offset < 0 ? ::write(fd, p, bytes) : ::pwrite(fd, p, bytes, offset);
    if (w < 0 && errno == EINTR)
      continue;
    if (w <= 0) {
      err = w < 0 ? errno : EIO;
      return Status::error(StatusCode::IO_ERROR, "");
    }
    p += w;
    bytes -= static_cast<std::size_t>(w);
    if (offset >= 0)
      offset += w;
  }
  return Status::success();
}

Status readAll(int fd, void* data, std::size_t bytes, off_t offset, int& err)
{
  char* p = static_cast<char*>(data);
  while (bytes > 0) {
    const ssize_t r = ::pread(fd, p, bytes, offset);
    if (r < 0 && errno == EINTR)
      continue;
    if (r <= 0) {
      err = r < 0 ? errno : EIO; // a file shorter than its index: it was changed
      return Status::error(StatusCode::IO_ERROR, "");
    }
    p += r;
    bytes -= static_cast<std::size_t>(r);
    offset += r;
  }
  return Status::success();
}

} // namespace

BlockStore::BlockStore(std::string folder, const TileFrame& frame, int tile_level,
                       int block_level, std::size_t buffer_points)
    : folder_(std::move(folder))
    , frame_(frame)
    , tile_level_(tile_level)
    , block_level_(block_level)
    , buffer_points_(std::max<std::size_t>(buffer_points, 64))
    , buffers_(std::size_t{1} << (2 * tile_level))
    , tile_points_(buffers_.size(), 0)
    , block_points_(std::size_t{1} << (2 * block_level), 0)
    , fds_(buffers_.size(), -1)
{}

BlockStore::~BlockStore()
{
  for (int fd : fds_)
    if (fd >= 0)
      ::close(fd);
}

std::string BlockStore::tilePath(std::uint32_t tile) const
{
  return folder_ + "/tile_" + std::to_string(tile) + ".xyz";
}

Status BlockStore::ioError(const std::string& what, const std::string& path,
                           int err) const
{
  std::string why = std::strerror(err);
  if (err == ENOSPC || err == EDQUOT || err == EFBIG)
    why += " (the temporary folder '" + folder_ +
           "' is full: free space there or choose another with --temp-dir)";
  return Status::error(StatusCode::IO_ERROR,
                       "cannot " + what + " '" + path + "': " + why);
}

Status BlockStore::add(const double* xyz, std::size_t n)
{
  for (std::size_t i = 0; i < n; ++i) {
    const double* p = xyz + 3 * i;
    const std::uint32_t tile = TileFrame::nodeOf(frame_.code(p[0], p[1]), tile_level_);
    std::vector<double>& buffer = buffers_[tile];
    buffer.insert(buffer.end(), p, p + 3);
    ++tile_points_[tile];
    if (buffer.size() >= 3 * buffer_points_) {
      const Status s = flush(tile);
      if (!s.ok())
        return s;
    }
  }
  return Status::success();
}

Status BlockStore::flush(std::uint32_t tile)
{
  std::vector<double>& buffer = buffers_[tile];
  if (buffer.empty())
    return Status::success();
  const std::string path = tilePath(tile);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
  if (fd < 0)
    return ioError("create", path, errno);
  int err = 0;
  const Status s = writeAll(fd, buffer.data(), buffer.size() * sizeof(double), -1, err);
  if (::close(fd) != 0 && s.ok())
    return ioError("write", path, errno);
  if (!s.ok())
    return ioError("write", path, err);
  buffer.clear();
  buffer.shrink_to_fit();
  return Status::success();
}

Status BlockStore::finish()
{
  const std::size_t blocks = block_points_.size();
  block_distinct_.assign(blocks, 0);
  block_start_.assign(blocks, 0);
  block_bounds_.assign(blocks, Rect{});
  for (std::uint32_t tile = 0; tile < buffers_.size(); ++tile) {
    if (tile_points_[tile] == 0)
      continue;
    Status s = flush(tile);
    if (s.ok())
      s = orderTile(tile);
    if (!s.ok())
      return s;
  }
  return Status::success();
}

Status BlockStore::orderTile(std::uint32_t tile)
{
  const std::string path = tilePath(tile);
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0)
    return ioError("open", path, errno);
  fds_[tile] = fd;
  const std::size_t n = tile_points_[tile];
  std::vector<double> in(3 * n);
  int err = 0;
  if (!readAll(fd, in.data(), n * POINT_BYTES, 0, err).ok())
    return ioError("read back", path, err);

  // Stable counting sort by block (the blocks of one tile are a contiguous range).
  const int shift = 2 * (block_level_ - tile_level_);
  const std::uint32_t first_block = tile << shift;
  const std::size_t tile_blocks = std::size_t{1} << shift;
  std::vector<std::uint32_t> block_of(n);
  std::vector<std::uint64_t> start(tile_blocks + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t code = frame_.code(in[3 * i], in[3 * i + 1]);
    block_of[i] = TileFrame::nodeOf(code, block_level_) - first_block;
    ++start[block_of[i] + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<double> out(3 * n);
  std::vector<std::uint64_t> next(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t k = next[block_of[i]]++;
    std::copy_n(&in[3 * i], 3, &out[3 * k]);
  }
  std::vector<double>().swap(in);
  if (!writeAll(fd, out.data(), n * POINT_BYTES, 0, err).ok())
    return ioError("write", path, err);

  // Per block: count, distinct XY positions, exact bounding box.
  std::vector<Point2> xy;
  for (std::size_t b = 0; b < tile_blocks; ++b) {
    const std::uint64_t begin = start[b], end = start[b + 1];
    const std::uint32_t block = first_block + static_cast<std::uint32_t>(b);
    block_points_[block] = end - begin;
    block_start_[block] = begin;
    if (begin == end)
      continue;
    xy.clear();
    Rect box{out[3 * begin], out[3 * begin + 1], out[3 * begin], out[3 * begin + 1]};
    for (std::uint64_t k = begin; k < end; ++k) {
      const Point2 p{out[3 * k], out[3 * k + 1]};
      xy.push_back(p);
      box.x0 = std::min(box.x0, p.x);
      box.y0 = std::min(box.y0, p.y);
      box.x1 = std::max(box.x1, p.x);
      box.y1 = std::max(box.y1, p.y);
    }
    std::sort(xy.begin(), xy.end(), [](const Point2& a, const Point2& c) {
      return a.x < c.x || (a.x == c.x && a.y < c.y);
    });
    block_distinct_[block] =
        static_cast<std::uint64_t>(std::unique(xy.begin(), xy.end()) - xy.begin());
    block_bounds_[block] = box;
  }
  return Status::success();
}

Status BlockStore::readBlock(std::uint32_t block, std::vector<double>& xyz) const
{
  const std::uint64_t n = block_points_[block];
  if (n == 0)
    return Status::success();
  const std::uint32_t tile = block >> (2 * (block_level_ - tile_level_));
  const std::size_t old = xyz.size();
  xyz.resize(old + 3 * n);
  int err = 0;
  if (!readAll(fds_[tile], &xyz[old], n * POINT_BYTES,
               static_cast<off_t>(block_start_[block] * POINT_BYTES), err)
           .ok())
    return ioError("read back", tilePath(tile), err);
  return Status::success();
}

std::uint64_t BlockStore::bytesOnDisk() const
{
  return std::accumulate(tile_points_.begin(), tile_points_.end(), std::uint64_t{0}) *
         POINT_BYTES;
}

} // namespace pcl_vts
