// Input expansion and sizes for pcd_to_mesh (input_list.h).
#include "input_list.h"

#include <pcl_vts/io/point_cloud_loader.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace pcl_vts {
namespace tools {
namespace {

namespace fs = std::filesystem;

bool expandFolder(const std::string& folder, std::vector<std::string>& files,
                  std::string& error)
{
  std::vector<std::string> found;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    CloudFileFormat format;
    if (it->is_regular_file(ec) &&
        cloudFileFormatFromExtension(it->path().string(), format))
      found.push_back(it->path().string());
  }
  if (ec) {
    error = "cannot list folder '" + folder + "': " + ec.message();
    return false;
  }
  if (found.empty()) {
    error = "folder '" + folder + "' holds no file with a supported extension";
    return false;
  }
  std::sort(found.begin(), found.end());
  files.insert(files.end(), found.begin(), found.end());
  return true;
}

std::string trimmed(const std::string& line)
{
  std::size_t a = 0, b = line.size();
  while (a < b && std::isspace(static_cast<unsigned char>(line[a])))
    ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(line[b - 1])))
    --b;
  return line.substr(a, b - a);
}

} // namespace

bool expandInputs(const std::vector<std::string>& arguments,
                  std::vector<std::string>& files, std::string& error)
{
  for (const std::string& argument : arguments) {
    std::error_code ec;
    if (argument.size() > 1 && argument[0] == '@') {
      const std::string list = argument.substr(1);
      std::ifstream in(list);
      if (!in) {
        error = "cannot read input list '" + list + "'";
        return false;
      }
      const fs::path base = fs::path(list).parent_path();
      std::vector<std::string> listed;
      for (std::string line; std::getline(in, line);) {
        line = trimmed(line);
        if (line.empty() || line[0] == '#')
          continue;
        listed.push_back(fs::path(line).is_absolute() ? line : (base / line).string());
      }
      if (listed.empty()) {
        error = "input list '" + list + "' names no file";
        return false;
      }
      if (!expandInputs(listed, files, error))
        return false;
    } else if (fs::is_directory(argument, ec)) {
      if (!expandFolder(argument, files, error))
        return false;
    } else {
      files.push_back(argument);
    }
  }
  return true;
}

bool parseByteSize(const std::string& text, std::uint64_t& bytes)
{
  std::size_t k = 0;
  std::uint64_t value = 0;
  while (k < text.size() && std::isdigit(static_cast<unsigned char>(text[k]))) {
    if (value > (UINT64_MAX - 9) / 10)
      return false;
    value = value * 10 + static_cast<std::uint64_t>(text[k++] - '0');
  }
  if (k == 0)
    return false;
  std::string suffix = text.substr(k);
  for (char& c : suffix)
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (suffix.size() == 2 && suffix[1] == 'B')
    suffix.pop_back();
  int shift = 0;
  if (suffix == "K")
    shift = 10;
  else if (suffix == "M")
    shift = 20;
  else if (suffix == "G")
    shift = 30;
  else if (suffix == "T")
    shift = 40;
  else if (!suffix.empty() && suffix != "B")
    return false;
  if (value == 0 || value > (UINT64_MAX >> shift))
    return false;
  bytes = value << shift;
  return true;
}

std::uint64_t physicalMemoryBytes()
{
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0
             ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page)
             : 0;
}

} // namespace tools
} // namespace pcl_vts
