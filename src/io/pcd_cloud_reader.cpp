// PCD -> double xyz. Order matters: our own strict header scan first (magic, field
// table, claimed size against the file size), then pcl::PCDReader::readHeader (which
// allocates the claimed body size, hence the scan), then the body, then x/y/z pulled
// from the PCLPointCloud2 bytes by their own type. Every failure is one line.
#include "reader_guard.h"

#include <pcl_vts/io/pcd_cloud_reader.h>

#include <pcl/PCLPointCloud2.h>
#include <pcl/PCLPointField.h>
#include <pcl/io/pcd_io.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <limits>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

namespace pcl_vts {
namespace {

// A header longer than this is not a PCD header (PCL writes a few hundred bytes).
constexpr std::size_t MAX_HEADER_BYTES = 1 << 20;
// LZF emits at most 264 bytes per 3 input bytes (a maximal back reference), so a
// compressed body cannot expand more than 88 times; anything beyond lies.
constexpr std::uint64_t MAX_LZF_RATIO = 90;

// Same numbers as the data_type of pcl::PCDReader::readHeader.
enum class DataFormat { ASCII = 0, BINARY = 1, BINARY_COMPRESSED = 2 };

bool isHeaderKeyword(const std::string& key)
{
  static const char* const KEYWORDS[] = {"VERSION",   "FIELDS", "COLUMNS", "SIZE",
                                         "TYPE",      "COUNT",  "WIDTH",   "HEIGHT",
                                         "VIEWPOINT", "POINTS", "DATA"};
  return std::any_of(std::begin(KEYWORDS), std::end(KEYWORDS),
                     [&](const char* k) { return key == k; });
}

struct HeaderField {
  std::string name;
  int size = 0;
  char type = 0;
  std::uint64_t count = 1;
  PcdValueType value_type = PcdValueType::FLOAT32;
};

/// The header as we read it, independently of PCL.
struct HeaderScan {
  std::vector<HeaderField> fields;
  bool has_width = false, has_height = false, has_points = false;
  std::uint64_t width = 0, height = 0, points = 0;
  DataFormat format = DataFormat::ASCII;
  std::uint64_t data_idx = 0;         ///< byte offset of the body
  std::uint64_t point_step = 0;       ///< bytes per point in binary bodies
  std::uint64_t values_per_point = 0; ///< tokens per line in ASCII bodies
};

std::string quoted(const std::string& path)
{
  return "'" + path + "'";
}

/// Printable, short excerpt of a header line for an error message.
std::string excerpt(const std::string& line)
{
  std::string out;
  for (char c : line.substr(0, 40))
    out += (c >= 32 && c < 127) ? c : '?';
  if (line.size() > 40)
    out += "...";
  return out;
}

std::vector<std::string> splitTokens(const std::string& line)
{
  std::vector<std::string> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r'))
      ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r')
      ++j;
    if (j > i)
      tokens.push_back(line.substr(i, j - i));
    i = j;
  }
  return tokens;
}

bool parseUnsigned(const std::string& token, std::uint64_t& value)
{
  if (token.empty() || token.size() > 19)
    return false;
  value = 0;
  for (char c : token) {
    if (c < '0' || c > '9')
      return false;
    value = value * 10 + static_cast<std::uint64_t>(c - '0');
  }
  return true;
}

bool checkedMul(std::uint64_t a, std::uint64_t b, std::uint64_t& out)
{
  return !__builtin_mul_overflow(a, b, &out);
}

bool valueTypeOf(int size, char type, PcdValueType& out)
{
  switch (type) {
  case 'F':
    if (size == 4 || size == 8) {
      out = size == 4 ? PcdValueType::FLOAT32 : PcdValueType::FLOAT64;
      return true;
    }
    return false;
  case 'I':
  case 'U': {
    const bool s = type == 'I';
    switch (size) {
    case 1:
      out = s ? PcdValueType::INT8 : PcdValueType::UINT8;
      return true;
    case 2:
      out = s ? PcdValueType::INT16 : PcdValueType::UINT16;
      return true;
    case 4:
      out = s ? PcdValueType::INT32 : PcdValueType::UINT32;
      return true;
    case 8:
      out = s ? PcdValueType::INT64 : PcdValueType::UINT64;
      return true;
    default:
      return false;
    }
  }
  default:
    return false;
  }
}

/// Parses one header line into scan; returns an empty string or the complaint.
std::string scanHeaderLine(const std::vector<std::string>& t, HeaderScan& scan,
                           bool& done)
{
  const std::string& key = t[0];
  const std::size_t nvalues = t.size() - 1;
  if (key == "VERSION")
    return {};
  if (key == "FIELDS" || key == "COLUMNS") {
    if (!scan.fields.empty())
      return "FIELDS given twice";
    if (nvalues == 0)
      return "FIELDS lists no field";
    for (std::size_t i = 1; i < t.size(); ++i)
      scan.fields.push_back({t[i], 0, 0, 1, PcdValueType::FLOAT32});
    return {};
  }
  if (key == "SIZE" || key == "TYPE" || key == "COUNT") {
    if (scan.fields.empty())
      return key + " comes before FIELDS";
    if (nvalues != scan.fields.size())
      return key + " has " + std::to_string(nvalues) + " values but FIELDS has " +
             std::to_string(scan.fields.size());
    if (key != "SIZE" && scan.fields[0].size == 0)
      return key + " comes before SIZE";
    if (key == "COUNT" && scan.fields[0].type == 0)
      return "COUNT comes before TYPE";
    for (std::size_t i = 0; i < nvalues; ++i) {
      HeaderField& f = scan.fields[i];
      const std::string& v = t[i + 1];
      std::uint64_t u = 0;
      if (key == "SIZE") {
        if (!parseUnsigned(v, u) || (u != 1 && u != 2 && u != 4 && u != 8))
          return "SIZE '" + excerpt(v) + "' of field '" + f.name +
                 "' is not 1, 2, 4 or 8";
        f.size = static_cast<int>(u);
      } else if (key == "TYPE") {
        if (v.size() != 1)
          return "TYPE '" + excerpt(v) + "' of field '" + f.name + "' is not F, I or U";
        f.type = static_cast<char>(std::toupper(static_cast<unsigned char>(v[0])));
        if (!valueTypeOf(f.size, f.type, f.value_type))
          return "field '" + f.name + "' has unsupported TYPE " + v + " with SIZE " +
                 std::to_string(f.size);
      } else {
        if (!parseUnsigned(v, u) || u == 0 || u > (1u << 20))
          return "COUNT '" + excerpt(v) + "' of field '" + f.name +
                 "' is not in [1, 2^20]";
        f.count = u;
      }
    }
    return {};
  }
  if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
    std::uint64_t u = 0;
    if (nvalues != 1 || !parseUnsigned(t[1], u) ||
        u > std::numeric_limits<std::uint32_t>::max())
      return key + " is not a 32-bit unsigned integer";
    if (key == "WIDTH") {
      scan.width = u;
      scan.has_width = true;
    } else if (key == "HEIGHT") {
      scan.height = u;
      scan.has_height = true;
    } else {
      if (scan.fields.empty())
        return "POINTS comes before FIELDS";
      scan.points = u;
      scan.has_points = true;
    }
    return {};
  }
  if (key == "VIEWPOINT")
    return nvalues == 7 ? std::string()
                        : "VIEWPOINT needs 7 values (tx ty tz qw qx qy qz)";
  if (key == "DATA") {
    if (nvalues != 1)
      return "DATA needs one of ascii, binary, binary_compressed";
    if (t[1] == "ascii")
      scan.format = DataFormat::ASCII;
    else if (t[1] == "binary")
      scan.format = DataFormat::BINARY;
    else if (t[1] == "binary_compressed")
      scan.format = DataFormat::BINARY_COMPRESSED;
    else
      return "DATA '" + excerpt(t[1]) + "' is not ascii, binary or binary_compressed";
    done = true;
    return {};
  }
  return "unknown header keyword '" + excerpt(key) + "'";
}

