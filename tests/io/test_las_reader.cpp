// LAS reader: synthetic files written here (every point format 0-10, LAS 1.0-1.4,
// extra bytes, 64-bit counts, filters) checked coordinate for coordinate against the
// integers the test wrote; every lying or cut header is an IO_ERROR naming the file,
// never a crash or a giant allocation; the real files of ../shared/data/las give the
// point and class counts listed in its README.
#include "support/temp_folder_test.h"

#include <pcl_vts/io/las_reader.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using pcl_vts::LasInfo;
using pcl_vts::LasReadOptions;
using pcl_vts::StatusCode;

constexpr std::size_t MIN_RECORD[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

struct LasPoint {
  std::int32_t x, y, z;
  std::uint8_t cls;
  std::uint8_t return_number = 1;
  std::uint8_t number_of_returns = 1;
};

struct LasSpec {
  int minor = 2;
  int format = 0;
  std::size_t extra_bytes = 0;
  std::array<double, 3> scale{0.01, 0.01, 0.001};
  std::array<double, 3> offset{500000.0, 5000000.0, 0.0};
  std::vector<LasPoint> points;
  std::vector<std::string> vlr_user_ids; ///< empty VLR payloads
  bool legacy_count = true;              ///< 1.4: also fill the 32-bit count
};

void put16(std::string& b, std::size_t at, std::uint16_t v)
{
  b[at] = static_cast<char>(v & 0xFF);
  b[at + 1] = static_cast<char>(v >> 8);
}

void put32(std::string& b, std::size_t at, std::uint32_t v)
{
  for (int k = 0; k < 4; ++k)
    b[at + k] = static_cast<char>((v >> (8 * k)) & 0xFF);
}

void put64(std::string& b, std::size_t at, std::uint64_t v)
{
  put32(b, at, static_cast<std::uint32_t>(v));
  put32(b, at + 4, static_cast<std::uint32_t>(v >> 32));
}

void putDouble(std::string& b, std::size_t at, double v)
{
  std::uint64_t u;
  std::memcpy(&u, &v, 8);
  put64(b, at, u);
}

/// A LAS file laid out as the specification says, written byte by byte here.
std::string makeLas(const LasSpec& s)
{
  const std::size_t header = s.minor == 4 ? 375 : s.minor == 3 ? 235 : 227;
  std::string b(header, '\0');
  std::memcpy(&b[0], "LASF", 4);
  b[24] = 1;
  b[25] = static_cast<char>(s.minor);
  std::memcpy(&b[26], "pcl_vts test", 12);
  put16(b, 94, static_cast<std::uint16_t>(header));
  put32(b, 100, static_cast<std::uint32_t>(s.vlr_user_ids.size()));
  for (const std::string& id : s.vlr_user_ids) {
    std::string vlr(54, '\0');
    std::memcpy(&vlr[2], id.data(), std::min<std::size_t>(id.size(), 16));
    b += vlr;
  }
  put32(b, 96, static_cast<std::uint32_t>(b.size()));
  b[104] = static_cast<char>(s.format);
  const std::size_t record = MIN_RECORD[s.format] + s.extra_bytes;
  put16(b, 105, static_cast<std::uint16_t>(record));
  if (s.minor < 4 || s.legacy_count)
    put32(b, 107, static_cast<std::uint32_t>(s.points.size()));
  if (s.minor == 4)
    put64(b, 247, s.points.size());
  for (int a = 0; a < 3; ++a) {
    putDouble(b, 131 + 8 * a, s.scale[a]);
    putDouble(b, 155 + 8 * a, s.offset[a]);
  }
  const bool extended = s.format >= 6;
  for (const LasPoint& p : s.points) {
    std::string r(record, '\xAB'); // junk in every byte the reader must not use
    put32(r, 0, static_cast<std::uint32_t>(p.x));
    put32(r, 4, static_cast<std::uint32_t>(p.y));
    put32(r, 8, static_cast<std::uint32_t>(p.z));
    if (extended) {
      r[14] = static_cast<char>(p.return_number | (p.number_of_returns << 4));
      r[15] = static_cast<char>(0xF0); // class flags, scanner channel: not the class
      r[16] = static_cast<char>(p.cls);
    } else {
      r[14] = static_cast<char>(p.return_number | (p.number_of_returns << 3) | 0xC0);
      r[15] = static_cast<char>((p.cls & 0x1F) | 0xE0); // synthetic/keypoint/withheld
    }
    b += r;
  }
  return b;
}

std::vector<LasPoint> somePoints(int n, bool extended_classes)
{
  std::vector<LasPoint> points;
  for (int i = 0; i < n; ++i) {
    LasPoint p{};
    p.x = -2000000000 + 123457 * i;
    p.y = 1999999999 - 98765 * i;
    p.z = (i % 7) * 1000 - 3000;
    p.cls = static_cast<std::uint8_t>(extended_classes ? (i * 37) % 256 : i % 32);
    p.number_of_returns = static_cast<std::uint8_t>(1 + i % 3);
    p.return_number = static_cast<std::uint8_t>(1 + (i / 3) % p.number_of_returns);
    points.push_back(p);
  }
  return points;
}

class LasReader : public pcl_vts::test::TempFolderTest {
 protected:
  /// Reads bytes written to a file; expects the code and words in the message.
  void expectError(const std::string& bytes, StatusCode code, const std::string& words,
                   const LasReadOptions& options = {}) const
  {
    const std::string path = write("bad.las", bytes);
    std::vector<double> xyz = {1.0};
    LasInfo info;
    const pcl_vts::Status s = pcl_vts::readLasCloud(path, options, xyz, info);
    EXPECT_EQ(s.code, code) << s.toString();
    EXPECT_NE(s.message.find(words), std::string::npos)
        << "expected '" << words << "' in: " << s.message;
    EXPECT_NE(s.message.find(path), std::string::npos) << "names the file";
    EXPECT_EQ(s.message.find('\n'), std::string::npos) << "one line";
    EXPECT_TRUE(xyz.empty());
  }
};

void expectPoints(const std::vector<double>& xyz, const LasSpec& s,
                  const std::vector<std::size_t>& kept)
{
  ASSERT_EQ(xyz.size(), 3 * kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const LasPoint& p = s.points[kept[k]];
    const std::int32_t ints[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a)
      ASSERT_EQ(xyz[3 * k + a], static_cast<double>(ints[a]) * s.scale[a] + s.offset[a])
          << "point " << kept[k] << " axis " << a;
  }
}

TEST_F(LasReader, EveryPointFormatAndVersionReadsExactCoordinates)
{
  for (int format = 0; format <= 10; ++format)
    for (int minor : {0, 1, 2, 3, 4}) {
      if (format >= 6 && minor < 4)
        continue;
      SCOPED_TRACE("LAS 1." + std::to_string(minor) + " format " +
                   std::to_string(format));
      LasSpec s;
      s.minor = minor;
      s.format = format;
      s.points = somePoints(50, format >= 6);
      const std::string path = write("f.las", makeLas(s));
      std::vector<double> xyz;
      LasInfo info;
      ASSERT_TRUE(pcl_vts::readLasCloud(path, {}, xyz, info).ok());
      EXPECT_EQ(info.version_minor, minor);
      EXPECT_EQ(info.point_format, format);
      EXPECT_EQ(info.record_length, MIN_RECORD[format]);
      EXPECT_EQ(info.points_read, 50u);
      EXPECT_EQ(info.points_kept, 50u);
      EXPECT_EQ(info.system_identifier, "pcl_vts test");
      std::vector<std::size_t> all(50);
      for (std::size_t i = 0; i < 50; ++i)
        all[i] = i;
      expectPoints(xyz, s, all);
      std::map<int, std::uint64_t> expected;
      for (const LasPoint& p : s.points)
        ++expected[p.cls];
      for (int c = 0; c < 256; ++c)
        EXPECT_EQ(info.class_counts[c], expected.count(c) ? expected[c] : 0u) << c;
    }
}

TEST_F(LasReader, ExtraBytesAreSkippedByTheHeaderRecordLength)
{
  for (int format : {1, 3, 6, 8}) {
    LasSpec s;
    s.minor = format >= 6 ? 4 : 2;
    s.format = format;
    s.extra_bytes = 13;
    s.points = somePoints(20, false);
    s.vlr_user_ids = {"LASF_Spec", "LASF_Spec"}; // two extra-bytes-like VLRs
    std::vector<double> xyz;
    LasInfo info;
    ASSERT_TRUE(pcl_vts::readLasCloud(write("e.las", makeLas(s)), {}, xyz, info).ok());
    EXPECT_EQ(info.record_length, MIN_RECORD[format] + 13);
    std::vector<std::size_t> all(20);
    for (std::size_t i = 0; i < 20; ++i)
      all[i] = i;
    expectPoints(xyz, s, all);
  }
}

TEST_F(LasReader, Las14With64BitCountOnlyIsRead)
{
  LasSpec s;
  s.minor = 4;
  s.format = 7;
  s.legacy_count = false;
  s.points = somePoints(30, true);
  std::vector<double> xyz;
  LasInfo info;
  ASSERT_TRUE(pcl_vts::readLasCloud(write("c.las", makeLas(s)), {}, xyz, info).ok());
  EXPECT_EQ(info.points_in_header, 30u);
  EXPECT_EQ(xyz.size(), 90u);
}

TEST_F(LasReader, ClassFilterKeepsListedClassesFullByteFromFormat6)
{
  for (int format : {1, 6}) {
    SCOPED_TRACE(format);
    LasSpec s;
    s.minor = format >= 6 ? 4 : 2;
    s.format = format;
    s.points = somePoints(600, format >= 6);
    const std::uint8_t wanted_a = 2;
    const std::uint8_t wanted_b = format >= 6 ? 65 : 9;
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < s.points.size(); ++i)
      if (s.points[i].cls == wanted_a || s.points[i].cls == wanted_b)
        kept.push_back(i);
    ASSERT_GE(kept.size(), 4u);
    LasReadOptions options;
    options.classes = {wanted_a, wanted_b};
    std::vector<double> xyz;
    LasInfo info;
    ASSERT_TRUE(
        pcl_vts::readLasCloud(write("k.las", makeLas(s)), options, xyz, info).ok());
    EXPECT_EQ(info.points_read, 600u);
    EXPECT_EQ(info.points_kept, kept.size());
    expectPoints(xyz, s, kept);
    for (int a = 0; a < 3; ++a) {
      EXPECT_LE(info.min[a], info.max[a]);
      for (std::size_t k = 0; k < kept.size(); ++k) {
        EXPECT_LE(info.min[a], xyz[3 * k + a]);
        EXPECT_GE(info.max[a], xyz[3 * k + a]);
      }
    }
  }
}

