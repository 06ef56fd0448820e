// ASCII grid, XYZ text and PLY point readers and the loader that picks among them:
// small files written here with known values (every cell centre, every PLY scalar
// type and byte order, header/comment/separator variants), each bad input an error
// naming the file (never a silent 0 or a crash); the real DEMs of ../shared/data
// checked against the independent test-side grid reader (tests/support/asc_reader.h).
#include "support/asc_reader.h"
#include "support/temp_folder_test.h"

#include <pcl_vts/io/asc_grid_reader.h>
#include <pcl_vts/io/ply_point_reader.h>
#include <pcl_vts/io/point_cloud_loader.h>
#include <pcl_vts/io/xyz_text_reader.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using pcl_vts::StatusCode;

using PointReaders = pcl_vts::test::TempFolderTest;

struct BadCase {
  std::string bytes;
  StatusCode code;
  std::string words; ///< expected in the message
};

void expectError(const pcl_vts::Status& s, StatusCode code, const std::string& words,
                 const std::string& path, const std::vector<double>& xyz)
{
  EXPECT_EQ(s.code, code) << s.toString();
  EXPECT_NE(s.message.find(words), std::string::npos)
      << "expected '" << words << "' in: " << s.message;
  EXPECT_NE(s.message.find(path), std::string::npos) << s.message;
  EXPECT_EQ(s.message.find('\n'), std::string::npos) << s.message;
  EXPECT_TRUE(xyz.empty());
}

/// Writes each case to folder/name; read must fail with its code and words.
template <typename Info>
void expectEachFails(const PointReaders& folder, const std::string& name,
                     const std::vector<BadCase>& cases,
                     pcl_vts::Status (*read)(const std::string&, std::vector<double>&,
                                             Info&))
{
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.bytes);
    const std::string path = folder.write(name, c.bytes);
    std::vector<double> xyz;
    Info info;
    expectError(read(path, xyz, info), c.code, c.words, path, xyz);
  }
}

// ---- ESRI ASCII grid

TEST_F(PointReaders, AscCornerGridGivesCellCentresAndSkipsNodata)
{
  const std::string path = write("g.asc", "ncols 3\nNROWS 2\nxllcorner 500000.5\n"
                                          "yllcorner 5000000\ncellsize 2\n"
                                          "NODATA_value -9999\n1 2 -9999\n4 5\n6.5\n");
  std::vector<double> xyz;
  pcl_vts::AscGridInfo info;
  ASSERT_TRUE(pcl_vts::readAscGrid(path, xyz, info).ok());
  EXPECT_EQ(info.nodata_cells, 1u);
  const std::vector<double> expected = {
      500001.5, 5000003, 1, 500003.5, 5000003, 2, // top row (r = 0)
      500001.5, 5000001, 4, 500003.5, 5000001, 5, 500005.5, 5000001, 6.5};
  EXPECT_EQ(xyz, expected);
}

TEST_F(PointReaders, AscCentreRegisteredGridIsNotShiftedByHalfACell)
{
  const std::string path =
      write("c.asc", "ncols 2\nnrows 2\nxllcenter 10\nyllcenter 20\ncellsize 1\n"
                     "1 2\n3 4\n");
  std::vector<double> xyz;
  pcl_vts::AscGridInfo info;
  ASSERT_TRUE(pcl_vts::readAscGrid(path, xyz, info).ok());
  EXPECT_TRUE(info.centre_registered);
  const std::vector<double> expected = {10, 21, 1, 11, 21, 2, 10, 20, 3, 11, 20, 4};
  EXPECT_EQ(xyz, expected);
}

