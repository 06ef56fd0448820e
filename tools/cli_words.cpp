// See cli_words.h. The words are the libraries' own names of their values, so that a
// summary line and the option that set it agree.
#include "cli_words.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace pcl_vts {
namespace tools {

bool parseDuplicateRule(const std::string& word, DuplicateRule& rule)
{
  for (const DuplicateRule r : {DuplicateRule::LOWEST_Z, DuplicateRule::HIGHEST_Z,
                                DuplicateRule::MEAN_Z, DuplicateRule::FIRST})
    if (word == duplicateRuleName(r)) {
      rule = r;
      return true;
    }
  return false;
}

bool parseLasReturnFilter(const std::string& word, LasReturnFilter& filter)
{
  for (const LasReturnFilter f :
       {LasReturnFilter::ALL, LasReturnFilter::FIRST, LasReturnFilter::LAST})
    if (word == lasReturnFilterName(f)) {
      filter = f;
      return true;
    }
  return false;
}

bool parseFiniteNumber(const std::string& text, double& value)
{
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0])))
    return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (*end != '\0' || errno == ERANGE || !std::isfinite(v))
    return false;
  value = v;
  return true;
}

bool parseNumberList(const std::string& text, std::size_t count,
                     std::vector<double>& numbers)
{
  numbers.clear();
  for (std::size_t start = 0;;) {
    const std::size_t comma = text.find(',', start);
    double v = 0.0;
    if (!parseFiniteNumber(text.substr(start, comma - start), v))
      return false;
    numbers.push_back(v);
    if (comma == std::string::npos)
      return numbers.size() == count;
    start = comma + 1;
  }
}

bool parseClassList(const std::string& text, std::vector<std::uint8_t>& classes,
                    std::string& error)
{
  classes.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma - start);
    if (item.empty() || item.size() > 3 ||
        item.find_first_not_of("0123456789") != std::string::npos ||
        std::stoi(item) > 255) {
      error = "'" + item + "' in '" + text +
              "' is not a class code 0-255 (e.g. --classes 2 or 2,9)";
      classes.clear();
      return false;
    }
    const auto code = static_cast<std::uint8_t>(std::stoi(item));
    if (std::find(classes.begin(), classes.end(), code) == classes.end())
      classes.push_back(code);
    if (comma == std::string::npos)
      return true;
    start = comma + 1;
  }
}

} // namespace tools
} // namespace pcl_vts
