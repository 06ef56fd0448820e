// PLY -> double xyz of the vertex element. The header is parsed into elements and
// properties; the body is walked element by element (binary: fixed-size scalars and
// counted lists, every read bounds-checked; ascii: whitespace tokens), stopping once
// the vertex element is read. Sizes claimed by the header are checked against the
// bytes left before anything is reserved. Paul Bourke's PLY description.
#include "reader_guard.h"
#include "text_scan.h"

#include <pcl_vts/io/ply_point_reader.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace pcl_vts {
namespace {

enum class PlyType { INT8, UINT8, INT16, UINT16, INT32, UINT32, FLOAT32, FLOAT64 };

bool plyTypeOf(const std::string& n, PlyType& t)
{
  static const std::pair<const char*, PlyType> NAMES[] = {
      {"char", PlyType::INT8},      {"int8", PlyType::INT8},
      {"uchar", PlyType::UINT8},    {"uint8", PlyType::UINT8},
      {"short", PlyType::INT16},    {"int16", PlyType::INT16},
      {"ushort", PlyType::UINT16},  {"uint16", PlyType::UINT16},
      {"int", PlyType::INT32},      {"int32", PlyType::INT32},
      {"uint", PlyType::UINT32},    {"uint32", PlyType::UINT32},
      {"float", PlyType::FLOAT32},  {"float32", PlyType::FLOAT32},
      {"double", PlyType::FLOAT64}, {"float64", PlyType::FLOAT64}};
  for (const auto& [name, type] : NAMES)
    if (n == name) {
      t = type;
      return true;
    }
  return false;
}

std::size_t sizeOf(PlyType t)
{
  switch (t) {
  case PlyType::INT8:
  case PlyType::UINT8:
    return 1;
  case PlyType::INT16:
  case PlyType::UINT16:
    return 2;
  case PlyType::INT32:
  case PlyType::UINT32:
  case PlyType::FLOAT32:
    return 4;
  case PlyType::FLOAT64:
    return 8;
  }
  return 8;
}

struct Property {
  std::string name;
  std::string type_name;
  PlyType type = PlyType::FLOAT32;
  bool is_list = false;
  PlyType count_type = PlyType::UINT8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Format { ASCII, BINARY_LE, BINARY_BE };

/// Reads one binary scalar at p (size checked by the caller).
double loadBinary(const std::uint8_t* p, PlyType t, bool big_endian)
{
  std::uint8_t b[8];
  const std::size_t n = sizeOf(t);
  for (std::size_t i = 0; i < n; ++i)
    b[i] = big_endian ? p[n - 1 - i] : p[i];
  switch (t) {
  case PlyType::INT8: {
    std::int8_t v;
    std::memcpy(&v, b, 1);
    return v;
  }
  case PlyType::UINT8:
    return b[0];
  case PlyType::INT16: {
    std::int16_t v;
    std::memcpy(&v, b, 2);
    return v;
  }
  case PlyType::UINT16: {
    std::uint16_t v;
    std::memcpy(&v, b, 2);
    return v;
  }
  case PlyType::INT32: {
    std::int32_t v;
    std::memcpy(&v, b, 4);
    return v;
  }
  case PlyType::UINT32: {
    std::uint32_t v;
    std::memcpy(&v, b, 4);
    return v;
  }
  case PlyType::FLOAT32: {
    float v;
    std::memcpy(&v, b, 4);
    return static_cast<double>(v);
  }
  case PlyType::FLOAT64: {
    double v;
    std::memcpy(&v, b, 8);
    return v;
  }
  }
  return 0.0;
}

std::vector<std::string> words(const char* p, const char* end)
{
  std::vector<std::string> out;
  while (p != end) {
    while (p != end && text::isSpace(*p))
      ++p;
    const char* q = p;
    while (q != end && !text::isSpace(*q))
      ++q;
    if (q != p)
      out.emplace_back(p, q);
    p = q;
  }
  return out;
}

/// Body reader: one cursor over the bytes after end_header.
class BodyCursor {
 public:
  BodyCursor(const char* p, const char* end, Format format)
      : p_(p)
      , end_(end)
      , format_(format)
  {}

