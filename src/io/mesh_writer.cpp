// Mesh files written exactly and atomically. Text numbers use std::to_chars' shortest
// round-trip form (at most 17 significant digits, max_digits10), so a reader parsing
// doubles gets every input bit back. Every write is checked; the first failure wins
// and the temp file is removed, so a failed run leaves nothing behind.
#include <pcl_vts/core/atomic_file.h>
#include <pcl_vts/io/mesh_writer.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string_view>
#include <utility>
#include <vector>

namespace pcl_vts {
namespace {

std::string quoted(const std::string& path)
{
  return "'" + path + "'";
}

std::string lowerCase(std::string s)
{
  for (char& c : s)
    if (c >= 'A' && c <= 'Z')
      c = static_cast<char>(c - 'A' + 'a');
  return s;
}

std::string oneLine(const std::string& text)
{
  std::string out = text;
  for (char& c : out)
    if (c == '\n' || c == '\r')
      c = ' ';
  return out;
}

/// Appends numbers to an AtomicFile in text or little-endian binary. The bytes are
/// built in a chunk of its own (a number is a to_chars or a memcpy into it, no call
/// per value) that goes to the file whole: 1 MiB at a time, the size AtomicFile
/// writes through without copying it into its own buffer.
class Emitter {
 public:
  explicit Emitter(AtomicFile& file)
      : file_(file)
      , chunk_(new char[CHUNK + SLACK])
  {}

  Emitter& text(std::string_view s)
  {
    while (!s.empty()) {
      const std::size_t n = std::min(s.size(), SLACK);
      std::memcpy(room(), s.data(), n);
      used_ += n;
      s.remove_prefix(n);
    }
    return *this;
  }

  Emitter& number(double v)
  {
    char* p = room();
    used_ += static_cast<std::size_t>(std::to_chars(p, p + SLACK, v).ptr - p);
    return *this;
  }

  Emitter& number(std::uint64_t v)
  {
    char* p = room();
    used_ += static_cast<std::size_t>(std::to_chars(p, p + SLACK, v).ptr - p);
    return *this;
  }

  template <typename T>
  void binary(T v)
  {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i)
      std::swap(b[i], b[sizeof(T) - 1 - i]);
#endif
    std::memcpy(room(), b, sizeof(T));
    used_ += sizeof(T);
  }

  /// Hands the bytes still held to the file; call before commit().
  void finish()
  {
    file_.write(chunk_.get(), used_);
    used_ = 0;
  }

 private:
  static constexpr std::size_t CHUNK = std::size_t{1} << 20;
  static constexpr std::size_t SLACK = 64; ///< the most one call appends

  /// Where the next at most SLACK bytes go; a full chunk goes to the file first.
  char* room()
  {
    if (used_ >= CHUNK) {
      file_.write(chunk_.get(), CHUNK);
      used_ -= CHUNK;
      std::memmove(chunk_.get(), chunk_.get() + CHUNK, used_);
    }
    return chunk_.get() + used_;
  }