TEST_F(PointReaders, AscBadInputsAreErrors)
{
  const std::string head = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
  const std::vector<BadCase> cases = {
      {"", StatusCode::IO_ERROR, "empty (0 bytes)"},
      {"hello world\n1 2 3\n", StatusCode::IO_ERROR, "not an ESRI ASCII grid"},
      {head, StatusCode::IO_ERROR, "truncated"},
      {head + "1 2 3\n", StatusCode::IO_ERROR, "truncated: 3 values"},
      {head + "1 2 3 4 5\n", StatusCode::IO_ERROR, "more values than"},
      {head + "1 2 x3 4\n", StatusCode::IO_ERROR, "'x3' is not a number"},
      {"ncols 2\nnrows 2\nxllcorner 0\ncellsize 1\n1 2 3 4\n", StatusCode::IO_ERROR,
       "yllcorner"},
      {"ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize -1\n1 2 3 4\n",
       StatusCode::IO_ERROR, "must be finite and > 0"},
      {"ncols 2.5\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3 4\n",
       StatusCode::IO_ERROR, "ncols 2.5"},
      {"ncols 100000\nnrows 100000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n",
       StatusCode::IO_ERROR, "100000 x 100000"},
      {head + "NODATA_value 7\n", StatusCode::IO_ERROR, "truncated"},
      {"ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\nnodata_value 7\n7 7\n",
       StatusCode::EMPTY_INPUT, "all 2 cells are NODATA"},
  };
  expectEachFails(*this, "bad.asc", cases, &pcl_vts::readAscGrid);
}

TEST(PointReadersSharedData, EveryDemMatchesTheIndependentGridReader)
{
  const std::string dir = std::string(PCL_VTS_SHARED_DATA_DIR) + "/dem";
  if (!fs::exists(dir))
    GTEST_SKIP() << "shared data not found at " << dir;
  // Valid cells from ../shared/data/README.md.
  const std::vector<std::pair<const char*, std::size_t>> files = {
      {"landlab/west_bijou_gully.asc", 1088},
      {"landlab/hugo_site.asc", 2152},
      {"landlab/zSW3.asc", 100448},
      {"landlab/pre_runout_DEM.asc", 9638},
      {"landlab/SRTMGL3_boulder_40.09_-105.55.asc", 34560},
      {"topotoolbox/exampleDEM_orkhon.asc", 17640},
      {"pysheds/dem.derived.asc", 131753},
      {"topotoolbox/srtm_bigtujunga30m_utm11.derived.asc", 769671}};
  for (const auto& [name, valid] : files) {
    SCOPED_TRACE(name);
    const std::string path = dir + "/" + name;
    std::vector<double> xyz;
    pcl_vts::AscGridInfo info;
    const pcl_vts::Status s = pcl_vts::readAscGrid(path, xyz, info);
    ASSERT_TRUE(s.ok()) << s.toString();
    EXPECT_EQ(info.points, valid);
    pcl_vts::test::AsciiGrid oracle;
    std::string why;
    ASSERT_TRUE(pcl_vts::test::readAsciiGrid(path, oracle, &why)) << why;
    EXPECT_EQ(info.ncols * info.nrows - info.nodata_cells, oracle.xyz.size() / 3);
    ASSERT_EQ(xyz.size(), oracle.xyz.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < xyz.size(); ++i)
      differ += std::abs(xyz[i] - oracle.xyz[i]) > 1e-9 * std::abs(oracle.xyz[i]);
    EXPECT_EQ(differ, 0u);
  }
}

// ---- XYZ text

TEST_F(PointReaders, XyzTextVariantsReadAlike)
{
  const std::vector<double> expected = {500000.001, 5000000.002, 12.5,
                                        500001.25,  5000001,     -3e-2};
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"a.xyz", "500000.001 5000000.002 12.5\n500001.25\t5000001  -3e-2\n"},
      {"b.csv", "x,y,z,intensity\n500000.001,5000000.002,12.5,7\n"
                "500001.25, 5000001, -3e-2, red\n"},
      {"bom.xyz", "\xEF\xBB\xBF"
                  "500000.001 5000000.002 12.5\n500001.25 5000001 -3e-2\n"},
      {"c.txt", "# exported\r\n500000.001;5000000.002;12.5\r\n\r\n"
                "// comment\r\n+500001.25;5000001;-3e-2;\r\n"},
      {"d.csv", "\"id\",\"Z\",\"X\",\"Y\"\n1,12.5,500000.001,5000000.002\n"
                "2,-3e-2,500001.25,5000001"},
  };
  for (const auto& [name, bytes] : cases) {
    SCOPED_TRACE(name);
    std::vector<double> xyz;
    pcl_vts::XyzTextInfo info;
    const pcl_vts::Status s = pcl_vts::readXyzText(write(name, bytes), xyz, info);
    ASSERT_TRUE(s.ok()) << s.toString();
    EXPECT_EQ(xyz, expected);
  }
}

