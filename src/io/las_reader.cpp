// LAS and LAZ -> double xyz. Order matters: signature, version, header size,
// compression (format bits, then a bounded walk of the VLRs for the laszip record),
// point format and record length, point count against the bytes after
// offset_to_points (LAS) or the chunk table (LAZ); only then is anything sized by the
// header allocated. ASPRS LAS 1.4 R15, tables 3-4 and 7-17; LAZ: laz/laz_stream.h.
#include "laz/laz_stream.h"
#include "little_endian.h"
#include "reader_guard.h"

#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/io/las_reader.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace pcl_vts {
namespace {

// Smallest public header per minor version: 1.0-1.2, 1.3 (+ waveform start),
// 1.4 (+ EVLRs and 64-bit counts).
constexpr std::size_t HEADER_SIZE_12 = 227;
constexpr std::size_t HEADER_SIZE_13 = 235;
constexpr std::size_t HEADER_SIZE_14 = 375;
constexpr std::size_t VLR_HEADER_SIZE = 54;
// Record sizes of point formats 0-10 without extra bytes.
constexpr std::size_t MIN_RECORD_LENGTH[11] = {20, 28, 26, 34, 57, 63,
                                               30, 36, 38, 59, 67};
constexpr std::uint16_t LASZIP_RECORD_ID = 22204;

/// A fixed-width, NUL-padded header string, trimmed and made printable.
std::string fixedString(const std::uint8_t* p, std::size_t n)
{
  std::string s;
  for (std::size_t i = 0; i < n && p[i] != 0; ++i)
    s += (p[i] >= 32 && p[i] < 127) ? static_cast<char>(p[i]) : '?';
  while (!s.empty() && s.back() == ' ')
    s.pop_back();
  return s;
}

Status lazError(const std::string& name, const std::string& why)
{
  return ioError(name, "cannot decode this LAZ file: " + why);
}

/// The payload of the laszip VLR inside [header_size, offset_to_points), or nullptr.
/// The walk stops at the first record that does not fit: VLRs are not trusted further.
const std::uint8_t* findLaszipVlr(const std::uint8_t* data, std::size_t header_size,
                                  std::size_t offset_to_points, std::uint32_t vlr_count,
                                  std::size_t& length)
{
  std::size_t at = header_size;
  for (std::uint32_t v = 0; v < vlr_count; ++v) {
    if (offset_to_points - at < VLR_HEADER_SIZE)
      return nullptr;
    const std::uint8_t* vlr = data + at;
    length = u16(vlr + 20);
    if (offset_to_points - at - VLR_HEADER_SIZE < length)
      return nullptr;
    const std::string user_id = fixedString(vlr + 2, 16);
    if (user_id == "laszip encoded" && u16(vlr + 18) == LASZIP_RECORD_ID)
      return vlr + VLR_HEADER_SIZE;
    at += VLR_HEADER_SIZE + length;
  }
  return nullptr;
}

/// Chunks of a LAZ file at most this large are decoded at once (LASzip writes 50000).
constexpr std::uint64_t MAX_CHUNK_POINTS = std::uint64_t{1} << 24;

std::string classList(const std::vector<std::uint8_t>& classes)
{
  std::string s;
  for (std::uint8_t c : classes)
    s += (s.empty() ? "" : ",") + std::to_string(c);
  return s;
}

/// Grows info's bounds by the points of xyz.
void growBounds(const std::vector<double>& xyz, LasInfo& info)
{
  for (std::size_t i = 0; i < xyz.size(); i += 3)
    for (int a = 0; a < 3; ++a) {
      info.min[a] = std::min(info.min[a], xyz[i + a]);
      info.max[a] = std::max(info.max[a], xyz[i + a]);
    }
}

Status parseLasImpl(const std::uint8_t* data, std::size_t size, const std::string& name,
                    const LasReadOptions& options, std::vector<double>& xyz,
                    LasInfo& info, PointOutput& output)
{
  if (size == 0)
    return ioError(name, "the file is empty (0 bytes)");
  if (size < 4 || std::memcmp(data, "LASF", 4) != 0)
    return ioError(name, "not a LAS file: no 'LASF' signature");
  if (size < HEADER_SIZE_12)
    return ioError(name, "truncated LAS header: " + std::to_string(size) +
                             " bytes, at least 227 needed");
  info.version_major = data[24];
  info.version_minor = data[25];
  if (info.version_major != 1 || info.version_minor > 4)
    return ioError(
        name, "unsupported LAS version " + std::to_string(info.version_major) + "." +
                  std::to_string(info.version_minor) + " (1.0 to 1.4 are read)");
  info.system_identifier = fixedString(data + 26, 32);
  info.generating_software = fixedString(data + 58, 32);
  const std::size_t min_header = info.version_minor == 4   ? HEADER_SIZE_14
                                 : info.version_minor == 3 ? HEADER_SIZE_13
                                                           : HEADER_SIZE_12;
  info.header_size = u16(data + 94);
  info.offset_to_points = u32(data + 96);
  const std::uint32_t vlr_count = u32(data + 100);
  const std::uint8_t format_byte = data[104];
  info.record_length = u16(data + 105);
  if (info.header_size < min_header)
    return ioError(name, "bad LAS header: header size " +
                             std::to_string(info.header_size) + " < " +
                             std::to_string(min_header) + " for LAS 1." +
                             std::to_string(info.version_minor));
  if (size < info.header_size)
    return ioError(name, "truncated LAS header: " + std::to_string(size) +
                             " bytes, header size " + std::to_string(info.header_size));
  if (info.offset_to_points < info.header_size || info.offset_to_points > size)
    return ioError(name, "bad LAS header: offset to point data " +
                             std::to_string(info.offset_to_points) + " is outside [" +
                             std::to_string(info.header_size) + ", " +
                             std::to_string(size) + "] (header size, file size)");
  // Bit 7 (and 6) of the format byte mark LAZ; the laszip VLR says how it is coded.
  std::size_t vlr_length = 0;
  const std::uint8_t* vlr_data = findLaszipVlr(
      data, info.header_size, info.offset_to_points, vlr_count, vlr_length);
  const bool compressed = (format_byte & 0xC0) != 0 || vlr_data != nullptr;
  if (compressed && vlr_data == nullptr)
    return lazError(name, "point format byte " + std::to_string(format_byte) +
                              " has the compression bit set, but no 'laszip encoded' "
                              "VLR (record 22204) says how");
  laz::LaszipVlr laszip;
  if (std::string why;
      compressed && !laz::parseLaszipVlr(vlr_data, vlr_length, laszip, why))
    return lazError(name, why);
  info.laz = compressed ? laszip.description() : std::string();
  info.point_format = format_byte & 0x3F;
  if (info.point_format > 10)
    return ioError(name, "unsupported LAS point format " +
                             std::to_string(info.point_format) + " (0 to 10 are read)");
  const std::size_t min_record = MIN_RECORD_LENGTH[info.point_format];
  if (info.record_length < min_record)
    return ioError(name, "bad LAS header: record length " +
                             std::to_string(info.record_length) + " < " +
                             std::to_string(min_record) + " bytes of point format " +
                             std::to_string(info.point_format));
  std::uint64_t count = u32(data + 107);
  if (info.version_minor == 4) {
    const std::uint64_t count64 = u64(data + 247);
    if (count64 != 0 || count == 0)
      count = count64;
  }
  info.points_in_header = count;
  for (int a = 0; a < 3; ++a) {
    info.scale[a] = f64(data + 131 + 8 * a);
    info.offset[a] = f64(data + 155 + 8 * a);
    info.header_max[a] = f64(data + 179 + 16 * a);
    info.header_min[a] = f64(data + 187 + 16 * a);
    if (!std::isfinite(info.scale[a]) || info.scale[a] == 0.0 ||
        !std::isfinite(info.offset[a]))
      return ioError(name, std::string("bad LAS header: ") + "xyz"[a] + " scale " +
                               formatValue(info.scale[a]) + " / offset " +
                               formatValue(info.offset[a]) +
                               " (scale must be finite and non-zero)");
  }
  if (count == 0)
    return Status::error(StatusCode::EMPTY_INPUT,
                         "'" + name + "' holds 0 points (LAS header point count)");
  std::vector<laz::Chunk> chunks;
  if (compressed) {
    std::string why;
    if (!laz::checkItems(laszip, info.point_format, info.record_length, why) ||
        !laz::readChunkTable(data, size, info.offset_to_points, count, laszip, chunks,
                             why))
      return lazError(name, why);
    for (const laz::Chunk& c : chunks)
      if (c.points > MAX_CHUNK_POINTS)
        return lazError(
            name, "a chunk of " + std::to_string(c.points) + " points, more than the " +
                      std::to_string(MAX_CHUNK_POINTS) + " decoded at once");
  } else {
    const std::size_t available = size - info.offset_to_points;
    if (count > available / info.record_length)
      return ioError(name, "truncated or corrupt: header claims " +
                               std::to_string(count) + " points of " +
                               std::to_string(info.record_length) + " bytes, only " +
                               std::to_string(available) + " bytes follow offset " +
                               std::to_string(info.offset_to_points));
  }

  std::array<bool, 256> keep_class{};
  keep_class.fill(options.classes.empty());
  for (std::uint8_t c : options.classes)
    keep_class[c] = true;
  const bool extended = info.point_format >= 6;
  // LAS: count * record_length <= size, so the reservation is bounded by the file;
  // a LAZ count is only bounded by its chunk table, so reserve no more than size.
  xyz.clear();
  xyz.reserve(3 * output.reserve(static_cast<std::size_t>(
                      std::min<std::uint64_t>(count, compressed ? size : count))));
  for (int a = 0; a < 3; ++a) {
    info.min[a] = std::numeric_limits<double>::infinity();
    info.max[a] = -std::numeric_limits<double>::infinity();
  }
  output.begin(data);
  const auto handOver = [&](const std::uint8_t* consumed) { // bounds, then the sink
    growBounds(xyz, info);
    return output.handOver(xyz, consumed);
  };
  const auto take = [&](const std::uint8_t* record) {
    const std::uint8_t returns = record[14];
    const unsigned return_number = extended ? (returns & 0x0F) : (returns & 0x07);
    const unsigned number_of_returns = extended ? (returns >> 4) : ((returns >> 3) & 7);
    const std::uint8_t cls = extended ? record[16] : (record[15] & 0x1F);
    ++info.class_counts[cls];
    if (!keep_class[cls])
      return;
    if (options.returns == LasReturnFilter::FIRST && return_number > 1)
      return;
    if (options.returns == LasReturnFilter::LAST && return_number < number_of_returns)
      return;
    for (int a = 0; a < 3; ++a)
      xyz.push_back(static_cast<double>(i32(record + 4 * a)) * info.scale[a] +
                    info.offset[a]);
  };
  const std::uint8_t* record = data + info.offset_to_points;
  if (!compressed) {
    for (std::uint64_t i = 0; i < count; ++i, record += info.record_length) {
      if (output.full(xyz))
        if (Status s = handOver(record); !s.ok())
          return s;
      take(record);
    }
  } else {
    // Batches of one chunk per thread, decoded together, then taken in file order.
    const unsigned threads = std::max(1u, options.threads);
    std::vector<std::vector<std::uint8_t>> decoded(threads);
    std::vector<std::string> errors(threads);
    for (std::size_t first = 0; first < chunks.size(); first += threads) {
      const std::size_t batch = std::min<std::size_t>(threads, chunks.size() - first);
      runTeam(static_cast<unsigned>(batch), [&](unsigned w) {
        try {
          // Only what is read here: the layered scheme skips the other fields.
          if (!laz::decodeChunk(data, chunks[first + w], laszip, info.record_length,
                                decoded[w], errors[w],
                                laz::LazFields::POSITION_CLASS_RETURNS) &&
              errors[w].empty())
            errors[w] = "undecodable";
        } catch (const std::bad_alloc&) {
          errors[w] = "out of memory while decoding it";
        }
      });
      for (std::size_t w = 0; w < batch; ++w) {
        if (!errors[w].empty())
          return lazError(name, "chunk " + std::to_string(first + w) + " of " +
                                    std::to_string(chunks.size()) + ": " + errors[w]);
        const std::uint8_t* r = decoded[w].data();
        for (std::uint64_t i = 0; i < chunks[first + w].points;
             ++i, r += info.record_length) {
          if (output.full(xyz))
            if (Status s = handOver(data + chunks[first + w].offset); !s.ok())
              return s;
          take(r);
        }
      }
      record =
          data + chunks[first + batch - 1].offset + chunks[first + batch - 1].bytes;
    }
  }
  info.points_read = count;
  growBounds(xyz, info);
  std::size_t kept = 0;
  if (Status s = output.finish(xyz, record, kept); !s.ok())
    return s;
  info.points_kept = kept;
  if (info.points_kept == 0) {
    std::string present;
    for (int c = 0; c < 256; ++c)
      if (info.class_counts[c] != 0)
        present += (present.empty() ? "" : ", ") + std::to_string(c) + " (" +
                   std::to_string(info.class_counts[c]) + ")";
    std::string filter;
    if (!options.classes.empty())
      filter = "classes " + classList(options.classes);
    if (options.returns != LasReturnFilter::ALL)
      filter += std::string(filter.empty() ? "" : ", ") +
                lasReturnFilterName(options.returns) + " returns";
    return Status::error(StatusCode::EMPTY_INPUT,
                         "'" + name + "': none of its " + std::to_string(count) +
                             " points passes the filter (" + filter +
                             "); classes present: " + present);
  }
  return Status::success();
}

} // namespace

