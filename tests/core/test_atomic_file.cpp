// AtomicFile: the file appears complete under its name or not at all; no temporary
// file is ever left behind, an existing file survives a failed write, and a
// temporary name already taken is not clobbered.
#include "support/temp_folder_test.h"

#include <pcl_vts/core/atomic_file.h>

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/resource.h>
#include <unistd.h>
#include <vector>

namespace pcl_vts {
namespace {

class AtomicFileTest : public test::TempFolderTest {
 protected:
  std::string read(const std::string& path) const
  {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }

  std::vector<std::string> names() const
  {
    std::vector<std::string> out;
    for (const auto& entry : std::filesystem::directory_iterator(root_))
      out.push_back(entry.path().filename().string());
    return out;
  }
};

TEST_F(AtomicFileTest, CommittedFileHoldsEveryByteAndNoTemporaryRemains)
{
  const std::string path = (root_ / "out.bin").string();
  // Small writes around one larger than the buffer: both paths of write().
  const std::string big(3u << 20, 'b');
  {
    AtomicFile file(path);
    ASSERT_TRUE(file.open().ok());
    file.write("abc");
    EXPECT_FALSE(std::filesystem::exists(path)); // not under its name before commit
    file.write(big.data(), big.size());
    file.write("xyz");
    const Status status = file.commit();
    ASSERT_TRUE(status.ok()) << status.toString();
    EXPECT_EQ(file.bytes(), big.size() + 6);
  }
  EXPECT_EQ(read(path), "abc" + big + "xyz");
  EXPECT_EQ(names(), std::vector<std::string>{"out.bin"});
}

TEST_F(AtomicFileTest, UncommittedFileLeavesNothing)
{
  const std::string path = (root_ / "out.bin").string();
  {
    AtomicFile file(path);
    ASSERT_TRUE(file.open().ok());
    file.write("abc");
    EXPECT_EQ(names().size(), 1u); // the temporary file
  }
  EXPECT_TRUE(names().empty());
}

TEST_F(AtomicFileTest, MissingFolderIsAnIoErrorNamingIt)
{
  const std::string path = (root_ / "no" / "such" / "out.bin").string();
  AtomicFile file(path);
  const Status status = file.open();
  EXPECT_EQ(status.code, StatusCode::IO_ERROR);
  EXPECT_NE(status.message.find("cannot write '" + path + "': folder '"),
            std::string::npos)
      << status.message;
  EXPECT_NE(status.message.find("/no/such/' does not exist"), std::string::npos)
      << status.message;
}

TEST_F(AtomicFileTest, TakenTemporaryNameIsNeitherClobberedNorRemoved)
{
  const std::string path = (root_ / "out.bin").string();
  const std::string taken =
      write(".out.bin.tmp." + std::to_string(::getpid()), "other");
  ASSERT_TRUE(writeFileAtomically(path, "new", 3).ok());
  EXPECT_EQ(read(path), "new");
  EXPECT_EQ(read(taken), "other");
  EXPECT_EQ(names().size(), 2u);
}

// A write that fails part-way (here the file size limit, as a full disk would) is
// reported by commit(), removes the temporary file and keeps the existing file.
TEST_F(AtomicFileTest, FailedWriteKeepsTheExistingFileAndLeavesNoTemporary)
{
  const std::string path = write("out.bin", "old");
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  rlimit limit = saved;
  limit.rlim_cur = 1u << 20;
  void (*previous)(int) = std::signal(SIGXFSZ, SIG_IGN); // EFBIG instead of a signal
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  const std::string big(2u << 20, 'b');
  const Status status = writeFileAtomically(path, big.data(), big.size());
  ::setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, previous);
  EXPECT_EQ(status.code, StatusCode::IO_ERROR);
  EXPECT_EQ(status.message, "cannot write '" + path + "': File too large");
  EXPECT_EQ(read(path), "old");
  EXPECT_EQ(names(), std::vector<std::string>{"out.bin"});
}

} // namespace
} // namespace pcl_vts