/// Scans the header from the first bytes of the file (our checks, before PCL's).
Status scanHeader(const std::string& path, const std::string& head, HeaderScan& scan)
{
  std::size_t pos = 0;
  std::size_t line_no = 0;
  bool seen_keyword = false, done = false;
  while (!done) {
    if (pos >= head.size())
      return ioError(path, head.size() >= MAX_HEADER_BYTES
                               ? "not a PCD file: no DATA line in the first 1 MiB"
                               : "not a PCD file or header cut short: no DATA line");
    const std::size_t eol = head.find('\n', pos);
    const std::size_t end = eol == std::string::npos ? head.size() : eol;
    const std::string line = head.substr(pos, end - pos);
    pos = eol == std::string::npos ? head.size() : eol + 1;
    ++line_no;
    const std::vector<std::string> tokens = splitTokens(line);
    if (tokens.empty() || tokens[0][0] == '#')
      continue;
    if (!seen_keyword && !isHeaderKeyword(tokens[0]))
      return ioError(path, "not a PCD file: header line " + std::to_string(line_no) +
                               " is '" + excerpt(line) + "'");
    const std::string complaint = scanHeaderLine(tokens, scan, done);
    if (!complaint.empty())
      return ioError(path, "bad PCD header, line " + std::to_string(line_no) + ": " +
                               complaint);
    seen_keyword = true;
  }
  scan.data_idx = pos;
  if (scan.fields.empty() || scan.fields[0].size == 0 || scan.fields[0].type == 0)
    return ioError(path, "bad PCD header: FIELDS, SIZE and TYPE are all required");
  if (!scan.has_points)
    return ioError(path, "bad PCD header: no POINTS line");
  // PCL's rules: no WIDTH and HEIGHT means unorganized; HEIGHT defaults to 1.
  const std::uint64_t width = scan.has_width ? scan.width : scan.points;
  const std::uint64_t height = scan.has_height ? scan.height : 1;
  std::uint64_t wh = 0;
  if (!checkedMul(width, height, wh) || wh != scan.points)
    return ioError(path, "bad PCD header: WIDTH " + std::to_string(width) +
                             " x HEIGHT " + std::to_string(height) + " != POINTS " +
                             std::to_string(scan.points));
  scan.width = width;
  scan.height = height;
  for (const HeaderField& f : scan.fields) {
    std::uint64_t bytes = 0;
    checkedMul(static_cast<std::uint64_t>(f.size), f.count, bytes);
    scan.point_step += bytes; // at most 1000s of fields x 8 x 2^20: no overflow
    scan.values_per_point += f.count;
  }
  // PCL unpacks a compressed body with the padding ("_") fields' bytes dropped but
  // the fields' offsets kept: the rows come out misaligned, so refuse rather than
  // guess.
  if (scan.format == DataFormat::BINARY_COMPRESSED)
    for (const HeaderField& f : scan.fields)
      if (f.name == "_")
        return ioError(path,
                       "unsupported: padding field '_' in a binary_compressed body");
  if (scan.point_step > std::numeric_limits<std::uint32_t>::max())
    return ioError(path, "bad PCD header: a point would take " +
                             std::to_string(scan.point_step) + " bytes");
  return Status::success();
}