TEST_F(LasReader, ReturnFilterKeepsFirstOrLastReturns)
{
  for (int format : {3, 9}) {
    LasSpec s;
    s.minor = format >= 6 ? 4 : 2;
    s.format = format;
    s.points = somePoints(60, false);
    for (auto [filter, name] : {std::pair{pcl_vts::LasReturnFilter::FIRST, "first"},
                                std::pair{pcl_vts::LasReturnFilter::LAST, "last"}}) {
      SCOPED_TRACE(name);
      std::vector<std::size_t> kept;
      for (std::size_t i = 0; i < s.points.size(); ++i) {
        const LasPoint& p = s.points[i];
        if (filter == pcl_vts::LasReturnFilter::FIRST
                ? p.return_number == 1
                : p.return_number == p.number_of_returns)
          kept.push_back(i);
      }
      ASSERT_GT(kept.size(), 0u);
      ASSERT_LT(kept.size(), 60u);
      LasReadOptions options;
      options.returns = filter;
      std::vector<double> xyz;
      LasInfo info;
      ASSERT_TRUE(
          pcl_vts::readLasCloud(write("r.las", makeLas(s)), options, xyz, info).ok());
      expectPoints(xyz, s, kept);
    }
  }
}

// ---- bad files: one-line IO_ERROR / EMPTY_INPUT, nothing returned