const char* lasReturnFilterName(LasReturnFilter filter)
{
  switch (filter) {
  case LasReturnFilter::ALL:
    return "all";
  case LasReturnFilter::FIRST:
    return "first";
  case LasReturnFilter::LAST:
    return "last";
  }
  return "unknown";
}

std::string LasInfo::description() const
{
  return (laz.empty() ? "LAS " : "LAZ ") + std::to_string(version_major) + "." +
         std::to_string(version_minor) + ", point format " +
         std::to_string(point_format) + ", " + std::to_string(record_length) +
         "-byte records" + (laz.empty() ? "" : " (" + laz + ")");
}

Status parseLasCloud(const std::uint8_t* data, std::size_t size,
                     const std::string& name, const LasReadOptions& options,
                     std::vector<double>& xyz, LasInfo& info)
{
  return guardedParse(name, xyz, info, [&] {
    PointOutput whole;
    return parseLasImpl(data, size, name, options, xyz, info, whole);
  });
}

Status readLasCloudChunks(const std::string& path, const LasReadOptions& options,
                          std::size_t chunk_points, const LasChunkSink& sink,
                          LasInfo& info)
{
  return readMappedFileInChunks(path, sink, chunk_points, info,
                                [&](const std::uint8_t* data, std::size_t size,
                                    std::vector<double>& chunk, PointOutput& output) {
                                  return parseLasImpl(data, size, path, options, chunk,
                                                      info, output);
                                });
}

Status readLasCloud(const std::string& path, const LasReadOptions& options,
                    std::vector<double>& xyz, LasInfo& info)
{
  return readMappedFile(path, xyz, info,
                        [&](const std::uint8_t* data, std::size_t size) {
                          return parseLasCloud(data, size, path, options, xyz, info);
                        });
}

} // namespace pcl_vts
