// Text table -> double xyz. A line splits into fields at runs of blanks and at
// single commas or semicolons (blanks around them ignored, so "1, 2, 3" and
// "1 2 3" read alike); an empty field between two commas is an error. The first
// non-comment line is a header when none of its first three fields is a number.
#include "reader_guard.h"
#include "text_scan.h"

#include <pcl_vts/io/xyz_text_reader.h>

#include <algorithm>
#include <cstring>

namespace pcl_vts {
namespace {

using Field = std::pair<const char*, const char*>;

/// Splits [p, end) into fields; false when a comma or semicolon has no value before
/// it (an empty value).
bool splitFields(const char* p, const char* end, std::vector<Field>& fields)
{
  fields.clear();
  bool after_separator = false;
  while (true) {
    while (p != end && (*p == ' ' || *p == '\t' || *p == '\r'))
      ++p;
    if (p == end)
      return true; // a trailing separator ("1,2,3,") is allowed
    if (*p == ',' || *p == ';') {
      if (fields.empty() || after_separator)
        return false;
      after_separator = true;
      ++p;
      continue;
    }
    const char* q = p;
    while (q != end && *q != ' ' && *q != '\t' && *q != '\r' && *q != ',' && *q != ';')
      ++q;
    fields.emplace_back(p, q);
    after_separator = false;
    p = q;
  }
}

std::string columnName(const Field& f)
{
  std::string s = text::lower(std::string(f.first, f.second));
  s.erase(std::remove(s.begin(), s.end(), '"'), s.end());
  s.erase(std::remove(s.begin(), s.end(), '\''), s.end());
  return s;
}

/// The first byte of [p, end) that no text file holds, or end.
const char* firstBinaryByte(const char* p, const char* end)
{
  for (; p != end; ++p) {
    const auto u = static_cast<unsigned char>(*p);
    if (u < 32 && u != '\n' && u != '\r' && u != '\t')
      return p;
  }
  return end;
}

Status parseXyzImpl(const char* p, const char* end, const std::string& name,
                    std::vector<double>& xyz, XyzTextInfo& info, PointOutput& output)
{
  if (p == end)
    return ioError(name, "the file is empty (0 bytes)");
  const char* const begin = p;
  output.begin(p);
  const auto binary = [&](const char* c) {
    return ioError(name, "not a text file: byte " +
                             std::to_string(static_cast<unsigned char>(*c)) +
                             " at offset " + std::to_string(c - begin));
  };
  // Whole, the file is checked first; streamed, line by line as it is read (a binary
  // file then fails at its first such line, after the points before it went out).
  if (!output.streaming())
    if (const char* c = firstBinaryByte(p, end); c != end)
      return binary(c);
  if (end - p >= 3 && std::memcmp(p, "\xEF\xBB\xBF", 3) == 0)
    p += 3; // UTF-8 byte order mark
  info.column = {0, 1, 2};
  std::size_t needed = 3; // fields a data line must have
  bool first = true;
  std::size_t line_no = 0;
  std::vector<Field> fields;
  xyz.clear();
  while (p != end) {
    if (output.full(xyz))
      if (Status s = output.handOver(xyz, p); !s.ok())
        return s;
    const char* eol = p;
    while (eol != end && *eol != '\n')
      ++eol;
    if (output.streaming())
      if (const char* c = firstBinaryByte(p, eol); c != eol)
        return binary(c);
    const char* line = p;
    p = eol == end ? end : eol + 1;
    ++line_no;
    const char* s = line;
    while (s != eol && (*s == ' ' || *s == '\t' || *s == '\r'))
      ++s;
    if (s == eol || *s == '#' || (eol - s >= 2 && s[0] == '/' && s[1] == '/'))
      continue;
    if (!splitFields(s, eol, fields))
      return ioError(name, "line " + std::to_string(line_no) + ": empty value in '" +
                               text::excerpt(s, eol) + "'");
    if (first) {
      first = false;
      // A header names columns: none of its first three fields is a number (a line
      // with some numbers is data, so a bad token there is an error, not a header).
      bool any_number = false;
      double ignored = 0.0;
      for (std::size_t i = 0; i < std::min<std::size_t>(3, fields.size()); ++i)
        any_number =
            any_number || text::parseDouble(fields[i].first, fields[i].second, ignored);
      if (!any_number) {
        info.header = std::string(s, eol);
        if (!info.header.empty() && info.header.back() == '\r')
          info.header.pop_back();
        std::array<bool, 3> found{};
        for (std::size_t i = 0; i < fields.size(); ++i)
          for (int a = 0; a < 3; ++a)
            if (!found[a] && columnName(fields[i]) == std::string(1, "xyz"[a])) {
              info.column[a] = i;
              found[a] = true;
            }
        if (!(found[0] && found[1] && found[2]))
          info.column = {0, 1, 2};
        needed = 1 + std::max({info.column[0], info.column[1], info.column[2]});
        continue;
      }
    }
    if (fields.size() < needed)
      return ioError(name, "line " + std::to_string(line_no) + " has " +
                               std::to_string(fields.size()) + " value(s), " +
                               std::to_string(needed) + " needed: '" +
                               text::excerpt(s, eol) + "'");
    for (int a = 0; a < 3; ++a) {
      const Field& f = fields[info.column[a]];
      double v = 0.0;
      if (!text::parseDouble(f.first, f.second, v))
        return ioError(name, "line " + std::to_string(line_no) + ": " + "xyz"[a] +
                                 " value '" + text::excerpt(f.first, f.second) +
                                 "' is not a number");
      xyz.push_back(v);
    }
  }
  if (Status s = output.finish(xyz, end, info.points); !s.ok())
    return s;
  if (info.points == 0)
    return Status::error(StatusCode::EMPTY_INPUT,
                         "'" + name + "' holds 0 points" +
                             (info.header.empty()
                                  ? std::string(" (no data line)")
                                  : std::string(" (header line only)")));
  return Status::success();
}

} // namespace

Status parseXyzText(const std::uint8_t* data, std::size_t size, const std::string& name,
                    std::vector<double>& xyz, XyzTextInfo& info)
{
  return guardedParse(name, xyz, info, [&] {
    const char* p = reinterpret_cast<const char*>(data);
    PointOutput whole;
    return parseXyzImpl(p, p + size, name, xyz, info, whole);
  });
}

Status readXyzTextChunks(const std::string& path, std::size_t chunk_points,
                         const XyzChunkSink& sink, XyzTextInfo& info)
{
  return readMappedFileInChunks(path, sink, chunk_points, info,
                                [&](const std::uint8_t* data, std::size_t size,
                                    std::vector<double>& chunk, PointOutput& output) {
                                  const char* p = reinterpret_cast<const char*>(data);
                                  return parseXyzImpl(p, p + size, path, chunk, info,
                                                      output);
                                });
}

Status readXyzText(const std::string& path, std::vector<double>& xyz, XyzTextInfo& info)
{
  return readMappedFile(path, xyz, info,
                        [&](const std::uint8_t* data, std::size_t size) {
                          return parseXyzText(data, size, path, xyz, info);
                        });
}

} // namespace pcl_vts