LasSpec smallSpec(int minor = 2, int format = 3)
{
  LasSpec s;
  s.minor = minor;
  s.format = format;
  s.points = somePoints(10, false);
  return s;
}

TEST_F(LasReader, MissingAndEmptyFilesAreIoErrors)
{
  std::vector<double> xyz;
  LasInfo info;
  const pcl_vts::Status s =
      pcl_vts::readLasCloud((root_ / "absent.las").string(), {}, xyz, info);
  EXPECT_EQ(s.code, StatusCode::IO_ERROR);
  EXPECT_NE(s.message.find("No such file"), std::string::npos) << s.message;
  expectError("", StatusCode::IO_ERROR, "empty (0 bytes)");
}

TEST_F(LasReader, WrongMagicAndShortHeaderAreIoErrors)
{
  expectError("ply\nformat ascii 1.0\n", StatusCode::IO_ERROR, "no 'LASF' signature");
  expectError(makeLas(smallSpec()).substr(0, 100), StatusCode::IO_ERROR,
              "truncated LAS header");
  std::string b = makeLas(smallSpec(4, 6));
  expectError(b.substr(0, 300), StatusCode::IO_ERROR, "truncated LAS header");
}

TEST_F(LasReader, TruncatedBodyIsAnIoError)
{
  std::string b = makeLas(smallSpec());
  b.resize(b.size() - 5);
  expectError(b, StatusCode::IO_ERROR, "truncated");
  b = makeLas(smallSpec());
  expectError(b.substr(0, 227), StatusCode::IO_ERROR, "truncated");
}