  AtomicFile& file_;
  std::unique_ptr<char[]> chunk_;
  std::size_t used_ = 0;
};

/// Records the first bad triangle id seen while streaming; the write then fails.
struct TriangleIdCheck {
  std::uint64_t vertex_count = 0;
  std::string error;
  bool ok(VertexId a, VertexId b, VertexId c, std::uint64_t triangle)
  {
    if (a < vertex_count && b < vertex_count && c < vertex_count)
      return true;
    if (error.empty())
      error = "triangle " + std::to_string(triangle) + " uses vertex " +
              std::to_string(std::max({a, b, c})) + " of " +
              std::to_string(vertex_count);
    return false;
  }
};

template <typename Source>
Status writePly(Emitter& out, const Source& mesh, bool ascii, bool dbl,
                const std::string& comment, TriangleIdCheck& check)
{
  const bool flags = mesh.hasInsertedFlags();
  const char* type = dbl ? "double" : "float";
  out.text("ply\nformat ")
      .text(ascii ? "ascii" : "binary_little_endian")
      .text(" 1.0\ncomment ")
      .text(comment)
      .text("\nelement vertex ")
      .number(mesh.vertexCount())
      .text("\nproperty ")
      .text(type)
      .text(" x\nproperty ")
      .text(type)
      .text(" y\nproperty ")
      .text(type)
      .text(flags ? " z\nproperty uchar inserted\nelement face " : " z\nelement face ")
      .number(mesh.triangleCount())
      .text("\nproperty list uchar int vertex_indices\nend_header\n");
  Status status = mesh.visitVertices([&](double x, double y, double z, bool inserted) {
    const double c[3] = {x, y, z};
    if (ascii) {
      out.number(c[0]).text(" ").number(c[1]).text(" ").number(c[2]);
      if (flags)
        out.text(inserted ? " 1" : " 0");
      out.text("\n");
      return;
    }
    for (double value : c) {
      if (dbl)
        out.binary(value);
      else
        out.binary(static_cast<float>(value));
    }
    if (flags)
      out.binary(static_cast<std::uint8_t>(inserted ? 1 : 0));
  });
  if (!status.ok())
    return status;
  std::uint64_t t = 0;
  return mesh.visitTriangles([&](VertexId a, VertexId b, VertexId c) {
    check.ok(a, b, c, t++);
    if (ascii) {
      out.text("3 ").number(std::uint64_t{a}).text(" ").number(std::uint64_t{b});
      out.text(" ").number(std::uint64_t{c}).text("\n");
      return;
    }
    out.binary(static_cast<std::uint8_t>(3));
    out.binary(static_cast<std::int32_t>(a));
    out.binary(static_cast<std::int32_t>(b));
    out.binary(static_cast<std::int32_t>(c));
  });
}

template <typename Source>
Status writeObj(Emitter& out, const Source& mesh, const std::string& comment,
                TriangleIdCheck& check)
{
  out.text("# ").text(comment).text("\n# ");
  if (mesh.hasInsertedFlags()) {
    std::uint64_t count = 0;
    const Status status =
        mesh.visitVertices([&](double, double, double, bool f) { count += f; });
    if (!status.ok())
      return status;
    out.number(count).text(" inserted vertices (hole filling)\n# ");
  }
  out.number(mesh.vertexCount()).text(" vertices, ");
  out.number(mesh.triangleCount()).text(" triangles\n");
  const Status status = mesh.visitVertices([&](double x, double y, double z, bool) {
    out.text("v ").number(x).text(" ").number(y).text(" ");
    out.number(z).text("\n");
  });
  if (!status.ok())
    return status;
  std::uint64_t t = 0;
  return mesh.visitTriangles([&](VertexId a, VertexId b, VertexId c) {
    check.ok(a, b, c, t++);
    out.text("f ").number(std::uint64_t{a} + 1).text(" ");
    out.number(std::uint64_t{b} + 1).text(" ").number(std::uint64_t{c} + 1);
    out.text("\n");
  });
}

template <typename Source>
Status writeVtk(Emitter& out, const Source& mesh, bool dbl, const std::string& comment,
                TriangleIdCheck& check)
{
  const std::uint64_t nt = mesh.triangleCount();
  out.text("# vtk DataFile Version 3.0\n").text(comment.substr(0, 255));
  out.text("\nASCII\nDATASET POLYDATA\nPOINTS ");
  out.number(mesh.vertexCount());
  out.text(dbl ? " double\n" : " float\n");
  Status status = mesh.visitVertices([&](double x, double y, double z, bool) {
    out.number(x).text(" ").number(y).text(" ");
    out.number(z).text("\n");
  });
  if (!status.ok())
    return status;
  out.text("POLYGONS ").number(nt).text(" ").number(4 * nt).text("\n");
  std::uint64_t t = 0;
  status = mesh.visitTriangles([&](VertexId a, VertexId b, VertexId c) {
    check.ok(a, b, c, t++);
    out.text("3 ").number(std::uint64_t{a}).text(" ").number(std::uint64_t{b});
    out.text(" ").number(std::uint64_t{c}).text("\n");
  });
  if (!status.ok() || !mesh.hasInsertedFlags())
    return status;
  out.text("POINT_DATA ").number(mesh.vertexCount());
  out.text("\nSCALARS inserted unsigned_char 1\nLOOKUP_TABLE default\n");
  return mesh.visitVertices(
      [&](double, double, double, bool f) { out.text(f ? "1\n" : "0\n"); });
}

/// The writers' view of a MeshSource: one call through its std::function per element.
class StreamView {
 public:
  explicit StreamView(const MeshSource& mesh)
      : mesh_(mesh)
  {}
  std::uint64_t vertexCount() const { return mesh_.vertexCount(); }
  std::uint64_t triangleCount() const { return mesh_.triangleCount(); }
  bool hasInsertedFlags() const { return mesh_.hasInsertedFlags(); }
  template <typename Visit>
  Status visitVertices(Visit&& visit) const
  {
    return mesh_.forEachVertex(visit);
  }
  template <typename Visit>
  Status visitTriangles(Visit&& visit) const
  {
    return mesh_.forEachTriangle(visit);
  }

