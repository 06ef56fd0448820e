// The tools' command lines without running a tool: the words turned into the
// libraries' typed settings (tools/cli_words.h) and the parsing of argv through
// Boost.Program_options (tools/command_line.h): order, last value wins, the one-line
// errors the tools print.
#include "cli_words.h"
#include "command_line.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pcl_vts {
namespace tools {
namespace {

TEST(CliWords, DuplicateRuleNamesRoundTrip)
{
  for (const DuplicateRule rule : {DuplicateRule::LOWEST_Z, DuplicateRule::HIGHEST_Z,
                                   DuplicateRule::MEAN_Z, DuplicateRule::FIRST}) {
    DuplicateRule parsed =
        rule == DuplicateRule::FIRST ? DuplicateRule::LOWEST_Z : DuplicateRule::FIRST;
    ASSERT_TRUE(parseDuplicateRule(duplicateRuleName(rule), parsed))
        << duplicateRuleName(rule);
    EXPECT_EQ(parsed, rule);
  }
  DuplicateRule parsed = DuplicateRule::FIRST;
  for (const char* bad : {"median", "", "Lowest", "lowest ", "?"})
    EXPECT_FALSE(parseDuplicateRule(bad, parsed)) << bad;
  EXPECT_EQ(parsed, DuplicateRule::FIRST) << "a refused word changes nothing";
}

TEST(CliWords, LasReturnFilterNamesRoundTrip)
{
  for (const LasReturnFilter filter :
       {LasReturnFilter::ALL, LasReturnFilter::FIRST, LasReturnFilter::LAST}) {
    LasReturnFilter parsed =
        filter == LasReturnFilter::ALL ? LasReturnFilter::LAST : LasReturnFilter::ALL;
    ASSERT_TRUE(parseLasReturnFilter(lasReturnFilterName(filter), parsed));
    EXPECT_EQ(parsed, filter);
  }
  LasReturnFilter parsed = LasReturnFilter::LAST;
  for (const char* bad : {"second", "", "unknown", "First"})
    EXPECT_FALSE(parseLasReturnFilter(bad, parsed)) << bad;
  EXPECT_EQ(parsed, LasReturnFilter::LAST);
}

TEST(CliWords, ClassListTakesCommaSeparatedCodesOnce)
{
  std::vector<std::uint8_t> classes;
  std::string error;
  ASSERT_TRUE(parseClassList("2", classes, error)) << error;
  EXPECT_EQ(classes, std::vector<std::uint8_t>{2});
  ASSERT_TRUE(parseClassList("2,9,255,2,0", classes, error)) << error;
  EXPECT_EQ(classes, (std::vector<std::uint8_t>{2, 9, 255, 0}));
  for (const char* bad : {"", "256", "2,", ",2", "a", "-1", "2;9", "1000", "2, 9"}) {
    SCOPED_TRACE(bad);
    error.clear();
    EXPECT_FALSE(parseClassList(bad, classes, error));
    EXPECT_TRUE(classes.empty());
    EXPECT_NE(error.find("is not a class code 0-255"), std::string::npos) << error;
    EXPECT_NE(error.find("'" + std::string(bad) + "'"), std::string::npos) << error;
  }
}

TEST(CliWords, NumbersAreWholeFiniteTexts)
{
  double v = 7.0;
  for (const auto& [text, value] : std::vector<std::pair<const char*, double>>{
           {"0", 0.0}, {"-2.5", -2.5}, {"1e3", 1000.0}, {"0x10", 16.0}, {".5", 0.5}}) {
    ASSERT_TRUE(parseFiniteNumber(text, v)) << text;
    EXPECT_EQ(v, value) << text;
  }
  v = 7.0;
  for (const char* bad : {"", " 1", "1 ", "2m", "inf", "nan", "1e999", "-", "1,2"})
    EXPECT_FALSE(parseFiniteNumber(bad, v)) << bad;
  EXPECT_EQ(v, 7.0) << "a refused text changes nothing";

  std::vector<double> n;
  ASSERT_TRUE(parseNumberList("0,-1.5,10,5e1", 4, n));
  EXPECT_EQ(n, (std::vector<double>{0.0, -1.5, 10.0, 50.0}));
  ASSERT_TRUE(parseNumberList("3", 1, n));
  EXPECT_EQ(n, std::vector<double>{3.0});
  for (const char* bad : {"1,2,3", "1,2,3,4,5", "1,2,,4", "1,2,3,", ",1,2,3", "1,2,3,x",
                          "1;2;3;4", "1, 2,3,4"})
    EXPECT_FALSE(parseNumberList(bad, 4, n)) << bad;
}

/// argv for CommandLine::parse from words, the program name first.
struct Argv {
  explicit Argv(std::vector<std::string> words)
      : words_(std::move(words))
  {
    pointers_.push_back(const_cast<char*>("tool"));
    for (std::string& w : words_)
      pointers_.push_back(w.data());
  }
  int argc() { return static_cast<int>(pointers_.size()); }
  char** argv() { return pointers_.data(); }

