// Raw point and PLY mesh files of compare_methods (compare_files.h). The PLY layout is
// fixed, so the reader checks the header line by line instead of parsing PLY in
// general.
#include "compare_files.h"

#include <pcl_vts/core/atomic_file.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace pcl_vts {
namespace compare {
namespace {

constexpr char POINTS_MAGIC[8] = {'P', 'V', 'T', 'S', 'P', 'T', 'S', '1'};

Status ioError(const std::string& path, const std::string& what)
{
  return Status::error(StatusCode::IO_ERROR, path + ": " + what);
}

/// Runs write(file) into an AtomicFile (core/atomic_file.h): path appears complete
/// or not at all.
template <class Writer>
Status writeAtomically(const std::string& path, Writer write)
{
  AtomicFile file(path);
  Status status = file.open();
  if (!status.ok())
    return status;
  write(file);
  return file.commit();
}

/// Appends count values; a failed write is kept by the file and reported by commit().
template <class T>
bool put(AtomicFile& file, const T* data, std::size_t count)
{
  file.write(data, sizeof(T) * count);
  return file.good();
}

template <class T>
bool get(std::istream& in, T* data, std::size_t count)
{
  in.read(reinterpret_cast<char*>(data),
          static_cast<std::streamsize>(sizeof(T) * count));
  return static_cast<std::size_t>(in.gcount()) == sizeof(T) * count;
}

} // namespace

Status writeTextFile(const std::string& path, const std::string& text)
{
  return writeAtomically(
      path, [&](AtomicFile& file) { return put(file, text.data(), text.size()); });
}

Status writePointSet(const std::string& path, const PointSet& points)
{
  return writeAtomically(path, [&](AtomicFile& file) {
    const std::uint64_t n = points.size();
    return put(file, POINTS_MAGIC, 8) && put(file, &n, 1) &&
           put(file, points.offset, 3) && put(file, points.xyz.data(), 3 * n);
  });
}

Status readPointSet(const std::string& path, PointSet& points)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return ioError(path, std::string("cannot open: ") + std::strerror(errno));
  char magic[8];
  std::uint64_t n = 0;
  if (!get(in, magic, 8) || std::memcmp(magic, POINTS_MAGIC, 8) != 0 ||
      !get(in, &n, 1) || !get(in, points.offset, 3))
    return ioError(path, "not a point file written by compare_methods");
  if (n > (std::uint64_t{1} << 31))
    return ioError(path, "point count " + std::to_string(n) + " is too large");
  points.xyz.resize(3 * n);
  if (!get(in, points.xyz.data(), 3 * n))
    return ioError(path, "truncated: expected " + std::to_string(n) + " points");
  return Status::success();
}

Status writeMeshPly(const std::string& path, const CompareMesh& mesh)
{
  const std::size_t nv = mesh.vertexCount(), nt = mesh.triangleCount();
  if (!mesh.source.empty() && mesh.source.size() != nv)
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "mesh source has " + std::to_string(mesh.source.size()) +
                             " entries for " + std::to_string(nv) + " vertices");
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\ncomment pcl_vts compare_methods\n"
         << "element vertex " << nv << "\nproperty double x\nproperty double y\n"
         << "property double z\nproperty int source\nelement face " << nt
         << "\nproperty list uchar uint vertex_indices\nend_header\n";
  return writeAtomically(path, [&](AtomicFile& file) {
    const std::string text = header.str();
    bool ok = put(file, text.data(), text.size());
    for (std::size_t v = 0; ok && v < nv; ++v) {
      const std::int32_t source = mesh.source.empty() ? -1 : mesh.source[v];
      ok = put(file, &mesh.xyz[3 * v], 3) && put(file, &source, 1);
    }
    const std::uint8_t three = 3;
    for (std::size_t t = 0; ok && t < nt; ++t)
      ok = put(file, &three, 1) && put(file, &mesh.triangles[3 * t], 3);
    return ok;
  });
}

Status readMeshPly(const std::string& path, CompareMesh& mesh)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return ioError(path, std::string("cannot open: ") + std::strerror(errno));
  const char* expected[] = {"ply", "format binary_little_endian 1.0", nullptr};
  std::string line;
  std::size_t nv = 0, nt = 0;
  for (int i = 0; expected[i]; ++i)
    if (!std::getline(in, line) || line != expected[i])
      return ioError(path, "not a mesh written by compare_methods");
  const std::string layout = "property double x|property double y|property double "
                             "z|property int source|property list uchar uint "
                             "vertex_indices|";
  std::string seen;
  while (std::getline(in, line) && line != "end_header") {
    if (line.rfind("comment", 0) == 0)
      continue;
    if (std::sscanf(line.c_str(), "element vertex %zu", &nv) == 1 ||
        std::sscanf(line.c_str(), "element face %zu", &nt) == 1)
      continue;
    seen += line + "|";
  }
  if (line != "end_header" || seen != layout || nv >= (std::size_t{1} << 31) ||
      nt >= (std::size_t{1} << 31))
    return ioError(path, "unexpected PLY header (not written by compare_methods)");
  mesh.xyz.resize(3 * nv);
  mesh.source.resize(nv);
  mesh.triangles.resize(3 * nt);
  for (std::size_t v = 0; v < nv; ++v)
    if (!get(in, &mesh.xyz[3 * v], 3) || !get(in, &mesh.source[v], 1))
      return ioError(path, "truncated vertex list");
  for (std::size_t t = 0; t < nt; ++t) {
    std::uint8_t count = 0;
    if (!get(in, &count, 1) || count != 3 || !get(in, &mesh.triangles[3 * t], 3))
      return ioError(path, "truncated or non-triangle face list");
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles[3 * t + k] >= nv)
        return ioError(path, "face " + std::to_string(t) + " has vertex id " +
                                 std::to_string(mesh.triangles[3 * t + k]) +
                                 " >= " + std::to_string(nv));
  }
  return Status::success();
}

} // namespace compare
} // namespace pcl_vts
