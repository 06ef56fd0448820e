// See command_line.h.
#include "command_line.h"

#include <boost/program_options/parsers.hpp>
#include <boost/program_options/positional_options.hpp>
#include <boost/program_options/value_semantic.hpp>

#include <algorithm>
#include <sstream>

namespace pcl_vts {
namespace tools {
namespace {

namespace po = boost::program_options;

/// The key of the positional arguments: no option can have it (a space).
const char* const POSITIONAL = "positional arguments";

std::string longName(const char* name)
{
  const std::string text = name;
  return text.substr(0, text.find(','));
}

} // namespace

CommandLine::Apply CommandLine::text(std::string& target)
{
  return [&target](const std::string& value, std::string&) {
    target = value;
    return true;
  };
}

CommandLine::CommandLine(unsigned width)
    : width_(width)
    , hidden_(std::make_unique<po::options_description>())
{
  hidden_->add_options()(POSITIONAL, po::value<std::vector<std::string>>());
}

CommandLine& CommandLine::group(const std::string& caption)
{
  groups_.push_back(
      std::make_unique<po::options_description>(caption, width_, width_ / 2));
  return *this;
}

CommandLine& CommandLine::value(const char* name, const char* value_name,
                                const std::string& help, Apply apply)
{
  if (groups_.empty())
    group("Options");
  groups_.back()->add_options()(name, po::value<std::string>()->value_name(value_name),
                                help.c_str());
  options_.emplace_back(longName(name), Option{std::move(apply), nullptr});
  return *this;
}

CommandLine& CommandLine::flag(const char* name, const std::string& help,
                               std::function<void()> apply)
{
  if (groups_.empty())
    group("Options");
  groups_.back()->add_options()(name, new po::untyped_value(true), help.c_str());
  options_.emplace_back(longName(name), Option{nullptr, std::move(apply)});
  return *this;
}

CommandLine& CommandLine::hiddenValue(const char* name, Apply apply)
{
  hidden_->add_options()(name, po::value<std::string>());
  options_.emplace_back(longName(name), Option{std::move(apply), nullptr});
  return *this;
}

bool CommandLine::parse(int argc, char** argv, std::vector<std::string>& positional,
                        std::string& error) const
{
  po::options_description all;
  for (const auto& g : groups_)
    all.add(*g);
  all.add(*hidden_);
  po::positional_options_description positions;
  positions.add(POSITIONAL, -1);
  // Strict: no abbreviations (--cell for --cell-size), no /x options.
  const int style =
      po::command_line_style::default_style & ~po::command_line_style::allow_guessing;
  std::vector<po::option> options;
  try {
    options = po::command_line_parser(argc, argv)
                  .options(all)
                  .positional(positions)
                  .style(style)
                  .run()
                  .options;
  } catch (const po::unknown_option& e) {
    error = "unknown option '" + e.get_option_name() + "'";
    return false;
  } catch (const po::invalid_command_line_syntax& e) {
    const std::string name = "option '" + e.get_option_name() + "'";
    error = e.kind() == po::invalid_syntax::extra_parameter ? name + " takes no value"
            : e.kind() == po::invalid_syntax::missing_parameter ||
                    e.kind() == po::invalid_syntax::empty_adjacent_parameter
                ? name + " needs a value"
                : e.what();
    return false;
  } catch (const po::error& e) {
    error = e.what();
    return false;
  }
  for (const po::option& given : options) {
    if (given.string_key == POSITIONAL) {
      positional.insert(positional.end(), given.value.begin(), given.value.end());
      continue;
    }
    const auto it = std::find_if(options_.begin(), options_.end(), [&](const auto& o) {
      return o.first == given.string_key;
    });
    if (it == options_.end()) { // declared to Program_options but not here: a bug
      error = "internal: option '--" + given.string_key + "' has no setting";
      return false;
    }
    if (it->second.flag) {
      it->second.flag();
      continue;
    }
    const std::string value = given.value.empty() ? std::string() : given.value[0];
    if (!it->second.apply(value, error))
      return false;
  }
  return true;
}

std::string CommandLine::help() const
{
  po::options_description visible(width_, width_ / 2);
  for (const auto& g : groups_)
    visible.add(*g);
  std::ostringstream out;
  out << visible;
  // Program_options leaves a blank at the end of each wrapped line.
  std::istringstream lines(out.str());
  std::string text;
  for (std::string line; std::getline(lines, line);)
    text += line.erase(line.find_last_not_of(' ') + 1) + "\n";
  return text;
}

} // namespace tools
} // namespace pcl_vts
