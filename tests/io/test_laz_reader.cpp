// The LAZ reader against independent decodings of real files (../shared/data/laz: the
// publishers' uncompressed twins and laz-perf's x y z): every point, every record byte,
// on 1 and 3 threads, whole and streamed; then refusals and corrupt files, which must
// end in one clear error and never in a crash or silently different points.
#include "../../src/io/laz/laz_stream.h"

#include <pcl_vts/io/las_reader.h>
#include <pcl_vts/io/point_cloud_loader.h>

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace pcl_vts;

namespace {

const std::string DATA = std::string(PCL_VTS_SHARED_DATA_DIR);

std::vector<std::uint8_t> fileBytes(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct Twin {
  const char* laz;  ///< under laz/
  const char* twin; ///< under DATA
};

// Every LAZ file whose uncompressed twin is in ../shared/data (README "laz/").
const Twin LAS_TWINS[] = {{"simple.laz", "laz/simple.twin.las"},
                          {"1_4_w_evlr.laz", "laz/1_4_w_evlr.twin.las"},
                          {"extrabytes.laz", "laz/extrabytes.twin.las"},
                          {"laszip-generated.laz", "laz/laszip-generated.twin.las"},
                          {"point-color.laz", "laz/point-color.twin.las"},
                          {"point-time.laz", "laz/point-time.twin.las"},
                          {"point-time-1.4.laz", "laz/point-time.twin.las"},
                          {"point10.laz", "laz/point10.twin.las"},
                          {"point10-1.0.laz", "laz/point10-1.0.twin.las"},
                          {"simple-laszip-compressor-version-1.2r0.laz",
                           "laz/simple-laszip-compressor-version-1.2r0.twin.las"},
                          {"autzen_trim.laz", "las/pdal/autzen_trim.las"},
                          {"lidR_Topography.laz", "las/from_laz/lidR_Topography.las"},
                          {"las_with_several_extra_byte_bloc.laz",
                           "las/from_laz/pdal_las_with_several_extra_byte_bloc.las"}};

class LazReader : public ::testing::Test {
 protected:
  void SetUp() override
  {
    if (!fs::exists(DATA + "/laz"))
      GTEST_SKIP() << "shared data not found at " << DATA << "/laz";
  }
};

Status readAll(const std::string& path, unsigned threads, std::vector<double>& xyz,
               LasInfo& info)
{
  LasReadOptions options;
  options.threads = threads;
  return readLasCloud(path, options, xyz, info);
}

/// Where a LAS file's records are, from its header.
struct Layout {
  std::size_t offset = 0, record_length = 0;
  std::uint64_t count = 0;
  int format = 0;
  const std::uint8_t* laszip = nullptr;
  std::size_t laszip_length = 0;
};

template <typename T>
T field(const std::vector<std::uint8_t>& b, std::size_t at)
{
  T v;
  std::memcpy(&v, b.data() + at, sizeof(T));
  return v;
}

Layout layoutOf(const std::vector<std::uint8_t>& b)
{
  Layout l;
  const std::size_t header_size = field<std::uint16_t>(b, 94);
  l.offset = field<std::uint32_t>(b, 96);
  const std::uint32_t vlrs = field<std::uint32_t>(b, 100);
  l.format = b[104] & 0x3F;
  l.record_length = field<std::uint16_t>(b, 105);
  l.count = field<std::uint32_t>(b, 107);
  if (b[25] == 4 && field<std::uint64_t>(b, 247) != 0)
    l.count = field<std::uint64_t>(b, 247);
  std::size_t at = header_size;
  for (std::uint32_t v = 0; v < vlrs; ++v) {
    const std::size_t length = field<std::uint16_t>(b, at + 20);
    if (std::string(reinterpret_cast<const char*>(&b[at + 2])) == "laszip encoded" &&
        field<std::uint16_t>(b, at + 18) == 22204) {
      l.laszip = b.data() + at + 54;
      l.laszip_length = length;
    }
    at += 54 + length;
  }
  return l;
}

/// Decodes every record of a LAZ file through the chunk interface.
std::vector<std::uint8_t> decodeRecords(const std::vector<std::uint8_t>& b)
{
  const Layout l = layoutOf(b);
  laz::LaszipVlr vlr;
  std::vector<laz::Chunk> chunks;
  std::string why;
  EXPECT_TRUE(l.laszip != nullptr);
  EXPECT_TRUE(laz::parseLaszipVlr(l.laszip, l.laszip_length, vlr, why)) << why;
  EXPECT_TRUE(laz::checkItems(vlr, l.format, l.record_length, why)) << why;
  EXPECT_TRUE(
      laz::readChunkTable(b.data(), b.size(), l.offset, l.count, vlr, chunks, why))
      << why;
  std::vector<std::uint8_t> all, records;
  for (const laz::Chunk& c : chunks) {
    EXPECT_TRUE(laz::decodeChunk(b.data(), c, vlr, l.record_length, records, why))
        << why;
    all.insert(all.end(), records.begin(), records.end());
  }
  return all;
}

} // namespace

TEST_F(LazReader, EveryFileReadsToItsTwinsPoints)
{
  for (const Twin& t : LAS_TWINS) {
    SCOPED_TRACE(t.laz);
    std::vector<double> laz_xyz, twin_xyz;
    LasInfo laz_info, twin_info;
    ASSERT_TRUE(readAll(DATA + "/laz/" + t.laz, 1, laz_xyz, laz_info).ok());
    ASSERT_TRUE(readAll(DATA + "/" + t.twin, 1, twin_xyz, twin_info).ok());
    EXPECT_EQ(laz_info.points_read, twin_info.points_read);
    EXPECT_EQ(laz_info.point_format, twin_info.point_format);
    EXPECT_EQ(laz_info.class_counts, twin_info.class_counts);
    ASSERT_EQ(laz_xyz.size(), twin_xyz.size());
    EXPECT_TRUE(laz_xyz == twin_xyz);
    EXPECT_NE(laz_info.laz.find("LASzip"), std::string::npos) << laz_info.laz;
    EXPECT_EQ(twin_info.laz, "");
    // Chunks decoded three at a time give the same points.
    std::vector<double> threaded;
    ASSERT_TRUE(readAll(DATA + "/laz/" + t.laz, 3, threaded, laz_info).ok());
    EXPECT_TRUE(threaded == laz_xyz);
  }
}

TEST_F(LazReader, EveryRecordByteEqualsTheTwins)
{
  // Intensity, GPS time, colour, NIR and extra bytes too, not only x y z: the layered
  // scheme decodes those from streams that the coordinates do not depend on.
  for (const Twin& t : LAS_TWINS) {
    SCOPED_TRACE(t.laz);
    const std::vector<std::uint8_t> laz = fileBytes(DATA + "/laz/" + t.laz);
    const std::vector<std::uint8_t> twin = fileBytes(DATA + "/" + t.twin);
    const Layout tl = layoutOf(twin);
    const std::vector<std::uint8_t> records = decodeRecords(laz);
    ASSERT_EQ(records.size(), tl.count * tl.record_length);
    EXPECT_TRUE(std::equal(records.begin(), records.end(), twin.begin() + tl.offset));
  }
}

TEST_F(LazReader, FilesWithoutLasTwinsMatchLazPerfsCoordinates)
{
  // .twin.pcd: x y z as float64 decoded by laz-perf (COPC's variable chunks, 1.4 with
  // extra bytes).
  for (const char* name : {"simple.copc.laz", "extra.laz", "autzen_trim.laz",
                           "1_4_w_evlr.laz", "simple.laz"}) {
    SCOPED_TRACE(name);
    const std::string stem = DATA + "/laz/" + std::string(name, std::strlen(name) - 4);
    std::vector<double> laz_xyz, pcd_xyz;
    LasInfo info;
    ASSERT_TRUE(readAll(stem + ".laz", 2, laz_xyz, info).ok());
    CloudDescription d;
    ASSERT_TRUE(
        loadPointCloud(stem + ".twin.pcd", CloudLoadOptions{}, pcd_xyz, d).ok());
    ASSERT_EQ(laz_xyz.size(), pcd_xyz.size());
    EXPECT_TRUE(laz_xyz == pcd_xyz);
  }
}

TEST_F(LazReader, VariableChunksAndLayersAreDescribed)
{
  std::vector<double> xyz;
  LasInfo info;
  ASSERT_TRUE(readAll(DATA + "/laz/simple.copc.laz", 1, xyz, info).ok());
  EXPECT_EQ(info.description(), "LAZ 1.4, point format 7, 36-byte records "
                                "(layered-chunked (3), LASzip 3.4.3, variable chunks)");
  ASSERT_TRUE(readAll(DATA + "/laz/autzen_trim.laz", 1, xyz, info).ok());
  EXPECT_EQ(info.description(),
            "LAZ 1.2, point format 3, 34-byte records "
            "(pointwise-chunked (2), LASzip 2.2.0, 50000 points per "
            "chunk)");
}

TEST_F(LazReader, StreamedChunksEqualTheWholeRead)
{
  for (const char* name : {"autzen_trim.laz", "las_with_several_extra_byte_bloc.laz"}) {
    SCOPED_TRACE(name);
    const std::string path = DATA + "/laz/" + name;
    std::vector<double> whole, streamed;
    LasInfo info;
    ASSERT_TRUE(readAll(path, 1, whole, info).ok());
    LasReadOptions options;
    options.threads = 2;
    options.classes = {2};
    std::vector<double> ground;
    ASSERT_TRUE(readLasCloud(path, options, ground, info).ok());
    std::size_t calls = 0;
    const Status s = readLasCloudChunks(
        path, options, 7000,
        [&](const double* xyz, std::size_t n) {
          EXPECT_LE(n, 7000u);
          streamed.insert(streamed.end(), xyz, xyz + 3 * n);
          ++calls;
          return Status::success();
        },
        info);
    ASSERT_TRUE(s.ok()) << s.message;
    EXPECT_GT(calls, 1u);
    EXPECT_TRUE(streamed == ground);
    EXPECT_LT(ground.size(), whole.size()); // the class filter applied
    EXPECT_EQ(info.points_kept, ground.size() / 3);
  }
}

TEST_F(LazReader, RefusalsSayWhat)
{
  const struct {
    const char* path;
    const char* words;
  } cases[] = {{"broken/broken_coder.laz", "unknown LASzip coder 15"},
               {"broken/broken_compressor.laz", "unknown LASzip compressor 16"},
               {"broken/broken_type.laz", "type 22"},
               {"broken/broken_version.laz", "version 6 of the pointwise items"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.path);
    std::vector<double> xyz;
    LasInfo info;
    const Status s = readAll(DATA + "/laz/" + c.path, 2, xyz, info);
    EXPECT_EQ(s.code, StatusCode::IO_ERROR);
    EXPECT_NE(s.message.find(c.words), std::string::npos) << s.message;
    EXPECT_NE(s.message.find("cannot decode this LAZ file"), std::string::npos);
    EXPECT_TRUE(xyz.empty());
  }
}

TEST_F(LazReader, PointwiseWaveformsAreRefused)
{
  // point-time.laz with its GPSTIME11 item relabelled WAVEPACKET13 (formats 4, 5).
  std::vector<std::uint8_t> bytes = fileBytes(DATA + "/laz/point-time.laz");
  const Layout l = layoutOf(bytes);
  const std::size_t item1 = static_cast<std::size_t>(l.laszip - bytes.data()) + 34 + 6;
  ASSERT_EQ(field<std::uint16_t>(bytes, item1), 7); // GPSTIME11
  bytes[item1] = 9;
  std::vector<double> xyz;
  LasInfo info;
  const Status s =
      parseLasCloud(bytes.data(), bytes.size(), "w.laz", LasReadOptions{}, xyz, info);
  EXPECT_EQ(s.code, StatusCode::IO_ERROR);
  EXPECT_NE(s.message.find("waveform packets of point formats 4 and 5"),
            std::string::npos)
      << s.message;
}

TEST_F(LazReader, WaveformFileAgreesWithItsHeader)
{
  // fullwave.laz (point format 10, LAS 1.4) has no twin (laz-perf cannot read it):
  // its header's point count, bounds and points per return are the reference.
  const std::string path = DATA + "/laz/fullwave.laz";
  std::vector<double> xyz;
  LasInfo info;
  const Status s = readAll(path, 2, xyz, info);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(info.point_format, 10);
  EXPECT_EQ(info.points_read, 10750u);
  EXPECT_EQ(xyz.size(), 3 * 10750u);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(info.min[a], info.header_min[a], info.scale[a] / 2) << a;
    EXPECT_NEAR(info.max[a], info.header_max[a], info.scale[a] / 2) << a;
  }
  const std::vector<std::uint8_t> bytes = fileBytes(path);
  const std::vector<std::uint8_t> records = decodeRecords(bytes);
  ASSERT_EQ(records.size(), 10750u * 67);
  std::array<std::uint64_t, 16> by_return{};
  for (std::size_t r = 0; r < 10750; ++r)
    ++by_return[records[67 * r + 14] & 0x0F];
  for (int k = 1; k <= 15; ++k)
    EXPECT_EQ(by_return[k], field<std::uint64_t>(bytes, 255 + 8 * (k - 1)))
        << "return " << k;
}