TEST_F(PointReaders, XyzTextBadInputsAreErrors)
{
  const std::vector<BadCase> cases = {
      {"", StatusCode::IO_ERROR, "empty (0 bytes)"},
      {"x y z\n", StatusCode::EMPTY_INPUT, "header line only"},
      {"# nothing\n\n", StatusCode::EMPTY_INPUT, "no data line"},
      {"1 2 3\n4 5 6O\n", StatusCode::IO_ERROR, "line 2: z value '6O' is not a number"},
      {"1 2 3\n4 5\n", StatusCode::IO_ERROR, "line 2 has 2 value(s), 3 needed"},
      {"1 2\n", StatusCode::IO_ERROR, "line 1 has 2 value(s)"},
      {"1,,2,3\n", StatusCode::IO_ERROR, "empty value"},
      {"x y z\n1 2 3\nx y z\n", StatusCode::IO_ERROR, "line 3: x value 'x'"},
      {"1 2 x\n4 5 6\n", StatusCode::IO_ERROR, "line 1: z value 'x' is not a number"},
      {"\xEF\xBB\xBF"
       "1 2 3\n4 5 6O\n",
       StatusCode::IO_ERROR, "line 2: z value '6O'"},
      {std::string("LASF\0\0\0", 7), StatusCode::IO_ERROR, "not a text file"},
  };
  expectEachFails(*this, "bad.xyz", cases, &pcl_vts::readXyzText);
}

/// What a streaming reader handed over: the points in order, in how many chunks.
struct Streamed {
  std::vector<double> xyz;
  std::size_t chunks = 0;
  pcl_vts::Status status;
};

/// Reads path with a chunked reader (readXyzTextChunks, ...), each chunk checked to
/// hold at most chunk_points points.
template <typename Read, typename Info>
Streamed readInChunks(Read read, const std::string& path, std::size_t chunk_points,
                      Info& info)
{
  Streamed out;
  out.status = read(
      path, chunk_points,
      [&](const double* xyz, std::size_t n) {
        EXPECT_LE(n, chunk_points);
        out.xyz.insert(out.xyz.end(), xyz, xyz + 3 * n);
        ++out.chunks;
        return pcl_vts::Status::success();
      },
      info);
  return out;
}