/// The claimed body must fit in the file before anything of that size is allocated.
Status checkBodySize(const std::string& path, int fd, std::uint64_t file_size,
                     const HeaderScan& scan)
{
  const std::uint64_t available = file_size - scan.data_idx;
  std::uint64_t body = 0;
  const bool fits = checkedMul(scan.points, scan.point_step, body);
  const std::string claim = "header claims " + std::to_string(scan.points) +
                            " points of " + std::to_string(scan.point_step) + " bytes";
  const std::string avail =
      "only " + std::to_string(available) + " bytes follow the header";
  switch (scan.format) {
  case DataFormat::BINARY:
    if (!fits || body > available)
      return ioError(path, "truncated or corrupt: " + claim + ", " + avail);
    return Status::success();
  case DataFormat::ASCII: {
    // Each value takes at least one character and one separator.
    std::uint64_t min_chars = 0;
    if (!checkedMul(scan.points, 2 * scan.values_per_point, min_chars) ||
        min_chars > available + 1)
      return ioError(path, "truncated or corrupt: header claims " +
                               std::to_string(scan.points) + " ASCII points of " +
                               std::to_string(scan.values_per_point) + " values, " +
                               avail);
    return Status::success();
  }
  case DataFormat::BINARY_COMPRESSED: {
    std::uint32_t sizes[2] = {0, 0};
    if (available < 8 || pread(fd, sizes, 8, static_cast<off_t>(scan.data_idx)) != 8)
      return ioError(path, "truncated: the compressed body has no size header");
    const std::uint64_t compressed = sizes[0], uncompressed = sizes[1];
    if (compressed == 0 || compressed > available - 8)
      return ioError(path, "truncated or corrupt: compressed body of " +
                               std::to_string(compressed) + " bytes, " + avail);
    if (!fits || uncompressed != body)
      return ioError(path, "corrupt: " + claim +
                               " but the compressed body unpacks to " +
                               std::to_string(uncompressed) + " bytes");
    if (uncompressed > compressed * MAX_LZF_RATIO + 1024)
      return ioError(path, "corrupt: " + std::to_string(compressed) +
                               " compressed bytes cannot hold " +
                               std::to_string(uncompressed) + " bytes");
    return Status::success();
  }
  }
  return Status::success();
}

