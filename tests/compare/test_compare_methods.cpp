// compare_methods end to end on a tiny synthetic input: every method gives a row
// (figures or a reason), the files appear, and bad input is refused with its exit
// code and no report left behind. No timing is checked.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace {

std::string scratchDir()
{
  char pattern[] = "/tmp/test_compare_methods.XXXXXX";
  const char* dir = ::mkdtemp(pattern);
  return dir ? dir : "/tmp";
}

int runTool(const std::string& args)
{
  const std::string command =
      std::string(PCL_VTS_COMPARE_METHODS) + " " + args + " >/dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string readFile(const std::string& path)
{
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

bool exists(const std::string& path)
{
  return ::access(path.c_str(), F_OK) == 0;
}

TEST(CompareMethods, EveryMethodGetsARowOnATinySyntheticInput)
{
  const std::string dir = scratchDir();
  ASSERT_EQ(runTool("--synthetic 2000 --name tiny --report " + dir + "/tiny.md --tsv " +
                    dir + "/tiny.tsv --pictures " + dir + " --picture-width 96 " +
                    "--time-limit 60"),
            0);
  std::istringstream tsv(readFile(dir + "/tiny.tsv"));
  std::string line;
  int rows = 0;
  for (const char* method : {"vts-raw", "vts", "gp3", "poisson", "bpa"}) {
    ASSERT_TRUE(std::getline(tsv, line)) << "no row for " << method;
    SCOPED_TRACE(line);
    std::istringstream fields(line);
    std::string name, points, row_method, seconds, status;
    std::getline(fields, name, '\t');
    std::getline(fields, points, '\t');
    std::getline(fields, row_method, '\t');
    std::getline(fields, seconds, '\t');
    std::getline(fields, status);
    EXPECT_EQ(name, "tiny");
    EXPECT_EQ(points, "2000");
    EXPECT_EQ(row_method, method);
    // Either figures or a reason, never a silent gap.
    EXPECT_TRUE((status == "ok" && !seconds.empty()) ||
                (status != "ok" && !status.empty()));
    if (std::string(method).rfind("vts", 0) == 0) {
      EXPECT_EQ(status, "ok"); // our own method must work
    }
    ++rows;
  }
  EXPECT_FALSE(std::getline(tsv, line));
  EXPECT_EQ(rows, 5);
  const std::string md = readFile(dir + "/tiny.md");
  for (const char* title : {"VTS, Delaunay only", "VTS + trim + fill",
                            "PCL GreedyProjection", "PCL Poisson", "Ball-Pivoting"})
    EXPECT_NE(md.find(title), std::string::npos) << title;
  EXPECT_NE(md.find("true surface"), std::string::npos);
  EXPECT_TRUE(exists(dir + "/tiny_top.png"));
  EXPECT_TRUE(exists(dir + "/tiny_oblique.png"));
}

TEST(CompareMethods, MissingInputIsAnInputErrorAndWritesNothing)
{
  const std::string dir = scratchDir();
  EXPECT_EQ(runTool(dir + "/no_such_file.pcd --report " + dir + "/r.md"), 2);
  EXPECT_FALSE(exists(dir + "/r.md"));
}

TEST(CompareMethods, BadOptionsAreUsageErrors)
{
  EXPECT_EQ(runTool("--synthetic 10"), 1); // below 100 points
  EXPECT_EQ(runTool("--synthetic 1000 --methods vts,magic"), 1);
  EXPECT_EQ(runTool("--synthetic 1000 --time-limit -1"), 1);
  EXPECT_EQ(runTool("--no-such-option x.pcd"), 1);
  EXPECT_EQ(runTool(""), 1);
}

TEST(CompareMethods, TooFewPointsIsADataError)
{
  const std::string dir = scratchDir();
  std::ofstream(dir + "/two.xyz") << "0 0 0\n1 0 0\n";
  EXPECT_EQ(runTool(dir + "/two.xyz --report " + dir + "/r.md"), 3);
  EXPECT_FALSE(exists(dir + "/r.md"));
}

} // namespace
