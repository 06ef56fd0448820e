// The mesh writer byte for byte: a two-triangle mesh in binary and ASCII PLY (float
// and double vertices, with and without inserted flags), OBJ and VTK, compared with
// files written out here by hand; the streamed (MeshSource) overload writes the same
// bytes as the TriangleMesh one; bad ids and unknown extensions leave no file.
#include <pcl_vts/io/mesh_writer.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace pcl_vts {
namespace {

namespace fs = std::filesystem;

class MeshWriter : public ::testing::Test {
 protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/mesh_writer_test.XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  /// The file's bytes, after checking that nothing else is in the folder.
  std::string bytes(const std::string& name) const
  {
    std::ifstream in(path(name), std::ios::binary);
    EXPECT_TRUE(in.good()) << name;
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  fs::path dir_;
};

/// Four vertices, two CCW triangles; every coordinate exact in float.
TriangleMesh tinyMesh()
{
  TriangleMesh m;
  m.xy = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  m.z = {1.0, 2.5, -0.5, 0.0};
  m.triangles = {0, 1, 2, 2, 1, 3};
  return m;
}

std::string raw(std::initializer_list<int> values)
{
  std::string s;
  for (const int v : values)
    s.push_back(static_cast<char>(v));
  return s;
}

// Little-endian floats and int32s of the tiny mesh.
const std::string F0 = raw({0, 0, 0, 0});
const std::string F1 = raw({0, 0, 0x80, 0x3f});
const std::string F2_5 = raw({0, 0, 0x20, 0x40});
const std::string FM0_5 = raw({0, 0, 0, 0xbf});
std::string i32(int v)
{
  return raw({v & 0xff, (v >> 8) & 0xff, (v >> 16) & 0xff, (v >> 24) & 0xff});
}

const std::string PLY_FACES_HEADER =
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n";

TEST_F(MeshWriter, BinaryPlyFloatBytes)
{
  MeshWriteOptions options;
  options.comment = "t";
  MeshWriteInfo info;
  ASSERT_TRUE(writeMesh(path("m.ply"), tinyMesh(), options, &info).ok());
  const std::string expected =
      "ply\nformat binary_little_endian 1.0\ncomment t\nelement vertex 4\n"
      "property float x\nproperty float y\nproperty float z\n" +
      PLY_FACES_HEADER + F0 + F0 + F1 + F1 + F0 + F2_5 + F0 + F1 + FM0_5 + F1 + F1 +
      F0 + raw({3}) + i32(0) + i32(1) + i32(2) + raw({3}) + i32(2) + i32(1) + i32(3);
  EXPECT_EQ(bytes("m.ply"), expected);
  EXPECT_EQ(info.format, MeshFileFormat::PLY);
  EXPECT_FALSE(info.ascii);
  EXPECT_FALSE(info.double_vertices);
  EXPECT_EQ(info.bytes, expected.size());
}

TEST_F(MeshWriter, BinaryPlyTurnsDoubleWhenFloatWouldRound)
{
  TriangleMesh mesh = tinyMesh();
  mesh.z[3] = 0.1; // not a float
  MeshWriteOptions options;
  options.comment = "t";
  MeshWriteInfo info;
  ASSERT_TRUE(writeMesh(path("m.ply"), mesh, options, &info).ok());
  const std::string D0 = raw({0, 0, 0, 0, 0, 0, 0, 0});
  const std::string D1 = raw({0, 0, 0, 0, 0, 0, 0xf0, 0x3f});
  const std::string D2_5 = raw({0, 0, 0, 0, 0, 0, 0x04, 0x40});
  const std::string DM0_5 = raw({0, 0, 0, 0, 0, 0, 0xe0, 0xbf});
  const std::string D0_1 = raw({0x9a, 0x99, 0x99, 0x99, 0x99, 0x99, 0xb9, 0x3f});
  const std::string expected =
      "ply\nformat binary_little_endian 1.0\ncomment t\nelement vertex 4\n"
      "property double x\nproperty double y\nproperty double z\n" +
      PLY_FACES_HEADER + D0 + D0 + D1 + D1 + D0 + D2_5 + D0 + D1 + DM0_5 + D1 + D1 +
      D0_1 + raw({3}) + i32(0) + i32(1) + i32(2) + raw({3}) + i32(2) + i32(1) + i32(3);
  EXPECT_EQ(bytes("m.ply"), expected);
  EXPECT_TRUE(info.double_vertices);
}

TEST_F(MeshWriter, AsciiPlyWithInsertedFlags)
{
  const std::vector<std::uint8_t> inserted = {0, 0, 1, 0};
  MeshWriteOptions options;
  options.ascii = true;
  options.comment = "two\nlines"; // one header line
  options.inserted = &inserted;
  ASSERT_TRUE(writeMesh(path("m.ply"), tinyMesh(), options).ok());
  EXPECT_EQ(bytes("m.ply"),
            "ply\nformat ascii 1.0\ncomment two lines\nelement vertex 4\n"
            "property float x\nproperty float y\nproperty float z\n"
            "property uchar inserted\n" +
                PLY_FACES_HEADER +
                "0 0 1 0\n1 0 2.5 0\n0 1 -0.5 1\n1 1 0 0\n"
                "3 0 1 2\n3 2 1 3\n");
}

TEST_F(MeshWriter, ObjBytes)
{
  TriangleMesh mesh = tinyMesh();
  mesh.z[3] = 0.1;
  MeshWriteOptions options;
  options.comment = "t";
  MeshWriteInfo info;
  ASSERT_TRUE(writeMesh(path("m.OBJ"), mesh, options, &info).ok());
  EXPECT_EQ(bytes("m.OBJ"), "# t\n# 4 vertices, 2 triangles\n"
                            "v 0 0 1\nv 1 0 2.5\nv 0 1 -0.5\nv 1 1 0.1\n"
                            "f 1 2 3\nf 3 2 4\n");
  EXPECT_EQ(info.format, MeshFileFormat::OBJ);
  EXPECT_TRUE(info.ascii);
  const std::vector<std::uint8_t> inserted = {1, 0, 1, 0};
  options.inserted = &inserted;
  ASSERT_TRUE(writeMesh(path("f.obj"), mesh, options).ok());
  EXPECT_EQ(bytes("f.obj"), "# t\n# 2 inserted vertices (hole filling)\n"
                            "# 4 vertices, 2 triangles\n"
                            "v 0 0 1\nv 1 0 2.5\nv 0 1 -0.5\nv 1 1 0.1\n"
                            "f 1 2 3\nf 3 2 4\n");
}

TEST_F(MeshWriter, VtkBytes)
{
  MeshWriteOptions options;
  options.comment = "t";
  ASSERT_TRUE(writeMesh(path("m.vtk"), tinyMesh(), options).ok());
  const std::string body = "0 0 1\n1 0 2.5\n0 1 -0.5\n1 1 0\n"
                           "POLYGONS 2 8\n3 0 1 2\n3 2 1 3\n";
  EXPECT_EQ(bytes("m.vtk"), "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n"
                            "POINTS 4 float\n" +
                                body);
  const std::vector<std::uint8_t> inserted = {0, 1, 0, 0};
  options.inserted = &inserted;
  options.force_double = true;
  ASSERT_TRUE(writeMesh(path("f.vtk"), tinyMesh(), options).ok());
  EXPECT_EQ(bytes("f.vtk"), "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n"
                            "POINTS 4 double\n" +
                                body +
                                "POINT_DATA 4\nSCALARS inserted unsigned_char 1\n"
                                "LOOKUP_TABLE default\n0\n1\n0\n0\n");
}

/// The tiny mesh handed out one element at a time, as the tiled path does.
class StreamedMesh : public MeshSource {
 public:
  StreamedMesh(const TriangleMesh& mesh, const std::vector<std::uint8_t>* flags)
      : mesh_(mesh)
      , flags_(flags)
  {}
  std::uint64_t vertexCount() const override { return mesh_.vertexCount(); }
  std::uint64_t triangleCount() const override { return mesh_.triangleCount(); }
  bool exactInFloat() const override { return verticesExactInFloat(mesh_); }
  bool hasInsertedFlags() const override { return flags_ != nullptr; }
  Status forEachVertex(const VertexVisit& visit) const override
  {
    for (std::size_t v = 0; v < mesh_.vertexCount(); ++v)
      visit(mesh_.xy[v].x, mesh_.xy[v].y, mesh_.z[v], flags_ && (*flags_)[v]);
    return Status::success();
  }
  Status forEachTriangle(const TriangleVisit& visit) const override
  {
    for (std::size_t t = 0; t < mesh_.triangleCount(); ++t)
      visit(mesh_.triangles[3 * t], mesh_.triangles[3 * t + 1],
            mesh_.triangles[3 * t + 2]);
    return Status::success();
  }

