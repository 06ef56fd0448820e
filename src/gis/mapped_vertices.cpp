// See mapped_vertices.h.
#include "mapped_vertices.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

namespace pcl_vts {

namespace {

Status ioFailure(const std::string& what, const std::string& verb,
                 const std::string& path)
{
  return Status::error(StatusCode::IO_ERROR, what + ": cannot " + verb + " '" + path +
                                                 "': " + std::strerror(errno));
}

} // namespace

Status MappedVertices::map(const MeshStream& mesh, const std::string& path,
                           const std::string& what)
{
  release();
  path_ = path;
  std::FILE* out = std::fopen(path.c_str(), "wb");
  if (!out)
    return ioFailure(what, "create", path);
  std::vector<double> buffer;
  bool written = true;
  std::uint64_t n = 0;
  Status s = mesh.vertices([&](double x, double y, double z) {
    buffer.insert(buffer.end(), {x, y, z});
    ++n;
    if (buffer.size() >= 3 * 8192) { // cleared after a failed write too: bounded
      written = written && std::fwrite(buffer.data(), sizeof(double), buffer.size(),
                                       out) == buffer.size();
      buffer.clear();
    }
  });
  if (written && !buffer.empty())
    written =
        std::fwrite(buffer.data(), sizeof(double), buffer.size(), out) == buffer.size();
  if (std::fclose(out) != 0)
    written = false;
  if (!s.ok())
    return s;
  if (!written)
    return ioFailure(what, "write (is the temporary folder full?)", path);
  if (n == 0)
    return Status::success();
  if (Status m = file_.open(path); !m.ok())
    return Status::error(StatusCode::IO_ERROR, what + ": " + m.message);
  if (file_.size() != n * 3 * sizeof(double)) {
    file_.close();
    return Status::error(StatusCode::IO_ERROR,
                         what + ": '" + path + "' holds " +
                             std::to_string(file_.size()) + " bytes, not the " +
                             std::to_string(n * 3 * sizeof(double)) + " written");
  }
  count_ = n;
  return Status::success();
}

void MappedVertices::release()
{
  file_.close();
  count_ = 0;
  if (!path_.empty())
    std::remove(path_.c_str());
  path_.clear();
}

} // namespace pcl_vts
