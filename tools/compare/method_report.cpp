// "key value" lines of a method process (method_report.h).
#include "compare_files.h"
#include "method_report.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace pcl_vts {
namespace compare {

Status writeMethodReport(const std::string& path, const MethodReport& report)
{
  std::ostringstream out;
  out.precision(17);
  out << "seconds " << report.seconds << "\n";
  out << "normal_seconds " << report.normal_seconds << "\n";
  out << "parameters " << report.parameters << "\n";
  for (const std::string& note : report.notes)
    out << "note " << note << "\n";
  return writeTextFile(path, out.str());
}

Status readMethodReport(const std::string& path, MethodReport& report)
{
  std::ifstream in(path);
  if (!in)
    return Status::error(StatusCode::IO_ERROR, path + ": cannot open");
  report = MethodReport{};
  bool have_seconds = false;
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t space = line.find(' ');
    const std::string key = line.substr(0, space);
    const std::string value = space == std::string::npos ? "" : line.substr(space + 1);
    if (key == "seconds") {
      report.seconds = std::strtod(value.c_str(), nullptr);
      have_seconds = true;
    } else if (key == "normal_seconds")
      report.normal_seconds = std::strtod(value.c_str(), nullptr);
    else if (key == "parameters")
      report.parameters = value;
    else if (key == "note")
      report.notes.push_back(value);
  }
  if (!have_seconds)
    return Status::error(StatusCode::IO_ERROR, path + ": no 'seconds' line");
  return Status::success();
}

} // namespace compare
} // namespace pcl_vts