 private:
  std::vector<std::string> words_;
  std::vector<char*> pointers_;
};

/// A tool with a value option, a flag, a short option and a hidden one; what each
/// received, in order.
struct Tool {
  std::vector<std::string> log;
  CommandLine cli;

  Tool()
  {
    cli.group("Group one")
        .value("size", "S", "a size (default: 1)",
               [this](const std::string& v, std::string& error) {
                 if (v == "bad") {
                   error = "--size: '" + v + "' is not a size";
                   return false;
                 }
                 log.push_back("size=" + v);
                 return true;
               })
        .flag("quiet", "say nothing", [this] { log.push_back("quiet"); });
    cli.group("Group two").flag("help,h", "print this help", [this] {
      log.push_back("help");
    });
    cli.hiddenValue("internal", [this](const std::string& v, std::string&) {
      log.push_back("internal=" + v);
      return true;
    });
  }

  /// True when parsed; positional and error filled.
  bool parse(std::vector<std::string> words, std::vector<std::string>& positional,
             std::string& error)
  {
    Argv args(std::move(words));
    return cli.parse(args.argc(), args.argv(), positional, error);
  }
};

TEST(CommandLine, OptionsApplyInOrderAndFilesComeAnywhere)
{
  Tool tool;
  std::vector<std::string> files;
  std::string error;
  ASSERT_TRUE(tool.parse({"a", "--size", "2", "b", "--quiet", "--size=-3", "-h",
                          "--internal", "x", "--", "--quiet", "-"},
                         files, error))
      << error;
  EXPECT_EQ(tool.log, (std::vector<std::string>{"size=2", "quiet", "size=-3", "help",
                                                "internal=x"}));
  EXPECT_EQ(files, (std::vector<std::string>{"a", "b", "--quiet", "-"}));
}

TEST(CommandLine, ErrorsAreOneLineNamingTheOption)
{
  struct Case {
    std::vector<std::string> words;
    std::string error;
  };
  const std::vector<Case> cases = {
      {{"a", "--frobnicate"}, "unknown option '--frobnicate'"},
      {{"a", "--siz", "2"}, "unknown option '--siz'"}, // no abbreviations
      {{"a", "--size"}, "option '--size' needs a value"},
      {{"a", "--size="}, "option '--size' needs a value"},
      {{"a", "--quiet=yes"}, "option '--quiet' takes no value"},
      {{"a", "--size", "bad"}, "--size: 'bad' is not a size"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.words.back());
    Tool tool;
    std::vector<std::string> files;
    std::string error;
    EXPECT_FALSE(tool.parse(c.words, files, error));
    EXPECT_EQ(error, c.error);
  }
}

TEST(CommandLine, HelpShowsTheGroupsButNotTheHiddenOptions)
{
  const std::string help = Tool().cli.help();
  for (const char* words : {"Group one:", "Group two:", "--size S",
                            "a size (default: 1)", "--quiet", "-h [ --help ]"})
    EXPECT_NE(help.find(words), std::string::npos) << words << " in:\n" << help;
  EXPECT_EQ(help.find("internal"), std::string::npos) << help;
  EXPECT_LT(help.find("Group one:"), help.find("Group two:"));
  EXPECT_EQ(help.find(" \n"), std::string::npos) << "no trailing blanks";
}

} // namespace
} // namespace tools
} // namespace pcl_vts
