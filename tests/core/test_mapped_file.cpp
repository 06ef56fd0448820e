// MappedFile: a file's bytes as they are on disk, an empty file as an empty range,
// each failure an IO_ERROR naming the file; close and dropPages keep it usable.
#include "support/temp_folder_test.h"

#include <pcl_vts/core/mapped_file.h>

#include <gtest/gtest.h>

#include <cstring>
#include <string>

namespace pcl_vts {
namespace test {
namespace {

using MappedFileTest = TempFolderTest;

TEST_F(MappedFileTest, HoldsTheBytesOfTheFileThroughDropPagesAndReopen)
{
  std::string bytes(3 * 4096 + 17, '\0');
  for (std::size_t k = 0; k < bytes.size(); ++k)
    bytes[k] = static_cast<char>(k * 7 + 1);
  const std::string path = write("a.bin", bytes);
  MappedFile file;
  ASSERT_TRUE(file.open(path).ok());
  ASSERT_EQ(file.size(), bytes.size());
  EXPECT_EQ(std::memcmp(file.data(), bytes.data(), bytes.size()), 0);
  file.dropPages(); // read back from the file
  EXPECT_EQ(std::memcmp(file.data(), bytes.data(), bytes.size()), 0);
  const std::string other = write("b.bin", "xyz");
  ASSERT_TRUE(file.open(other).ok()); // the first mapping released
  ASSERT_EQ(file.size(), 3u);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(file.data()), 3), "xyz");
  file.close();
  EXPECT_EQ(file.data(), nullptr);
  EXPECT_EQ(file.size(), 0u);
  file.dropPages(); // nothing mapped: nothing to do
}

TEST_F(MappedFileTest, AnEmptyFileIsAnEmptyRange)
{
  MappedFile file;
  ASSERT_TRUE(file.open(write("empty.bin", "")).ok());
  EXPECT_EQ(file.size(), 0u);
  EXPECT_EQ(file.data(), nullptr);
}

TEST_F(MappedFileTest, AMissingFileOrAFolderIsAnIoErrorNamingIt)
{
  MappedFile file;
  const std::string missing = (root_ / "missing.bin").string();
  Status s = file.open(missing);
  EXPECT_EQ(s.code, StatusCode::IO_ERROR);
  EXPECT_NE(s.message.find("'" + missing + "': cannot open"), std::string::npos)
      << s.message;
  s = file.open(root_.string());
  EXPECT_EQ(s.code, StatusCode::IO_ERROR);
  EXPECT_NE(s.message.find("not a regular file"), std::string::npos) << s.message;
  EXPECT_EQ(file.data(), nullptr);
  EXPECT_EQ(file.size(), 0u);
}

} // namespace
} // namespace test
} // namespace pcl_vts