 private:
  const MeshSource& mesh_;
};

/// The writers' view of a TriangleMesh (and its optional inserted flags): the same
/// visits as StreamView, inlined into plain loops over the arrays.
class ArrayView {
 public:
  ArrayView(const TriangleMesh& mesh, const std::vector<std::uint8_t>* flags)
      : mesh_(mesh)
      , flags_(flags)
  {}
  std::uint64_t vertexCount() const { return mesh_.vertexCount(); }
  std::uint64_t triangleCount() const { return mesh_.triangleCount(); }
  bool hasInsertedFlags() const { return flags_ != nullptr; }
  template <typename Visit>
  Status visitVertices(Visit&& visit) const
  {
    for (std::size_t v = 0; v < mesh_.vertexCount(); ++v)
      visit(mesh_.xy[v].x, mesh_.xy[v].y, mesh_.z[v], flags_ && (*flags_)[v] != 0);
    return Status::success();
  }
  template <typename Visit>
  Status visitTriangles(Visit&& visit) const
  {
    const VertexId* t = mesh_.triangles.data();
    for (std::size_t k = 0; k < mesh_.triangleCount(); ++k, t += 3)
      visit(t[0], t[1], t[2]);
    return Status::success();
  }

 private:
  const TriangleMesh& mesh_;
  const std::vector<std::uint8_t>* flags_;
};

Status checkMesh(const std::string& path, const TriangleMesh& mesh)
{
  const auto bad = [&](const std::string& why) {
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "cannot write " + quoted(path) + ": " + why);
  };
  if (mesh.xy.size() != mesh.z.size())
    return bad("the mesh has " + std::to_string(mesh.xy.size()) + " xy but " +
               std::to_string(mesh.z.size()) + " z values");
  if (mesh.triangles.size() % 3 != 0)
    return bad("the triangle array length " + std::to_string(mesh.triangles.size()) +
               " is not a multiple of 3");
  if (mesh.vertexCount() >
      static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    return bad(std::to_string(mesh.vertexCount()) +
               " vertices do not fit the 32-bit signed indices of the file");
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    if (mesh.triangles[i] >= mesh.vertexCount())
      return bad("triangle " + std::to_string(i / 3) + " uses vertex " +
                 std::to_string(mesh.triangles[i]) + " of " +
                 std::to_string(mesh.vertexCount()));
  return Status::success();
}

/// Writes a mesh seen through StreamView or ArrayView (the same bytes for the same
/// mesh): the format's header and elements, then the atomic commit.
template <typename View>
Status writeView(const std::string& path, const View& mesh, MeshFileFormat format,
                 bool dbl, const MeshWriteOptions& options, MeshWriteInfo* info)
{
  Status status = Status::success();
  const bool ascii = options.ascii || format != MeshFileFormat::PLY;
  const std::string comment = oneLine(options.comment);
  TriangleIdCheck check;
  check.vertex_count = mesh.vertexCount();
  try {
    AtomicFile file(path);
    status = file.open();
    if (!status.ok())
      return status;
    Emitter out(file);
    switch (format) {
    case MeshFileFormat::PLY:
      status = writePly(out, mesh, ascii, dbl, comment, check);
      break;
    case MeshFileFormat::OBJ:
      status = writeObj(out, mesh, comment, check);
      break;
    case MeshFileFormat::VTK:
      status = writeVtk(out, mesh, dbl, comment, check);
      break;
    }
    if (!status.ok())
      return status; // the AtomicFile removes its temp file
    out.finish();
    if (!check.error.empty())
      return Status::error(StatusCode::INVALID_PARAMETER,
                           "cannot write " + quoted(path) + ": " + check.error);
    status = file.commit();
    if (!status.ok())
      return status;
    if (info != nullptr)
      *info = {format, ascii, format == MeshFileFormat::OBJ ? true : dbl, file.bytes()};
  } catch (const std::bad_alloc&) {
    return Status::error(StatusCode::IO_ERROR,
                         "cannot write " + quoted(path) + ": out of memory");
  }
  return Status::success();
}

} // namespace