TEST_F(PointReaders, XyzTextStreamedInChunksEqualsTheWholeRead)
{
  // A header in another column order, comments, CRLF, blank lines: every chunk size
  // gives the points of the whole read, in order, and the same info.
  std::string text = "# survey\r\nid;Z;X;Y\r\n";
  for (int i = 0; i < 1000; ++i) {
    text += std::to_string(i) + ";" + std::to_string(100 + i % 17) + ".25;" +
            std::to_string(500000 + i) + ".5;" + std::to_string(4100000 + 3 * i) +
            "\r\n";
    if (i % 97 == 0)
      text += "\r\n// note\r\n";
  }
  const std::string path = write("s.csv", text);
  std::vector<double> whole;
  pcl_vts::XyzTextInfo whole_info;
  ASSERT_TRUE(pcl_vts::readXyzText(path, whole, whole_info).ok());
  ASSERT_EQ(whole.size(), 3000u);
  for (const std::size_t chunk :
       {std::size_t{1}, std::size_t{7}, std::size_t{1000}, std::size_t{1} << 20}) {
    SCOPED_TRACE(chunk);
    pcl_vts::XyzTextInfo info;
    const Streamed streamed =
        readInChunks(&pcl_vts::readXyzTextChunks, path, chunk, info);
    ASSERT_TRUE(streamed.status.ok()) << streamed.status.toString();
    EXPECT_EQ(streamed.xyz, whole);
    EXPECT_EQ(streamed.chunks, (1000 + chunk - 1) / chunk);
    EXPECT_EQ(info.points, 1000u);
    EXPECT_EQ(info.column, whole_info.column);
    EXPECT_EQ(info.header, whole_info.header);
  }
  // Errors: a bad line late in the file, binary bytes after text, a failing sink.
  const auto streamed = [&](const std::string& bytes, std::size_t chunk,
                            const pcl_vts::Status& answer =
                                pcl_vts::Status::success()) {
    pcl_vts::XyzTextInfo info;
    return pcl_vts::readXyzTextChunks(
        write("e.xyz", bytes), chunk,
        [&](const double*, std::size_t) { return answer; }, info);
  };
  pcl_vts::Status s = streamed("1 2 3\n4 5 6\n7 8 x\n", 1);
  EXPECT_EQ(s.code, StatusCode::IO_ERROR);
  EXPECT_NE(s.message.find("line 3: z value 'x'"), std::string::npos) << s.message;
  s = streamed(std::string("1 2 3\n4 5 6\n\0\1\2", 15), 1);
  EXPECT_EQ(s.code, StatusCode::IO_ERROR);
  EXPECT_NE(s.message.find("not a text file: byte 0 at offset 12"), std::string::npos)
      << s.message;
  s = streamed("1 2 3\n4 5 6\n", 1,
               pcl_vts::Status::error(StatusCode::IO_ERROR, "sink full"));
  EXPECT_EQ(s.message, "sink full");
  s = streamed("# only a comment\n", 4);
  EXPECT_EQ(s.code, StatusCode::EMPTY_INPUT);
}

TEST_F(PointReaders, AscGridStreamedInChunksEqualsTheWholeRead)
{
  // 37 x 23 cells, NODATA every 5th, values wrapping lines: every chunk size gives the
  // points of the whole read, in order; a grid with one value too many or too few
  // fails after or before the expected points went out.
  std::string text = "ncols 37\nnrows 23\nxllcenter 500000.5\nyllcorner 4100000\n"
                     "cellsize 2\nNODATA_value -9999\n";
  for (int i = 0; i < 37 * 23; ++i)
    text += (i % 5 == 0 ? std::string("-9999") : std::to_string(100 + i % 29) + ".5") +
            (i % 11 == 10 ? "\n" : " ");
  const std::string path = write("g.asc", text);
  std::vector<double> whole;
  pcl_vts::AscGridInfo whole_info;
  ASSERT_TRUE(pcl_vts::readAscGrid(path, whole, whole_info).ok());
  ASSERT_EQ(whole.size(), 3u * (37 * 23 - (37 * 23 + 4) / 5));
  for (const std::size_t chunk :
       {std::size_t{1}, std::size_t{50}, std::size_t{1} << 20}) {
    SCOPED_TRACE(chunk);
    pcl_vts::AscGridInfo info;
    const Streamed streamed =
        readInChunks(&pcl_vts::readAscGridChunks, path, chunk, info);
    ASSERT_TRUE(streamed.status.ok()) << streamed.status.toString();
    EXPECT_EQ(streamed.xyz, whole);
    EXPECT_EQ(info.points, whole_info.points);
    EXPECT_EQ(info.nodata_cells, whole_info.nodata_cells);
  }
  const auto streamedStatus = [&](const std::string& bytes) {
    pcl_vts::AscGridInfo info;
    return pcl_vts::readAscGridChunks(
        write("e.asc", bytes), 2,
        [](const double*, std::size_t) { return pcl_vts::Status::success(); }, info);
  };
  const std::string head = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
  pcl_vts::Status s = streamedStatus(head + "1 2 3 4 5\n");
  EXPECT_NE(s.message.find("more values than ncols x nrows"), std::string::npos)
      << s.message;
  s = streamedStatus(head + "1 2 3\n");
  EXPECT_NE(s.message.find("truncated"), std::string::npos) << s.message;
  s = streamedStatus(head + "1 2 x 4\n");
  EXPECT_NE(s.message.find("value 3 'x' is not a number"), std::string::npos)
      << s.message;
}