TEST_F(LasReader, HeaderClaimingBillionsOfPointsFailsBeforeAllocating)
{
  std::string b = makeLas(smallSpec());
  put32(b, 107, 4000000000u);
  expectError(b, StatusCode::IO_ERROR, "4000000000");
  std::string b14 = makeLas(smallSpec(4, 6));
  put32(b14, 107, 0);
  put64(b14, 247, std::uint64_t(1) << 60);
  expectError(b14, StatusCode::IO_ERROR, std::to_string(std::uint64_t(1) << 60));
}

TEST_F(LasReader, InconsistentHeaderFieldsAreIoErrors)
{
  std::string b = makeLas(smallSpec());
  put16(b, 105, 33); // format 3 needs 34 bytes
  expectError(b, StatusCode::IO_ERROR, "record length 33 < 34");

  b = makeLas(smallSpec());
  put32(b, 96, 100); // points inside the header
  expectError(b, StatusCode::IO_ERROR, "offset to point data 100");

  b = makeLas(smallSpec());
  put32(b, 96, 1u << 30); // beyond the end
  expectError(b, StatusCode::IO_ERROR, "offset to point data");

  b = makeLas(smallSpec());
  put16(b, 94, 200);
  expectError(b, StatusCode::IO_ERROR, "header size 200 < 227");

  b = makeLas(smallSpec(4, 6));
  put16(b, 94, 227); // LAS 1.4 needs the 375-byte header
  expectError(b, StatusCode::IO_ERROR, "header size 227 < 375");

  b = makeLas(smallSpec());
  b[24] = 2;
  expectError(b, StatusCode::IO_ERROR, "unsupported LAS version 2.2");

  b = makeLas(smallSpec());
  b[104] = 11;
  expectError(b, StatusCode::IO_ERROR, "unsupported LAS point format 11");

  b = makeLas(smallSpec());
  putDouble(b, 139, 0.0); // y scale
  expectError(b, StatusCode::IO_ERROR, "y scale 0");

  b = makeLas(smallSpec());
  putDouble(b, 155, std::nan(""));
  expectError(b, StatusCode::IO_ERROR, "x scale");
}