/// Picks the field for one axis: exact lower case first, then upper case.
int findAxisField(const std::vector<pcl::PCLPointField>& fields, char lower)
{
  const std::string lo(1, lower);
  const std::string up(1, static_cast<char>(std::toupper(lower)));
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name == lo)
      return static_cast<int>(i);
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name == up)
      return static_cast<int>(i);
  return -1;
}

bool valueTypeOfPcl(std::uint8_t datatype, PcdValueType& out)
{
  switch (datatype) {
  case pcl::PCLPointField::INT8:
    out = PcdValueType::INT8;
    return true;
  case pcl::PCLPointField::UINT8:
    out = PcdValueType::UINT8;
    return true;
  case pcl::PCLPointField::INT16:
    out = PcdValueType::INT16;
    return true;
  case pcl::PCLPointField::UINT16:
    out = PcdValueType::UINT16;
    return true;
  case pcl::PCLPointField::INT32:
    out = PcdValueType::INT32;
    return true;
  case pcl::PCLPointField::UINT32:
    out = PcdValueType::UINT32;
    return true;
  case pcl::PCLPointField::INT64:
    out = PcdValueType::INT64;
    return true;
  case pcl::PCLPointField::UINT64:
    out = PcdValueType::UINT64;
    return true;
  case pcl::PCLPointField::FLOAT32:
    out = PcdValueType::FLOAT32;
    return true;
  case pcl::PCLPointField::FLOAT64:
    out = PcdValueType::FLOAT64;
    return true;
  default:
    return false;
  }
}

template <typename T>
double load(const std::uint8_t* p)
{
  T v;
  std::memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
}

double loadValue(const std::uint8_t* p, PcdValueType type)
{
  switch (type) {
  case PcdValueType::INT8:
    return load<std::int8_t>(p);
  case PcdValueType::UINT8:
    return load<std::uint8_t>(p);
  case PcdValueType::INT16:
    return load<std::int16_t>(p);
  case PcdValueType::UINT16:
    return load<std::uint16_t>(p);
  case PcdValueType::INT32:
    return load<std::int32_t>(p);
  case PcdValueType::UINT32:
    return load<std::uint32_t>(p);
  case PcdValueType::INT64:
    return load<std::int64_t>(p);
  case PcdValueType::UINT64:
    return load<std::uint64_t>(p);
  case PcdValueType::FLOAT32:
    return load<float>(p);
  case PcdValueType::FLOAT64:
    return load<double>(p);
  }
  return 0.0;
}

/// Strict number: the whole token, optional sign, decimal, "nan"/"inf" allowed.
bool parseNumber(const char* first, const char* last, double& value)
{
  if (first != last && *first == '+')
    ++first;
  const auto r = std::from_chars(first, last, value);
  return r.ec == std::errc() && r.ptr == last;
}

