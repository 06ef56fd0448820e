// Private to the text readers (ASCII grid, XYZ, PLY headers): strict number parsing
// (the whole token or nothing; never a silent 0) and short printable excerpts of bad
// tokens for one-line messages.
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <string>

namespace pcl_vts {
namespace text {

/// The whole [first, last) is one number: optional sign, decimal or exponent form,
/// "nan"/"inf" (any case) allowed; false otherwise.
inline bool parseDouble(const char* first, const char* last, double& value)
{
  if (first != last && *first == '+')
    ++first;
  if (first == last || *first == '+')
    return false;
  const auto r = std::from_chars(first, last, value);
  return r.ec == std::errc() && r.ptr == last;
}

/// The whole [first, last) is a decimal integer in [0, 2^63).
inline bool parseCount(const char* first, const char* last, std::uint64_t& value)
{
  if (first != last && *first == '+')
    ++first;
  if (first == last || last - first > 18)
    return false;
  value = 0;
  for (const char* p = first; p != last; ++p) {
    if (*p < '0' || *p > '9')
      return false;
    value = value * 10 + static_cast<std::uint64_t>(*p - '0');
  }
  return true;
}

/// At most 40 printable characters of [first, last), "..." when cut.
inline std::string excerpt(const char* first, const char* last)
{
  std::string out;
  for (const char* p = first; p != last && out.size() < 40; ++p)
    out += (*p >= 32 && *p < 127) ? *p : '?';
  if (last - first > 40)
    out += "...";
  return out;
}

inline bool isSpace(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

/// Lower-case ASCII copy.
inline std::string lower(std::string s)
{
  for (char& c : s)
    if (c >= 'A' && c <= 'Z')
      c = static_cast<char>(c - 'A' + 'a');
  return s;
}

} // namespace text
} // namespace pcl_vts