TEST_F(LasReader, CompressionBitWithoutLaszipVlrIsRefused)
{
  // The LAZ files themselves are tested in test_laz_reader.cpp.
  std::string b = makeLas(smallSpec());
  b[104] = static_cast<char>(3 | 0x80);
  expectError(b, StatusCode::IO_ERROR, "no 'laszip encoded' VLR");
}

TEST_F(LasReader, ZeroPointsAndEmptyFilterResultAreEmptyInput)
{
  LasSpec s = smallSpec();
  s.points.clear();
  expectError(makeLas(s), StatusCode::EMPTY_INPUT, "0 points");
  s = smallSpec();
  for (LasPoint& p : s.points)
    p.cls = 1;
  LasReadOptions options;
  options.classes = {2, 9};
  expectError(makeLas(s), StatusCode::EMPTY_INPUT,
              "classes 2,9); classes present: 1 (10)", options);
}

// ---- the real files: counts from ../shared/data/README.md

struct RealLas {
  const char* path;
  std::uint64_t points;
  std::map<int, std::uint64_t> classes; ///< the counts the README states
  double z_min, z_max;                  ///< the README's z range, rounded outward
};

TEST(LasReaderSharedData, EveryFileGivesTheReadmeCounts)
{
  const std::string dir = std::string(PCL_VTS_SHARED_DATA_DIR) + "/las";
  if (!fs::exists(dir))
    GTEST_SKIP() << "shared data not found at " << dir;
  const std::vector<RealLas> files = {
      {"pdal/autzen_trim.las", 110000, {{2, 26107}, {1, 83893}}, 406, 521},
      {"from_laz/lidR_Topography.las",
       73403,
       {{2, 8159}, {9, 3897}, {1, 61347}},
       788.9,
       830},
      {"from_laz/pdal_las_with_several_extra_byte_bloc.las",
       697721,
       {{2, 683023}},
       99.6,
       120.5},
      {"pdal/hexbin-crop.las", 38367, {{2, 35318}}, 3107, 3210},
      {"pdal/4_6_crop.las", 23875, {{2, 9003}}, 7077, 7140},
      {"laspy/file_with_both_wkt_and_geotiff_vlrs.las",
       25408,
       {{2, 9808}, {6, 3737}},
       1352,
       1404},
      {"pdal/sample_c.las", 14408, {{2, 1368}, {6, 12525}}, 627, 657},
      {"liblas/certainty3d-color-utm-feet-navd88.las", 10126, {{0, 10126}}, 2700, 2977},
      {"pdal/mvk-thin.las", 6280, {{2, 1693}}, 95, 230},
      {"pdal/epsg_4326.las", 5380, {{0, 5380}}, 39, 79},
      // The README calls the 902 points "building"; they are class 5 (high vegetation),
      // and its "veg 284" are classes 3 + 4 (257 + 27).
      {"pdal/warsaw_small.las", 3000, {{2, 1381}, {5, 902}, {0, 433}}, 84.6, 104.6},
      {"pdal/simple.las", 1065, {{2, 276}, {1, 789}}, 406, 587},
      {"pdal/test1_4.las", 1000, {{2, 1000}}, 5592, 5600},
  };
  for (const RealLas& f : files) {
    SCOPED_TRACE(f.path);
    std::vector<double> xyz;
    LasInfo info;
    const pcl_vts::Status s = pcl_vts::readLasCloud(dir + "/" + f.path, {}, xyz, info);
    ASSERT_TRUE(s.ok()) << s.toString();
    EXPECT_EQ(info.points_read, f.points);
    EXPECT_EQ(info.points_kept, f.points);
    EXPECT_EQ(xyz.size(), 3 * f.points);
    for (const auto& [cls, count] : f.classes)
      EXPECT_EQ(info.class_counts[cls], count) << "class " << cls;
    EXPECT_GE(info.min[2], f.z_min);
    EXPECT_LE(info.max[2], f.z_max);

    if (f.classes.count(2) == 0)
      continue;
    LasReadOptions ground;
    ground.classes = {2};
    std::vector<double> g;
    LasInfo ginfo;
    ASSERT_TRUE(pcl_vts::readLasCloud(dir + "/" + f.path, ground, g, ginfo).ok());
    EXPECT_EQ(ginfo.points_kept, f.classes.at(2));
    EXPECT_EQ(g.size(), 3 * f.classes.at(2));
  }
}