/// PCL's readBodyASCII stores 0 for a short line or an unparsable value and only
/// warns, so ASCII bodies are read here, strictly, straight into doubles.
Status readAsciiBody(const std::string& path, const HeaderScan& scan,
                     const std::array<std::uint64_t, 3>& column,
                     std::vector<double>& xyz, PointOutput& output)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return ioError(path, std::string("cannot reopen: ") + std::strerror(errno));
  in.seekg(static_cast<std::streamoff>(scan.data_idx));
  xyz.reserve(3 * output.reserve(static_cast<std::size_t>(scan.points)));
  std::string line;
  std::uint64_t read = 0, line_no = 0;
  std::vector<std::pair<const char*, const char*>> tokens;
  tokens.reserve(scan.values_per_point + 1);
  while (std::getline(in, line)) {
    ++line_no;
    tokens.clear();
    const char* p = line.data();
    const char* end = p + line.size();
    while (p < end && tokens.size() <= scan.values_per_point) {
      while (p < end && (*p == ' ' || *p == '\t' || *p == '\r'))
        ++p;
      const char* q = p;
      while (q < end && *q != ' ' && *q != '\t' && *q != '\r')
        ++q;
      if (q > p)
        tokens.emplace_back(p, q);
      p = q;
    }
    if (tokens.empty())
      continue;
    if (read == scan.points)
      return ioError(path, "corrupt: the ASCII body holds more than the " +
                               std::to_string(scan.points) + " points of its header");
    if (tokens.size() != scan.values_per_point)
      return ioError(path, "corrupt: body line " + std::to_string(line_no) + " has " +
                               (tokens.size() > scan.values_per_point
                                    ? std::string("more than ")
                                    : std::string()) +
                               std::to_string(tokens.size()) + " values, expected " +
                               std::to_string(scan.values_per_point));
    for (int a = 0; a < 3; ++a) {
      const auto& tok = tokens[column[a]];
      double value = 0.0;
      if (!parseNumber(tok.first, tok.second, value))
        return ioError(path, "corrupt: body line " + std::to_string(line_no) +
                                 ": value '" +
                                 excerpt(std::string(tok.first, tok.second)) +
                                 "' is not a number");
      xyz.push_back(value);
    }
    ++read;
    if (output.full(xyz))
      if (Status s = output.handOver(xyz, nullptr); !s.ok())
        return s;
  }
  if (in.bad())
    return ioError(path, std::string("read failed: ") + std::strerror(errno));
  if (read != scan.points)
    return ioError(path, "truncated: header claims " + std::to_string(scan.points) +
                             " points, the ASCII body holds " + std::to_string(read));
  return Status::success();
}

/// The header with WIDTH, HEIGHT and POINTS set to 1, for PCL's header check.
std::string headerOfOnePoint(const std::string& header)
{
  std::string out;
  std::istringstream lines(header);
  for (std::string line; std::getline(lines, line);) {
    const std::vector<std::string> t = splitTokens(line);
    if (!t.empty() && (t[0] == "WIDTH" || t[0] == "HEIGHT" || t[0] == "POINTS"))
      line = t[0] + " 1";
    out += line + "\n";
  }
  return out;
}

/// Maps the file open on fd; the size must still be the one the header was checked
/// against (the body is read through the mapping).
Status mapWhole(const std::string& path, int fd, std::uint64_t file_size,
                MappedFile& map)
{
  if (Status s = map.open(fd, path); !s.ok())
    return s;
  if (map.size() != file_size)
    return ioError(path, "the file changed while it was read");
  return Status::success();
}

/// Lets PCL unpack an LZF-compressed body (whole: its columns are stored one after
/// the other).
Status readCompressedBody(const std::string& path, int fd, std::uint64_t file_size,
                          const HeaderScan& scan, int pcd_version,
                          pcl::PCLPointCloud2& cloud)
{
  MappedFile map;
  if (Status s = mapWhole(path, fd, file_size, map); !s.ok())
    return s;
  const int rc = pcl::PCDReader().readBodyBinary(
      map.data(), cloud, pcd_version, true, static_cast<unsigned int>(scan.data_idx));
  map.close();
  if (rc != 0)
    return ioError(path, "corrupt: PCL could not unpack the binary body");
  if (cloud.data.size() != scan.points * scan.point_step)
    return ioError(path, "corrupt: the binary body does not match the header");
  return Status::success();
}

/// x, y, z of each record of a row-major binary body, in chunks through output.
/// (PCL's reader of an uncompressed body is a copy of these bytes.)
Status readRecords(const std::uint8_t* body, std::uint64_t points,
                   std::uint64_t point_step,
                   const std::vector<pcl::PCLPointField>& fields,
                   const std::array<int, 3>& axis, const PcdCloudInfo& info,
                   std::vector<double>& xyz, PointOutput& output)
{
  xyz.reserve(3 * output.reserve(static_cast<std::size_t>(points)));
  for (std::uint64_t i = 0; i < points; ++i) {
    const std::uint8_t* point = body + i * point_step;
    for (int a = 0; a < 3; ++a)
      xyz.push_back(loadValue(point + fields[axis[a]].offset, info.xyz_types[a]));
    if (output.full(xyz))
      if (Status s = output.handOver(xyz, point + point_step); !s.ok())
        return s;
  }
  return Status::success();
}

