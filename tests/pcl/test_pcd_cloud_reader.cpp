// The PCD reader in chunks (readPcdCloudChunks) against the whole read, for the three
// bodies PCL writes (ascii, binary, binary_compressed): the same points in the same
// order, chunks no larger than asked, a failing sink stops the read.
#include <pcl_vts/io/pcd_cloud_reader.h>

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace {

class PcdCloudReader : public ::testing::Test {
 protected:
  void SetUp() override
  {
    root_ = std::filesystem::temp_directory_path() /
            ("pcl_vts_pcd_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(root_);
  }
  void TearDown() override { std::filesystem::remove_all(root_); }

  /// 1000 points with an intensity field before x: x, y, z are not the first bytes.
  std::string write(const std::string& name, int format) const
  {
    pcl::PointCloud<pcl::PointXYZI> cloud;
    for (int i = 0; i < 1000; ++i) {
      pcl::PointXYZI p;
      p.x = 1000.25f + static_cast<float>(i % 37);
      p.y = 2000.5f + static_cast<float>(i / 37);
      p.z = 10.0f + 0.125f * static_cast<float>(i % 11);
      p.intensity = static_cast<float>(i);
      cloud.push_back(p);
    }
    const std::string path = (root_ / name).string();
    pcl::PCDWriter writer;
    if (format == 0)
      writer.writeASCII(path, cloud);
    else if (format == 1)
      writer.writeBinary(path, cloud);
    else
      writer.writeBinaryCompressed(path, cloud);
    return path;
  }

  std::filesystem::path root_;
};

TEST_F(PcdCloudReader, StreamedInChunksEqualsTheWholeRead)
{
  for (int format = 0; format < 3; ++format) {
    SCOPED_TRACE("format " + std::to_string(format));
    const std::string path = write("c" + std::to_string(format) + ".pcd", format);
    std::vector<double> whole;
    pcl_vts::PcdCloudInfo whole_info;
    ASSERT_TRUE(pcl_vts::readPcdCloud(path, whole, whole_info).ok());
    ASSERT_EQ(whole.size(), 3000u);
    EXPECT_EQ(whole[3 * 40], 1000.25 + 3);
    EXPECT_EQ(whole[3 * 40 + 1], 2000.5 + 1);
    for (const std::size_t chunk :
         {std::size_t{1}, std::size_t{7}, std::size_t{1000}, std::size_t{1} << 20}) {
      SCOPED_TRACE(chunk);
      std::vector<double> streamed;
      std::size_t chunks = 0;
      pcl_vts::PcdCloudInfo info;
      const pcl_vts::Status s = pcl_vts::readPcdCloudChunks(
          path, chunk,
          [&](const double* xyz, std::size_t n) {
            EXPECT_LE(n, chunk);
            streamed.insert(streamed.end(), xyz, xyz + 3 * n);
            ++chunks;
            return pcl_vts::Status::success();
          },
          info);
      ASSERT_TRUE(s.ok()) << s.toString();
      EXPECT_EQ(streamed, whole);
      EXPECT_EQ(chunks, (1000 + chunk - 1) / chunk);
      EXPECT_EQ(info.points, 1000u);
      EXPECT_EQ(info.data_format, whole_info.data_format);
    }
    // A sink that fails stops the read with its error.
    std::size_t calls = 0;
    pcl_vts::PcdCloudInfo info;
    const pcl_vts::Status s = pcl_vts::readPcdCloudChunks(
        path, 10,
        [&](const double*, std::size_t) {
          ++calls;
          return pcl_vts::Status::error(pcl_vts::StatusCode::IO_ERROR, "sink full");
        },
        info);
    EXPECT_EQ(s.message, "sink full");
    EXPECT_EQ(calls, 1u);
  }
}

TEST_F(PcdCloudReader, ATruncatedBinaryBodyFailsBeforeAnyPointGoesOut)
{
  const std::string path = write("t.pcd", 1);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 5);
  std::size_t calls = 0;
  pcl_vts::PcdCloudInfo info;
  const pcl_vts::Status s = pcl_vts::readPcdCloudChunks(
      path, 10,
      [&](const double*, std::size_t) {
        ++calls;
        return pcl_vts::Status::success();
      },
      info);
  EXPECT_EQ(s.code, pcl_vts::StatusCode::IO_ERROR);
  EXPECT_NE(s.message.find("truncated"), std::string::npos) << s.message;
  EXPECT_EQ(calls, 0u);
}

} // namespace
