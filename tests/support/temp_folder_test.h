// A GoogleTest fixture owning a fresh temp folder (removed after the test) where the
// reader tests write the small files they read back.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace pcl_vts {
namespace test {

class TempFolderTest : public ::testing::Test {
 public:
  /// Writes bytes to root/name; returns the path.
  std::string write(const std::string& name, const std::string& bytes) const
  {
    const std::string path = (root_ / name).string();
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
  }

 protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/pcl_vts_reader_test.XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    root_ = pattern;
  }

  void TearDown() override
  {
    std::error_code ec;
    std::filesystem::remove_all(root_, ec);
  }

  std::filesystem::path root_;
};

} // namespace test
} // namespace pcl_vts