/// Closes a descriptor on every return path.
struct FdCloser {
  int fd;
  ~FdCloser()
  {
    if (fd >= 0)
      ::close(fd);
  }
};

Status readPcdCloudImpl(const std::string& path, std::vector<double>& xyz,
                        PcdCloudInfo& info, PointOutput& output)
{
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    return ioError(path, std::string("cannot open: ") + std::strerror(errno));
  FdCloser closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    return ioError(path, std::string("cannot stat: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode))
    return ioError(path, "not a regular file");
  const auto file_size = static_cast<std::uint64_t>(st.st_size);
  // pcl::io::loadPCDFile crashes on an empty file: never let PCL see one.
  if (file_size == 0)
    return ioError(path, "the file is empty (0 bytes)");

  std::string head(std::min<std::uint64_t>(file_size, MAX_HEADER_BYTES), '\0');
  const ssize_t got = ::pread(fd, head.data(), head.size(), 0);
  if (got < 0)
    return ioError(path, std::string("read failed: ") + std::strerror(errno));
  head.resize(static_cast<std::size_t>(got));

  HeaderScan scan;
  Status status = scanHeader(path, head, scan);
  if (!status.ok())
    return status;
  if (scan.points == 0)
    return Status::error(StatusCode::EMPTY_INPUT, quoted(path) + " holds 0 points");
  status = checkBodySize(path, fd, file_size, scan);
  if (!status.ok())
    return status;

  pcl::PCLPointCloud2 cloud;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int pcd_version = 0, data_type = 0;
  unsigned int data_idx = 0;
  // PCL parses only the header bytes we scanned (on some damaged files it read a
  // claim from past the DATA line), with one point claimed: it allocates and zeroes
  // the body its header claims, which a streamed read must not hold.
  const std::string one_point =
      headerOfOnePoint(head.substr(0, static_cast<std::size_t>(scan.data_idx)));
  std::istringstream header_only(one_point);
  if (pcl::PCDReader().readHeader(header_only, cloud, origin, orientation, pcd_version,
                                  data_type, data_idx) != 0)
    return ioError(path, "bad PCD header: PCL's reader rejects it");
  if (cloud.width != 1 || cloud.height != 1 || cloud.point_step != scan.point_step ||
      data_idx != one_point.size() || data_type != static_cast<int>(scan.format) ||
      cloud.fields.size() != scan.fields.size() || cloud.data.size() != scan.point_step)
    return ioError(path, "bad PCD header: PCL's reader reads it differently");
  cloud.width = static_cast<std::uint32_t>(scan.width);
  cloud.height = static_cast<std::uint32_t>(scan.height);
  cloud.row_step = static_cast<std::uint32_t>(scan.width * scan.point_step);

  std::array<int, 3> axis{};
  for (int a = 0; a < 3; ++a) {
    axis[a] = findAxisField(cloud.fields, "xyz"[a]);
    if (axis[a] < 0) {
      std::string names;
      for (const HeaderField& f : scan.fields)
        names += (names.empty() ? "" : " ") + f.name;
      return ioError(path, std::string("no '") + "xyz"[a] +
                               "' field (fields: " + names + ")");
    }
    const pcl::PCLPointField& f = cloud.fields[axis[a]];
    if (f.count != 1)
      return ioError(path, "field '" + f.name + "' has COUNT " +
                               std::to_string(f.count) + ", expected 1");
    if (!valueTypeOfPcl(f.datatype, info.xyz_types[a]) ||
        info.xyz_types[a] != scan.fields[axis[a]].value_type)
      return ioError(path, "field '" + f.name + "' has an unsupported type");
    info.xyz_names[a] = f.name;
  }

  cloud.data.clear();
  cloud.data.shrink_to_fit();
  std::size_t delivered = 0;
  if (scan.format == DataFormat::ASCII) {
    std::array<std::uint64_t, 3> column{};
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < axis[a]; ++i)
        column[a] += scan.fields[i].count;
    output.begin(nullptr);
    status = readAsciiBody(path, scan, column, xyz, output);
    if (status.ok())
      status = output.finish(xyz, nullptr, delivered);
  } else if (scan.format == DataFormat::BINARY) {
    // Straight from the mapped file, its pages dropped behind the reader.
    MappedFile map;
    if (Status s = mapWhole(path, fd, file_size, map); !s.ok())
      return s;
    const std::uint8_t* body = map.data() + scan.data_idx;
    output.begin(body);
    status = readRecords(body, scan.points, scan.point_step, cloud.fields, axis, info,
                         xyz, output);
    if (status.ok())
      status = output.finish(xyz, body + scan.points * scan.point_step, delivered);
  } else {
    cloud.data.resize(static_cast<std::size_t>(scan.points * scan.point_step));
    status = readCompressedBody(path, fd, file_size, scan, pcd_version, cloud);
    if (!status.ok())
      return status;
    output.begin(nullptr);
    status = readRecords(cloud.data.data(), scan.points, cloud.point_step, cloud.fields,
                         axis, info, xyz, output);
    if (status.ok())
      status = output.finish(xyz, nullptr, delivered);
  }
  if (!status.ok())
    return status;
  if (delivered != scan.points)
    return ioError(path, "internal: " + std::to_string(delivered) + " of " +
                             std::to_string(scan.points) + " points delivered");

  info.points = scan.points;
  info.width = static_cast<std::uint32_t>(scan.width);
  info.height = static_cast<std::uint32_t>(scan.height);
  info.data_format = scan.format == DataFormat::ASCII    ? "ascii"
                     : scan.format == DataFormat::BINARY ? "binary"
                                                         : "binary_compressed";
  info.fields.clear();
  for (const HeaderField& f : scan.fields)
    info.fields += (info.fields.empty() ? "" : " ") + f.name;
  return Status::success();
}

/// The read with its post-conditions: nothing half-filled on error, exceptions of PCL
/// and of allocation turned into one line.
Status readPcdCloudWith(const std::string& path, std::vector<double>& xyz,
                        PcdCloudInfo& info, PointOutput& output)
{
  info = PcdCloudInfo();
  Status status;
  try {
    status = readPcdCloudImpl(path, xyz, info, output);
  } catch (const std::bad_alloc&) {
    status = ioError(path, "out of memory while reading");
  } catch (const std::exception& e) {
    status = ioError(path, std::string("read failed: ") + e.what());
  }
  if (!status.ok()) {
    xyz.clear();
    xyz.shrink_to_fit();
  }
  return status;
}

} // namespace