TEST_F(PointReaders, XyzTextNanAndInfPassThroughForThePipelineToDrop)
{
  std::vector<double> xyz;
  pcl_vts::XyzTextInfo info;
  ASSERT_TRUE(
      pcl_vts::readXyzText(write("n.xyz", "1 2 nan\ninf 2 3\n"), xyz, info).ok());
  ASSERT_EQ(xyz.size(), 6u);
  EXPECT_TRUE(std::isnan(xyz[2]));
  EXPECT_TRUE(std::isinf(xyz[3]));
}

// ---- PLY

template <typename T>
void appendValue(std::string& b, T v, bool big_endian)
{
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  if (big_endian)
    std::reverse(bytes, bytes + sizeof(T));
  b.append(bytes, sizeof(T));
}

TEST_F(PointReaders, PlyEveryScalarTypeAndByteOrder)
{
  const std::vector<std::array<double, 3>> points = {
      {1, 2, 3}, {100, -7, 12}, {-5, 120, 0}, {17, 33, 99}};
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"})
    for (const char* type : {"char", "uchar", "short", "ushort", "int", "uint", "float",
                             "double", "int32", "float64"}) {
      SCOPED_TRACE(std::string(format) + " " + type);
      const std::string t = type;
      const bool be = std::string(format) == "binary_big_endian";
      std::string b = std::string("ply\nformat ") + format +
                      " 1.0\ncomment made by a test\nelement vertex 4\n"
                      "property uchar flag\nproperty " +
                      t + " x\nproperty " + t + " y\nproperty " + t +
                      " z\nproperty list uchar int extra\nelement face 1\n"
                      "property list uchar int vertex_indices\nend_header\n";
      for (const auto& p : points) {
        const bool signed_ok = t != "uchar" && t != "ushort" && t != "uint";
        if (!signed_ok && (p[1] < 0 || p[0] < 0))
          continue;
        if (std::string(format) == "ascii") {
          b += "1 " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " +
               std::to_string(p[2]) + " 2 5 6\n";
          continue;
        }
        appendValue<std::uint8_t>(b, 1, be);
        for (double v : p) {
          if (t == "char")
            appendValue(b, static_cast<std::int8_t>(v), be);
          else if (t == "uchar")
            appendValue(b, static_cast<std::uint8_t>(v), be);
          else if (t == "short")
            appendValue(b, static_cast<std::int16_t>(v), be);
          else if (t == "ushort")
            appendValue(b, static_cast<std::uint16_t>(v), be);
          else if (t == "int" || t == "int32")
            appendValue(b, static_cast<std::int32_t>(v), be);
          else if (t == "uint")
            appendValue(b, static_cast<std::uint32_t>(v), be);
          else if (t == "float")
            appendValue(b, static_cast<float>(v), be);
          else
            appendValue(b, v, be);
        }
        appendValue<std::uint8_t>(b, 2, be);
        appendValue<std::int32_t>(b, 5, be);
        appendValue<std::int32_t>(b, 6, be);
      }
      std::vector<double> expected;
      for (const auto& p : points)
        if ((t != "uchar" && t != "ushort" && t != "uint") || (p[0] >= 0 && p[1] >= 0))
          expected.insert(expected.end(), p.begin(), p.end());
      const std::size_t n = expected.size() / 3;
      const std::size_t at = b.find("element vertex 4");
      b.replace(at, 16, "element vertex " + std::to_string(n));
      std::vector<double> xyz;
      pcl_vts::PlyPointInfo info;
      const pcl_vts::Status s = pcl_vts::readPlyPoints(write("p.ply", b), xyz, info);
      ASSERT_TRUE(s.ok()) << s.toString();
      EXPECT_EQ(xyz, expected);
      EXPECT_EQ(info.faces, 1u);
      EXPECT_EQ(info.xyz_types[0], t);
    }
}