TEST(LasReaderSharedData, Format8FullByteClass65AndExtraBytes)
{
  const std::string path = std::string(PCL_VTS_SHARED_DATA_DIR) +
                           "/las/from_laz/pdal_las_with_several_extra_byte_bloc.las";
  if (!fs::exists(path))
    GTEST_SKIP() << "shared data not found at " << path;
  LasReadOptions options;
  options.classes = {65};
  std::vector<double> xyz;
  LasInfo info;
  ASSERT_TRUE(pcl_vts::readLasCloud(path, options, xyz, info).ok());
  EXPECT_EQ(info.point_format, 8);
  EXPECT_EQ(info.record_length, 41u);
  EXPECT_EQ(info.version_minor, 4);
  EXPECT_GT(info.points_kept, 0u);
  EXPECT_EQ(info.points_kept, info.class_counts[65]);
}
TEST(LasReaderSharedData, ChunkedReadingGivesTheSamePointsInTheSameOrder)
{
  const std::string path =
      std::string(PCL_VTS_SHARED_DATA_DIR) + "/las/pdal/autzen_trim.las";
  if (!fs::exists(path))
    GTEST_SKIP() << "shared data not found at " << path;
  for (const std::vector<std::uint8_t>& classes :
       std::vector<std::vector<std::uint8_t>>{{}, {2}}) {
    LasReadOptions options;
    options.classes = classes;
    std::vector<double> whole;
    LasInfo whole_info;
    ASSERT_TRUE(pcl_vts::readLasCloud(path, options, whole, whole_info).ok());
    for (std::size_t chunk : {std::size_t{1}, std::size_t{777}, std::size_t{1} << 20}) {
      std::vector<double> joined;
      std::size_t calls = 0;
      LasInfo info;
      const pcl_vts::Status s = pcl_vts::readLasCloudChunks(
          path, options, chunk,
          [&](const double* xyz, std::size_t n) {
            EXPECT_LE(n, chunk);
            ++calls;
            joined.insert(joined.end(), xyz, xyz + 3 * n);
            return pcl_vts::Status::success();
          },
          info);
      ASSERT_TRUE(s.ok()) << s.toString();
      EXPECT_TRUE(joined == whole) << "chunk " << chunk;
      EXPECT_EQ(calls, (whole.size() / 3 + chunk - 1) / chunk);
      EXPECT_EQ(info.points_kept, whole_info.points_kept);
      EXPECT_EQ(info.min, whole_info.min);
      EXPECT_EQ(info.max, whole_info.max);
      EXPECT_EQ(info.class_counts, whole_info.class_counts);
    }
  }
  // A sink's error stops the read and comes back.
  std::size_t calls = 0;
  LasInfo info;
  const pcl_vts::Status s = pcl_vts::readLasCloudChunks(
      path, LasReadOptions{}, 1000,
      [&](const double*, std::size_t) {
        return ++calls == 3
                   ? pcl_vts::Status::error(pcl_vts::StatusCode::IO_ERROR, "disk full")
                   : pcl_vts::Status::success();
      },
      info);
  EXPECT_EQ(s.code, StatusCode::IO_ERROR);
  EXPECT_EQ(s.message, "disk full");
  EXPECT_EQ(calls, 3u);
}

} // namespace