  /// One value of type t; false (with why_ set) at the end or on a bad token.
  bool next(PlyType t, double& v)
  {
    if (format_ != Format::ASCII) {
      const std::size_t n = sizeOf(t);
      if (static_cast<std::size_t>(end_ - p_) < n) {
        why_ = "truncated";
        return false;
      }
      v = loadBinary(reinterpret_cast<const std::uint8_t*>(p_), t,
                     format_ == Format::BINARY_BE);
      p_ += n;
      return true;
    }
    while (p_ != end_ && text::isSpace(*p_))
      ++p_;
    const char* q = p_;
    while (q != end_ && !text::isSpace(*q))
      ++q;
    if (q == p_) {
      why_ = "truncated";
      return false;
    }
    if (!text::parseDouble(p_, q, v)) {
      why_ = "value '" + text::excerpt(p_, q) + "' is not a number";
      return false;
    }
    p_ = q;
    return true;
  }

  /// Where the next value starts.
  const char* at() const { return p_; }
  std::size_t left() const { return static_cast<std::size_t>(end_ - p_); }
  const std::string& why() const { return why_; }

 private:
  const char* p_;
  const char* end_;
  Format format_;
  std::string why_;
};

Status parsePlyImpl(const char* p, const char* end, const std::string& name,
                    std::vector<double>& xyz, PlyPointInfo& info, PointOutput& output)
{
  if (p == end)
    return ioError(name, "the file is empty (0 bytes)");
  if (end - p < 4 || std::memcmp(p, "ply", 3) != 0 || (p[3] != '\n' && p[3] != '\r'))
    return ioError(name, "not a PLY file: no 'ply' magic line");
  std::vector<Element> elements;
  bool has_format = false, done = false;
  Format format = Format::ASCII;
  std::size_t line_no = 0;
  while (!done) {
    if (p == end)
      return ioError(name, "PLY header cut short: no end_header line");
    const char* eol = p;
    while (eol != end && *eol != '\n')
      ++eol;
    const std::vector<std::string> w = words(p, eol);
    const std::string line_text = text::excerpt(p, eol);
    p = eol == end ? end : eol + 1;
    ++line_no;
    if (line_no > 10000)
      return ioError(name, "bad PLY header: more than 10000 lines");
    const auto bad = [&](const std::string& why) {
      return ioError(name, "bad PLY header, line " + std::to_string(line_no) + ": " +
                               why + " ('" + line_text + "')");
    };
    if (w.empty() || (line_no == 1 && w[0] == "ply"))
      continue;
    const std::string& key = w[0];
    if (key == "comment" || key == "obj_info")
      continue;
    if (key == "end_header") {
      done = true;
    } else if (key == "format") {
      if (w.size() != 3 || has_format)
        return bad("expected one 'format <kind> 1.0'");
      has_format = true;
      info.format = w[1];
      if (w[1] == "ascii")
        format = Format::ASCII;
      else if (w[1] == "binary_little_endian")
        format = Format::BINARY_LE;
      else if (w[1] == "binary_big_endian")
        format = Format::BINARY_BE;
      else
        return bad("unknown format");
    } else if (key == "element") {
      std::uint64_t count = 0;
      if (w.size() != 3 ||
          !text::parseCount(w[2].data(), w[2].data() + w[2].size(), count))
        return bad("expected 'element <name> <count>'");
      elements.push_back({w[1], count, {}});
    } else if (key == "property") {
      if (elements.empty())
        return bad("property before any element");
      Property prop;
      if (w.size() == 5 && w[1] == "list") {
        prop.is_list = true;
        if (!plyTypeOf(w[2], prop.count_type) || !plyTypeOf(w[3], prop.type) ||
            prop.count_type == PlyType::FLOAT32 || prop.count_type == PlyType::FLOAT64)
          return bad("bad list property types");
        prop.name = w[4];
      } else if (w.size() == 3 && plyTypeOf(w[1], prop.type)) {
        prop.name = w[2];
        prop.type_name = w[1];
      } else {
        return bad("expected 'property <type> <name>' or a list property");
      }
      elements.back().properties.push_back(prop);
    } else {
      return bad("unknown keyword '" +
                 text::excerpt(key.data(), key.data() + key.size()) + "'");
    }
  }
  if (!has_format)
    return ioError(name, "bad PLY header: no format line");
  const auto vertex_it =
      std::find_if(elements.begin(), elements.end(),
                   [](const Element& e) { return e.name == "vertex"; });
  if (vertex_it == elements.end())
    return ioError(name, "bad PLY header: no vertex element");
  for (const Element& e : elements)
    if (e.name == "face")
      info.faces = static_cast<std::size_t>(e.count);
  const Element& vertex = *vertex_it;
  std::array<int, 3> axis{-1, -1, -1};
  for (std::size_t i = 0; i < vertex.properties.size(); ++i)
    for (int a = 0; a < 3; ++a)
      if (!vertex.properties[i].is_list && axis[a] < 0 &&
          vertex.properties[i].name == std::string(1, "xyz"[a]))
        axis[a] = static_cast<int>(i);
  for (int a = 0; a < 3; ++a) {
    if (axis[a] < 0)
      return ioError(name, std::string("bad PLY header: the vertex element has no "
                                       "scalar '") +
                               "xyz"[a] + "' property");
    info.xyz_types[a] = vertex.properties[axis[a]].type_name;
  }
  if (vertex.count == 0)
    return Status::error(StatusCode::EMPTY_INPUT, "'" + name + "' holds 0 vertices");

  BodyCursor body(p, end, format);
  output.begin(p);
  // Each value takes at least one byte (binary) or two characters (ascii).
  const std::size_t min_bytes_per_value = format == Format::ASCII ? 2 : 1;
  for (const Element& e : elements) {
    std::uint64_t min_bytes = 0;
    if (__builtin_mul_overflow(e.count, e.properties.size() * min_bytes_per_value,
                               &min_bytes) ||
        min_bytes > body.left() + 1)
      return ioError(name, "truncated or corrupt: header claims " +
                               std::to_string(e.count) + " " + e.name +
                               " elements, only " + std::to_string(body.left()) +
                               " bytes follow the header");
    if (e.properties.empty())
      continue; // no bytes, whatever its count
    const bool is_vertex = &e == &vertex;
    if (is_vertex) {
      xyz.clear();
      xyz.reserve(3 * output.reserve(static_cast<std::size_t>(e.count)));
    }
    double point[3] = {0.0, 0.0, 0.0};
    for (std::uint64_t i = 0; i < e.count; ++i) {
      if (is_vertex && output.full(xyz))
        if (Status s = output.handOver(xyz, body.at()); !s.ok())
          return s;
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& prop = e.properties[k];
        double v = 0.0;
        std::uint64_t items = 1;
        if (prop.is_list) {
          if (!body.next(prop.count_type, v) || !(v >= 0.0 && v <= 4294967295.0) ||
              v != std::floor(v))
            return ioError(name,
                           "corrupt " + e.name + " " + std::to_string(i) + ": " +
                               (body.why().empty() ? "bad list count" : body.why()));
          items = static_cast<std::uint64_t>(v);
          if (items > body.left())
            return ioError(name, "truncated or corrupt: " + e.name + " " +
                                     std::to_string(i) + " lists " +
                                     std::to_string(items) + " values");
        }
        for (std::uint64_t j = 0; j < items; ++j)
          if (!body.next(prop.type, v))
            return ioError(name, (body.why() == "truncated"
                                      ? "truncated: the body ends in " + e.name + " " +
                                            std::to_string(i) + " of " +
                                            std::to_string(e.count)
                                      : "corrupt: " + e.name + " " + std::to_string(i) +
                                            ": " + body.why()));
        if (is_vertex)
          for (int a = 0; a < 3; ++a)
            if (static_cast<int>(k) == axis[a])
              point[a] = v;
      }
      if (is_vertex)
        xyz.insert(xyz.end(), point, point + 3);
    }
    if (is_vertex)
      break;
  }
  if (Status s = output.finish(xyz, body.at(), info.vertices); !s.ok())
    return s;
  return Status::success();
}

} // namespace

Status parsePlyPoints(const std::uint8_t* data, std::size_t size,
                      const std::string& name, std::vector<double>& xyz,
                      PlyPointInfo& info)
{
  return guardedParse(name, xyz, info, [&] {
    const char* p = reinterpret_cast<const char*>(data);
    PointOutput whole;
    return parsePlyImpl(p, p + size, name, xyz, info, whole);
  });
}

Status readPlyPointChunks(const std::string& path, std::size_t chunk_points,
                          const PlyChunkSink& sink, PlyPointInfo& info)
{
  return readMappedFileInChunks(path, sink, chunk_points, info,
                                [&](const std::uint8_t* data, std::size_t size,
                                    std::vector<double>& chunk, PointOutput& output) {
                                  const char* p = reinterpret_cast<const char*>(data);
                                  return parsePlyImpl(p, p + size, path, chunk, info,
                                                      output);
                                });
}

Status readPlyPoints(const std::string& path, std::vector<double>& xyz,
                     PlyPointInfo& info)
{
  return readMappedFile(path, xyz, info,
                        [&](const std::uint8_t* data, std::size_t size) {
                          return parsePlyPoints(data, size, path, xyz, info);
                        });
}

} // namespace pcl_vts