const char* meshFileFormatName(MeshFileFormat format)
{
  switch (format) {
  case MeshFileFormat::PLY:
    return "PLY";
  case MeshFileFormat::OBJ:
    return "OBJ";
  case MeshFileFormat::VTK:
    return "VTK";
  }
  return "unknown";
}

Status meshFileFormatFromPath(const std::string& path, MeshFileFormat& format)
{
  const std::size_t slash = path.rfind('/');
  const std::size_t dot = path.rfind('.');
  const std::string ext =
      (dot == std::string::npos || (slash != std::string::npos && dot < slash))
          ? std::string()
          : lowerCase(path.substr(dot));
  if (ext == ".ply")
    format = MeshFileFormat::PLY;
  else if (ext == ".obj")
    format = MeshFileFormat::OBJ;
  else if (ext == ".vtk")
    format = MeshFileFormat::VTK;
  else
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "unknown output extension " +
                             quoted(ext.empty() ? std::string("(none)") : ext) +
                             " in " + quoted(path) + " (use .ply, .obj or .vtk)");
  // "dir/.ply" has an extension but no name: writing it would hide the mesh.
  if (dot == (slash == std::string::npos ? 0 : slash + 1))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "output path " + quoted(path) + " has no file name");
  return Status::success();
}

bool verticesExactInFloat(const TriangleMesh& mesh)
{
  const auto exact = [](double v) {
    // The range check first: converting an out-of-range double to float is undefined.
    return std::fabs(v) <= std::numeric_limits<float>::max() &&
           static_cast<double>(static_cast<float>(v)) == v;
  };
  for (const Point2& p : mesh.xy)
    if (!exact(p.x) || !exact(p.y))
      return false;
  for (double v : mesh.z)
    if (!exact(v))
      return false;
  return true;
}

Status writeMesh(const std::string& path, const TriangleMesh& mesh,
                 const MeshWriteOptions& options, MeshWriteInfo* info)
{
  MeshFileFormat format = MeshFileFormat::PLY;
  Status status = meshFileFormatFromPath(path, format);
  if (!status.ok())
    return status;
  status = checkMesh(path, mesh);
  if (!status.ok())
    return status;
  const std::vector<std::uint8_t>* flags = options.inserted;
  if (flags != nullptr && flags->size() != mesh.vertexCount())
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "cannot write " + quoted(path) + ": " +
                             std::to_string(flags->size()) + " inserted flags for " +
                             std::to_string(mesh.vertexCount()) + " vertices");
  return writeView(path, ArrayView(mesh, flags), format,
                   options.force_double || !verticesExactInFloat(mesh), options, info);
}

Status writeMesh(const std::string& path, const MeshSource& mesh,
                 const MeshWriteOptions& options, MeshWriteInfo* info)
{
  MeshFileFormat format = MeshFileFormat::PLY;
  const Status status = meshFileFormatFromPath(path, format);
  if (!status.ok())
    return status;
  if (mesh.vertexCount() >
      static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
    return Status::error(
        StatusCode::INVALID_PARAMETER,
        "cannot write " + quoted(path) + ": " + std::to_string(mesh.vertexCount()) +
            " vertices do not fit the 32-bit signed indices of the file");
  return writeView(path, StreamView(mesh), format,
                   options.force_double || !mesh.exactInFloat(), options, info);
}

} // namespace pcl_vts
