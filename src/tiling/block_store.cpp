// Tile files and their block index (block_store.h).
#include "block_store.h"
#include "global_hull.h"

#include <pcl_vts/tiling/job_comm.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <numeric>
#include <sys/stat.h>
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
                       int block_level, std::size_t buffer_points, int rank, int ranks)
    : folder_(std::move(folder))
    , frame_(frame)
    , tile_level_(tile_level)
    , block_level_(block_level)
    , buffer_points_(std::max<std::size_t>(buffer_points, 64))
    , rank_(rank)
    , ranks_(ranks)
    , buffers_(std::size_t{1} << (2 * tile_level))
    , part_points_(buffers_.size(), 0)
    , block_points_(std::size_t{1} << (2 * block_level), 0)
    , block_distinct_(block_points_.size(), 0)
    , block_start_(block_points_.size(), 0)
    , block_bounds_(block_points_.size(),
                    Rect{HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL})
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

std::string BlockStore::partPath(std::uint32_t tile, int rank) const
{
  return folder_ + "/tile_" + std::to_string(tile) + ".part" + std::to_string(rank);
}

Status BlockStore::ioError(const std::string& what, const std::string& path,
                           int err) const
{
  std::string why = std::strerror(err);
  if (err == ENOSPC || err == EDQUOT || err == EFBIG)
    why += " (the temporary folder '" + folder_ +
           "' is full: free space there or choose another folder)";
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
    ++part_points_[tile];
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
  const std::string path = partPath(tile, rank_);
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

Status BlockStore::flush()
{
  for (std::uint32_t tile = 0; tile < buffers_.size(); ++tile)
    if (Status s = flush(tile); !s.ok())
      return s;
  return Status::success();
}

Status BlockStore::orderTile(std::uint32_t tile)
{
  // The parts in rank order: the points in input order.
  std::vector<double> in;
  int err = 0;
  for (int r = 0; r < ranks_; ++r) {
    const std::string part = partPath(tile, r);
    const int fd = ::open(part.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
      if (errno == ENOENT)
        continue; // that rank had no point here
      return ioError("open", part, errno);
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || st.st_size % static_cast<off_t>(POINT_BYTES) != 0) {
      ::close(fd);
      return ioError("read back", part, EIO);
    }
    const std::size_t old = in.size();
    in.resize(old + static_cast<std::size_t>(st.st_size) / sizeof(double));
    const Status s =
        readAll(fd, &in[old], static_cast<std::size_t>(st.st_size), 0, err);
    ::close(fd);
    ::unlink(part.c_str());
    if (!s.ok())
      return ioError("read back", part, err);
  }
  const std::size_t n = in.size() / 3;
  if (n == 0)
    return Status::success();

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
  const std::string path = tilePath(tile);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0)
    return ioError("create", path, errno);
  const Status written = writeAll(fd, out.data(), n * POINT_BYTES, 0, err);
  if (::close(fd) != 0 && written.ok())
    return ioError("write", path, errno);
  if (!written.ok())
    return ioError("write", path, err);

  // Per block: count, distinct XY positions, exact bounding box.
  std::vector<Point2> xy, tile_hull;
  for (std::size_t b = 0; b < tile_blocks; ++b) {
    const std::uint64_t begin = start[b], end = start[b + 1];
    const std::uint32_t block = first_block + static_cast<std::uint32_t>(b);
    block_points_[block] = end - begin;
    block_start_[block] = begin;
    if (begin == end)
      continue;
    xy.clear();
    Rect box{HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
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
    // Only a block's hull vertices can be vertices of the global hull.
    const std::vector<Point2> block_hull = hullOfSorted(xy);
    tile_hull.insert(tile_hull.end(), block_hull.begin(), block_hull.end());
  }
  tile_hull = hullOf(std::move(tile_hull));
  // The hull of a set does not depend on the order the tiles' hulls arrive in.
  const std::lock_guard<std::mutex> lock(hull_mutex_);
  hull_.insert(hull_.end(), tile_hull.begin(), tile_hull.end());
  hull_ = hullOf(std::move(hull_));
  return Status::success();
}

void BlockStore::shareIndex(JobComm& comm)
{
  comm.sum(block_points_);
  comm.sum(block_distinct_);
  comm.sum(block_start_);
  comm.sum(part_points_); // now: every rank's points per tile
  std::vector<double> low(2 * block_bounds_.size()), high(2 * block_bounds_.size());
  for (std::size_t b = 0; b < block_bounds_.size(); ++b) {
    low[2 * b] = block_bounds_[b].x0;
    low[2 * b + 1] = block_bounds_[b].y0;
    high[2 * b] = block_bounds_[b].x1;
    high[2 * b + 1] = block_bounds_[b].y1;
  }
  comm.min(low);
  comm.max(high);
  for (std::size_t b = 0; b < block_bounds_.size(); ++b)
    block_bounds_[b] = Rect{low[2 * b], low[2 * b + 1], high[2 * b], high[2 * b + 1]};
  // Every rank's hull, to every rank: the hull of their union is the global hull.
  std::vector<Point2> all;
  for (int root = 0; root < comm.size(); ++root) {
    std::string bytes;
    if (root == comm.rank())
      bytes.assign(reinterpret_cast<const char*>(hull_.data()),
                   hull_.size() * sizeof(Point2));
    comm.broadcast(bytes, root);
    const std::size_t n = bytes.size() / sizeof(Point2);
    const std::size_t old = all.size();
    all.resize(old + n);
    std::memcpy(all.data() + old, bytes.data(), n * sizeof(Point2));
  }
  hull_ = hullOf(std::move(all));
}

std::uint64_t BlockStore::tilePoints(std::uint32_t tile) const
{
  return part_points_[tile];
}

int BlockStore::openTile(std::uint32_t tile) const
{
  const std::lock_guard<std::mutex> lock(fd_mutex_);
  if (fds_[tile] < 0)
    fds_[tile] = ::open(tilePath(tile).c_str(), O_RDONLY | O_CLOEXEC);
  return fds_[tile];
}

Status BlockStore::readBlock(std::uint32_t block, std::vector<double>& xyz) const
{
  const std::uint64_t n = block_points_[block];
  if (n == 0)
    return Status::success();
  const std::uint32_t tile = block >> (2 * (block_level_ - tile_level_));
  const int fd = openTile(tile);
  if (fd < 0)
    return ioError("open", tilePath(tile), errno);
  const std::size_t old = xyz.size();
  xyz.resize(old + 3 * n);
  int err = 0;
  if (!readAll(fd, &xyz[old], n * POINT_BYTES,
               static_cast<off_t>(block_start_[block] * POINT_BYTES), err)
           .ok())
    return ioError("read back", tilePath(tile), err);
  return Status::success();
}

void BlockStore::closeTileFiles()
{
  const std::lock_guard<std::mutex> lock(fd_mutex_);
  for (int& fd : fds_)
    if (fd >= 0) {
      ::close(fd);
      fd = -1;
    }
}

void BlockStore::removeTileFiles()
{
  // The tiles this rank ordered (orderTile: t = rank, rank + ranks, ...). A file
  // that is not there (an empty tile) is no error.
  for (std::size_t t = static_cast<std::size_t>(rank_); t < buffers_.size();
       t += static_cast<std::size_t>(ranks_))
    ::unlink(tilePath(static_cast<std::uint32_t>(t)).c_str());
}

void BlockStore::releaseTileFile(std::uint32_t tile)
{
  const std::lock_guard<std::mutex> lock(fd_mutex_);
  if (fds_[tile] >= 0) {
    ::close(fds_[tile]);
    fds_[tile] = -1;
  }
  ::unlink(tilePath(tile).c_str());
}

std::uint64_t BlockStore::bytesOnDisk() const
{
  return std::accumulate(part_points_.begin(), part_points_.end(), std::uint64_t{0}) *
         POINT_BYTES;
}

} // namespace pcl_vts