TEST_F(LazReader, TruncatedFilesFailOrReadTheSamePoints)
{
  const fs::path dir =
      fs::temp_directory_path() /
      ("pcl_vts_laz_" +
       std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::create_directories(dir);
  for (const char* name : {"point-color.laz", "1_4_w_evlr.laz", "simple.copc.laz"}) {
    SCOPED_TRACE(name);
    const std::vector<std::uint8_t> bytes = fileBytes(DATA + "/laz/" + name);
    std::vector<double> intact;
    LasInfo info;
    ASSERT_TRUE(readAll(DATA + "/laz/" + name, 1, intact, info).ok());
    // Cuts inside the point data must fail; later ones (EVLRs) may read the same
    // points.
    const Layout l = layoutOf(bytes);
    laz::LaszipVlr vlr;
    std::vector<laz::Chunk> chunks;
    std::string why;
    ASSERT_TRUE(laz::parseLaszipVlr(l.laszip, l.laszip_length, vlr, why));
    ASSERT_TRUE(laz::readChunkTable(bytes.data(), bytes.size(), l.offset, l.count, vlr,
                                    chunks, why));
    const std::size_t points_end = chunks.back().offset + chunks.back().bytes;
    std::size_t failed = 0, tries = 0;
    for (std::size_t cut = 0; cut < bytes.size(); cut += 1 + bytes.size() / 97) {
      const std::string path = (dir / "cut.laz").string();
      std::ofstream(path, std::ios::binary)
          .write(reinterpret_cast<const char*>(bytes.data()), static_cast<long>(cut));
      std::vector<double> xyz;
      const Status s = readAll(path, 2, xyz, info);
      if (s.ok())
        EXPECT_TRUE(xyz == intact) << "cut at " << cut;
      else
        ++failed;
      if (cut <= points_end) {
        ++tries;
        EXPECT_FALSE(s.ok()) << "cut at " << cut << " of " << points_end;
      }
    }
    EXPECT_GE(failed, tries);
  }
  fs::remove_all(dir);
}

TEST_F(LazReader, CorruptBytesAreMostlyDetectedAndNeverCrash)
{
  // Arithmetic-coded bytes carry no checksum; the reader's checks are the chunk table,
  // the layer sizes and that each decoded stream ends exactly on its last byte. The
  // reader decodes only the layers of x, y, z, returns and class, so a flip in another
  // layer (GPS time, intensity, colour) cannot change the points and goes unseen; a
  // flip that changes the points without an error is what is counted against it.
  for (const char* name : {"point-time.laz", "1_4_w_evlr.laz", "autzen_trim.laz"}) {
    SCOPED_TRACE(name);
    const std::vector<std::uint8_t> intact = fileBytes(DATA + "/laz/" + name);
    const Layout l = layoutOf(intact);
    std::vector<double> reference;
    LasInfo reference_info;
    ASSERT_TRUE(parseLasCloud(intact.data(), intact.size(), name, LasReadOptions{},
                              reference, reference_info)
                    .ok());
    std::size_t detected = 0, harmless = 0, tries = 0;
    for (std::size_t at = l.offset; at < intact.size();
         at += 1 + (intact.size() - l.offset) / 150) {
      std::vector<std::uint8_t> bytes = intact;
      bytes[at] ^= 0x5A;
      std::vector<double> xyz;
      LasInfo info;
      const Status s =
          parseLasCloud(bytes.data(), bytes.size(), name, LasReadOptions{}, xyz, info);
      ++tries;
      if (!s.ok()) {
        ++detected;
        EXPECT_EQ(s.code, StatusCode::IO_ERROR) << s.message;
      } else if (xyz == reference && info.class_counts == reference_info.class_counts) {
        ++harmless;
      }
    }
    std::printf(
        "[ detected ] %s: %zu of %zu flipped bytes, %zu more left the points as "
        "they were\n",
        name, detected, tries, harmless);
    EXPECT_GE((detected + harmless) * 10, tries * 9);
    EXPECT_GE(detected * 10, tries * 7);
  }
}
