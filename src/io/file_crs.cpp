// See file_crs.h. The LAS header is read with plain stream reads (the records sit
// between the header and the points, or after them as 1.4 EVLRs): independent of
// the point reader, which maps the whole file.
#include "little_endian.h"

#include <pcl_vts/io/file_crs.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sys/stat.h>
#include <vector>

namespace pcl_vts {

namespace {

constexpr std::size_t VLR_HEADER = 54;
constexpr std::size_t EVLR_HEADER = 60;
constexpr std::uint16_t WKT_RECORD = 2112;
constexpr std::uint16_t GEOKEY_RECORD = 34735;
constexpr std::uint16_t PROJECTED_CS_KEY = 3072;
constexpr std::uint16_t GEOGRAPHIC_TYPE_KEY = 2048;
constexpr std::uint16_t USER_DEFINED = 32767;
constexpr std::uint64_t MAX_RECORD = 1u << 20; // a WKT is a few KiB

std::string trimmed(const std::string& s)
{
  std::size_t end = s.find('\0');
  if (end == std::string::npos)
    end = s.size();
  std::size_t begin = 0;
  while (begin < end && std::isspace(static_cast<unsigned char>(s[begin])))
    ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(s[end - 1])))
    --end;
  return s.substr(begin, end - begin);
}

bool readAt(std::ifstream& in, std::uint64_t at, std::size_t n,
            std::vector<std::uint8_t>& out)
{
  out.resize(n);
  in.clear();
  in.seekg(static_cast<std::streamoff>(at));
  in.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(n));
  return static_cast<std::size_t>(in.gcount()) == n;
}

/// The EPSG code in a GeoKeyDirectory, 0 when none.
unsigned geoKeyEpsg(const std::vector<std::uint8_t>& body)
{
  if (body.size() < 8)
    return 0;
  const std::size_t keys = u16(body.data() + 6);
  unsigned projected = 0, geographic = 0;
  for (std::size_t k = 0; k < keys && 8 + 8 * (k + 1) <= body.size(); ++k) {
    const std::uint8_t* e = body.data() + 8 + 8 * k;
    if (u16(e + 2) != 0) // stored elsewhere: not a short code
      continue;
    const unsigned id = u16(e), value = u16(e + 6);
    if (value == 0 || value == USER_DEFINED)
      continue;
    if (id == PROJECTED_CS_KEY)
      projected = value;
    else if (id == GEOGRAPHIC_TYPE_KEY)
      geographic = value;
  }
  return projected ? projected : geographic;
}

} // namespace

Status readLasCrs(const std::string& path, std::string& crs, std::string& source)
{
  crs.clear();
  source.clear();
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return Status::error(StatusCode::IO_ERROR,
                         "'" + path + "': cannot open: " + std::strerror(errno));
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(in.tellg());
  std::vector<std::uint8_t> head;
  if (!readAt(in, 0, 227, head) || std::memcmp(head.data(), "LASF", 4) != 0)
    return Status::success(); // the point reader reports what is wrong
  const unsigned minor = head[25];
  const std::uint64_t header_size = u16(head.data() + 94);
  const std::uint64_t offset_to_points = u32(head.data() + 96);
  const std::uint32_t vlrs = u32(head.data() + 100);
  std::string wkt;
  unsigned epsg = 0;
  std::vector<std::uint8_t> rec, body;
  auto consider = [&](const std::uint8_t* r, std::uint64_t body_at,
                      std::uint64_t length) {
    if (std::string(reinterpret_cast<const char*>(r + 2),
                    strnlen(reinterpret_cast<const char*>(r + 2), 16)) !=
            "LASF_Projection" ||
        length > MAX_RECORD)
      return;
    const std::uint16_t id = u16(r + 18);
    if (id != WKT_RECORD && id != GEOKEY_RECORD)
      return;
    if (!readAt(in, body_at, static_cast<std::size_t>(length), body))
      return;
    if (id == WKT_RECORD && wkt.empty())
      wkt = trimmed(std::string(body.begin(), body.end()));
    else if (id == GEOKEY_RECORD && !epsg)
      epsg = geoKeyEpsg(body);
  };
  std::uint64_t at = header_size;
  for (std::uint32_t v = 0; v < vlrs; ++v) {
    if (at + VLR_HEADER > offset_to_points || !readAt(in, at, VLR_HEADER, rec))
      break;
    const std::uint64_t length = u16(rec.data() + 20);
    if (at + VLR_HEADER + length > offset_to_points)
      break;
    consider(rec.data(), at + VLR_HEADER, length);
    at += VLR_HEADER + length;
  }
  if (minor >= 4 && readAt(in, 0, 375, head)) {
    std::uint64_t eat = u64(head.data() + 235);
    const std::uint32_t evlrs = u32(head.data() + 243);
    for (std::uint32_t v = 0; v < evlrs && eat != 0; ++v) {
      if (eat + EVLR_HEADER > size || !readAt(in, eat, EVLR_HEADER, rec))
        break;
      const std::uint64_t length = u64(rec.data() + 20);
      if (length > size - eat - EVLR_HEADER)
        break;
      consider(rec.data(), eat + EVLR_HEADER, length);
      eat += EVLR_HEADER + length;
    }
  }
  if (!wkt.empty()) {
    crs = wkt;
    source = "LAS OGC WKT record";
  } else if (epsg) {
    crs = "EPSG:" + std::to_string(epsg);
    source = "LAS GeoTIFF keys";
  }
  return Status::success();
}

Status readPrjSidecar(const std::string& path, std::string& crs, std::string& source)
{
  crs.clear();
  source.clear();
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  const std::string stem =
      dot == std::string::npos || (slash != std::string::npos && dot < slash)
          ? path
          : path.substr(0, dot);
  for (const char* ext : {".prj", ".PRJ"}) {
    const std::string prj = stem + ext;
    struct stat st {};
    if (::stat(prj.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
      continue;
    std::ifstream in(prj, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)),
                     std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof())
      return Status::error(StatusCode::IO_ERROR, "'" + prj + "': cannot read");
    crs = trimmed(text);
    if (!crs.empty())
      source = "'" + prj + "'";
    return Status::success();
  }
  return Status::success();
}

} // namespace pcl_vts