TEST_F(PointReaders, PlyElementsBeforeTheVertexElementAreSkipped)
{
  std::string b = "ply\nformat binary_little_endian 1.0\nelement camera 2\n"
                  "property float a\nproperty list uchar short l\n"
                  "element vertex 2\nproperty double x\nproperty double y\n"
                  "property double z\nend_header\n";
  for (int k = 0; k < 2; ++k) {
    appendValue(b, 1.5f, false);
    appendValue<std::uint8_t>(b, 3, false);
    for (int j = 0; j < 3; ++j)
      appendValue<std::int16_t>(b, 9, false);
  }
  for (double v : {500000.001, 5000000.002, 7.0, 1.0, 2.0, 3.0})
    appendValue(b, v, false);
  std::vector<double> xyz;
  pcl_vts::PlyPointInfo info;
  ASSERT_TRUE(pcl_vts::readPlyPoints(write("c.ply", b), xyz, info).ok());
  EXPECT_EQ(xyz, (std::vector<double>{500000.001, 5000000.002, 7.0, 1.0, 2.0, 3.0}));
}

TEST_F(PointReaders, PlyStreamedInChunksEqualsTheWholeRead)
{
  // Binary with an element before the vertices and faces after them, and ascii:
  // every chunk size gives the whole read's vertices; a truncated body fails after
  // the vertices before it went out.
  std::string bin =
      "ply\nformat binary_little_endian 1.0\nelement camera 1\n"
      "property float a\nelement vertex 500\nproperty float nx\n"
      "property double x\nproperty double y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  appendValue(bin, 1.5f, false);
  std::string ascii = "ply\nformat ascii 1.0\nelement vertex 500\nproperty double x\n"
                      "property double y\nproperty double z\nend_header\n";
  for (int i = 0; i < 500; ++i) {
    appendValue(bin, 0.25f, false);
    appendValue(bin, 500000.0 + i, false);
    appendValue(bin, 4100000.5 + 2 * i, false);
    appendValue(bin, static_cast<float>(i % 7), false);
    ascii += std::to_string(500000 + i) + " " + std::to_string(4100000 + 2 * i) +
             ".5 " + std::to_string(i % 7) + "\n";
  }
  appendValue<std::uint8_t>(bin, 3, false);
  for (int v : {0, 1, 2})
    appendValue<std::int32_t>(bin, v, false);
  for (const auto& [name, bytes] :
       {std::pair{"b.ply", bin}, std::pair{"a.ply", ascii}}) {
    SCOPED_TRACE(name);
    const std::string path = write(name, bytes);
    std::vector<double> whole;
    pcl_vts::PlyPointInfo whole_info;
    ASSERT_TRUE(pcl_vts::readPlyPoints(path, whole, whole_info).ok());
    ASSERT_EQ(whole.size(), 1500u);
    for (const std::size_t chunk :
         {std::size_t{1}, std::size_t{33}, std::size_t{1} << 20}) {
      SCOPED_TRACE(chunk);
      pcl_vts::PlyPointInfo info;
      const Streamed streamed =
          readInChunks(&pcl_vts::readPlyPointChunks, path, chunk, info);
      ASSERT_TRUE(streamed.status.ok()) << streamed.status.toString();
      EXPECT_EQ(streamed.xyz, whole);
      EXPECT_EQ(info.vertices, 500u);
      EXPECT_EQ(info.faces, whole_info.faces);
    }
  }
  std::size_t got = 0;
  pcl_vts::PlyPointInfo info;
  const pcl_vts::Status s = pcl_vts::readPlyPointChunks(
      write("t.ply", ascii.substr(0, ascii.size() - 40)), 10,
      [&](const double*, std::size_t n) {
        got += n;
        return pcl_vts::Status::success();
      },
      info);
  EXPECT_EQ(s.code, StatusCode::IO_ERROR);
  EXPECT_NE(s.message.find("truncated"), std::string::npos) << s.message;
  EXPECT_GT(got, 0u);
}