 private:
  const TriangleMesh& mesh_;
  const std::vector<std::uint8_t>* flags_;
};

TEST_F(MeshWriter, StreamedOverloadWritesTheSameBytes)
{
  TriangleMesh exact = tinyMesh();
  TriangleMesh rounding = tinyMesh();
  rounding.xy[1].x = 1.0 / 3.0;
  const std::vector<std::uint8_t> inserted = {0, 1, 1, 0};
  for (const TriangleMesh* mesh : {&exact, &rounding})
    for (const std::vector<std::uint8_t>* flags :
         {static_cast<const std::vector<std::uint8_t>*>(nullptr), &inserted})
      for (const bool ascii : {false, true})
        for (const std::string ext : {".ply", ".obj", ".vtk"}) {
          SCOPED_TRACE(ext + (ascii ? " ascii" : "") + (flags ? " flags" : "") +
                       (mesh == &exact ? " float" : " double"));
          MeshWriteOptions options;
          options.ascii = ascii;
          options.inserted = flags;
          MeshWriteInfo a, b;
          ASSERT_TRUE(writeMesh(path("a" + ext), *mesh, options, &a).ok());
          options.inserted = nullptr;
          ASSERT_TRUE(
              writeMesh(path("b" + ext), StreamedMesh(*mesh, flags), options, &b).ok());
          EXPECT_EQ(bytes("a" + ext), bytes("b" + ext));
          EXPECT_EQ(a.bytes, b.bytes);
          EXPECT_EQ(a.double_vertices, b.double_vertices);
        }
}

TEST_F(MeshWriter, BadIdsAndExtensionsLeaveNoFile)
{
  TriangleMesh mesh = tinyMesh();
  mesh.triangles[5] = 4;
  Status s = writeMesh(path("m.ply"), StreamedMesh(mesh, nullptr), MeshWriteOptions{});
  EXPECT_EQ(s.code, StatusCode::INVALID_PARAMETER);
  EXPECT_NE(s.message.find("triangle 1 uses vertex 4 of 4"), std::string::npos)
      << s.message;
  s = writeMesh(path("m.stl"), tinyMesh(), MeshWriteOptions{});
  EXPECT_EQ(s.code, StatusCode::INVALID_PARAMETER);
  EXPECT_TRUE(fs::is_empty(dir_)) << "a file or temp file was left";
}

} // namespace
} // namespace pcl_vts
