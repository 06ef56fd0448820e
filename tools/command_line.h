// The command lines of pcd_to_mesh and compare_methods, read by Boost.Program_options:
// `--name VALUE`, `--name=VALUE`, `-h`, positional arguments anywhere, `--` ending the
// options. Each option is declared once, with its --help text and the function that
// turns its value into a typed setting; the values are applied in command-line order
// (a repeated option: the last one wins), and every failure is one line naming the
// option, for the tool's usage error (exit 1).
#pragma once

#include <boost/program_options/options_description.hpp>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pcl_vts {
namespace tools {

class CommandLine {
 public:
  /// Turns an option's value into a setting; false with a one-line reason.
  using Apply = std::function<bool(const std::string& value, std::string& error)>;
  /// The value as it is, into target (a path, a name).
  static Apply text(std::string& target);

  /// width: the --help line length.
  explicit CommandLine(unsigned width = 80);

  /// The options declared next go under this heading in --help.
  CommandLine& group(const std::string& caption);
  /// An option with a value: `name` is the long name, with ",x" for a short one;
  /// value_name is how --help shows the value.
  CommandLine& value(const char* name, const char* value_name, const std::string& help,
                     Apply apply);
  /// An option without a value.
  CommandLine& flag(const char* name, const std::string& help,
                    std::function<void()> apply);
  /// An option with a value that --help does not show (between a tool's processes).
  CommandLine& hiddenValue(const char* name, Apply apply);

  /// Parses argv[1..argc): the positional arguments in order into `positional`, the
  /// options applied in order. False with error set to "unknown option '--x'",
  /// "option '--x' needs a value", "option '--x' takes no value" or what an Apply
  /// said.
  bool parse(int argc, char** argv, std::vector<std::string>& positional,
             std::string& error) const;

  /// The option groups as --help shows them.
  std::string help() const;

 private:
  struct Option {
    Apply apply;
    std::function<void()> flag;
  };
  unsigned width_;
  std::vector<std::unique_ptr<boost::program_options::options_description>> groups_;
  std::unique_ptr<boost::program_options::options_description> hidden_;
  std::vector<std::pair<std::string, Option>> options_; ///< by long name
};

} // namespace tools
} // namespace pcl_vts