TEST_F(PointReaders, PlyBadInputsAreErrors)
{
  const std::string head =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  const std::vector<BadCase> cases = {
      {"", StatusCode::IO_ERROR, "empty (0 bytes)"},
      {"PLY\nformat ascii 1.0\n", StatusCode::IO_ERROR, "no 'ply' magic"},
      {"ply\nformat ascii 1.0\nelement vertex 3\n", StatusCode::IO_ERROR,
       "no end_header"},
      {head, StatusCode::IO_ERROR, "truncated"},
      {head + std::string(20, '\0'), StatusCode::IO_ERROR, "truncated"},
      {"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
       "property float x\nproperty float y\nproperty float z\nend_header\n" +
           std::string(64, '\0'),
       StatusCode::IO_ERROR, "4000000000"},
      {"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n1 2 3\n4 5 six\n",
       StatusCode::IO_ERROR, "'six' is not a number"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "end_header\n1 2\n",
       StatusCode::IO_ERROR, "no scalar 'z'"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty half x\nend_header\n",
       StatusCode::IO_ERROR, "bad PLY header, line 4"},
      {"ply\nformat ascii 2.0 x\nend_header\n", StatusCode::IO_ERROR, "format"},
      {"ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int v\n"
       "end_header\n3 0 1 2\n",
       StatusCode::IO_ERROR, "no vertex element"},
      {"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n",
       StatusCode::EMPTY_INPUT, "0 vertices"},
  };
  expectEachFails(*this, "bad.ply", cases, &pcl_vts::readPlyPoints);
}

// ---- loader

TEST_F(PointReaders, LoaderChoosesByExtensionAnyCaseThenByContent)
{
  const std::string grid = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                           "1 2\n3 4\n";
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                          "property float y\nproperty float z\nend_header\n"
                          "0 0 1\n1 0 2\n0 1 3\n";
  struct Case {
    std::string name, bytes;
    pcl_vts::CloudFileFormat format;
    std::size_t kept;
  };
  const std::vector<Case> cases = {
      {"g.ASC", grid, pcl_vts::CloudFileFormat::ASC, 4},
      {"g.dem", grid, pcl_vts::CloudFileFormat::ASC, 4},
      {"p.Ply", ply, pcl_vts::CloudFileFormat::PLY, 3},
      {"p_no_extension", ply, pcl_vts::CloudFileFormat::PLY, 3},
      {"t.CSV", "1,2,3\n", pcl_vts::CloudFileFormat::XYZ, 1},
      {"t.TXT", "1 2 3\n4 5 6\n", pcl_vts::CloudFileFormat::XYZ, 2},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    std::vector<double> xyz;
    pcl_vts::CloudDescription d;
    const pcl_vts::Status s =
        pcl_vts::loadPointCloud(write(c.name, c.bytes), {}, xyz, d);
    ASSERT_TRUE(s.ok()) << s.toString();
    EXPECT_EQ(d.format, c.format);
    EXPECT_EQ(d.points_kept, c.kept);
    EXPECT_EQ(xyz.size(), 3 * c.kept);
  }
  std::vector<double> xyz;
  pcl_vts::CloudDescription d;
  const std::string odd = write("x.dat", "hello\n");
  expectError(pcl_vts::loadPointCloud(odd, {}, xyz, d), StatusCode::IO_ERROR,
              "unknown input format", odd, xyz);
  pcl_vts::CloudLoadOptions options;
  options.classes = {2};
  const std::string txt = write("c.txt", "1 2 3\n");
  const pcl_vts::Status s = pcl_vts::loadPointCloud(txt, options, xyz, d);
  expectError(s, StatusCode::INVALID_PARAMETER, "LAS input only", txt, xyz);
  // The library names its settings, not a tool's flags (the tool adds those).
  EXPECT_EQ(s.message.find("--"), std::string::npos) << s.message;
}

} // namespace