const char* pcdValueTypeName(PcdValueType type)
{
  switch (type) {
  case PcdValueType::INT8:
    return "int8";
  case PcdValueType::UINT8:
    return "uint8";
  case PcdValueType::INT16:
    return "int16";
  case PcdValueType::UINT16:
    return "uint16";
  case PcdValueType::INT32:
    return "int32";
  case PcdValueType::UINT32:
    return "uint32";
  case PcdValueType::INT64:
    return "int64";
  case PcdValueType::UINT64:
    return "uint64";
  case PcdValueType::FLOAT32:
    return "float32";
  case PcdValueType::FLOAT64:
    return "float64";
  }
  return "unknown";
}

bool PcdCloudInfo::xyzAllFloat32() const
{
  return std::all_of(xyz_types.begin(), xyz_types.end(),
                     [](PcdValueType t) { return t == PcdValueType::FLOAT32; });
}

bool PcdCloudInfo::xyzAnyFloat64() const
{
  return std::any_of(xyz_types.begin(), xyz_types.end(),
                     [](PcdValueType t) { return t == PcdValueType::FLOAT64; });
}

std::string PcdCloudInfo::xyzDescription() const
{
  if (xyz_types[0] == xyz_types[1] && xyz_types[1] == xyz_types[2])
    return xyz_names[0] + " " + xyz_names[1] + " " + xyz_names[2] + " " +
           pcdValueTypeName(xyz_types[0]);
  std::string out;
  for (int a = 0; a < 3; ++a)
    out += (a ? " " : "") + xyz_names[a] + ":" + pcdValueTypeName(xyz_types[a]);
  return out;
}

Status readPcdCloud(const std::string& path, std::vector<double>& xyz,
                    PcdCloudInfo& info)
{
  PointOutput whole;
  return readPcdCloudWith(path, xyz, info, whole);
}

Status readPcdCloudChunks(const std::string& path, std::size_t chunk_points,
                          const PointOutput::Sink& sink, PcdCloudInfo& info)
{
  std::vector<double> chunk;
  PointOutput output(sink, chunk_points);
  return readPcdCloudWith(path, chunk, info, output);
}

} // namespace pcl_vts
