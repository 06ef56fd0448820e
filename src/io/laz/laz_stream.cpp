// LAZ point data: VLR, chunk table, chunk decoding. See laz_stream.h; the layout is
// LASzip's (laszip_dll / lasreadpoint in LASzip 3.4), checked field by field here.
#include "integer_decoder.h"
#include "item_state.h"
#include "laz_stream.h"

#include <algorithm>
#include <cstring>
#include <memory>

namespace pcl_vts {
namespace laz {
namespace {

constexpr std::size_t VLR_FIXED_SIZE = 34; // before the item list

const char* compressorName(std::uint16_t c)
{
  switch (c) {
  case POINTWISE:
    return "pointwise";
  case POINTWISE_CHUNKED:
    return "pointwise-chunked";
  case LAYERED_CHUNKED:
    return "layered-chunked";
  }
  return "unknown";
}

std::string itemName(const Item& item)
{
  static const char* const names[] = {
      "BYTE",    "SHORT",   "INT",       "LONG",         "FLOAT",
      "DOUBLE",  "POINT10", "GPSTIME11", "RGB12",        "WAVEPACKET13",
      "POINT14", "RGB14",   "RGBNIR14",  "WAVEPACKET14", "BYTE14"};
  const std::string name =
      item.type < 15 ? names[item.type] : "type " + std::to_string(item.type);
  return name + " v" + std::to_string(item.version) + " (" + std::to_string(item.size) +
         " bytes)";
}

/// How often (in points) a chunk's decoding looks for a stream read past its end.
constexpr std::uint64_t CHECK_EVERY = 256;

template <typename Items>
bool overranAny(const Items& items)
{
  for (const auto& item : items)
    if (item->overran())
      return true;
  return false;
}

/// The item decoders of one chunk.
struct ChunkDecoders {
  std::vector<std::unique_ptr<PointwiseItemDecoder>> pointwise;
  std::vector<std::unique_ptr<LayeredItemDecoder>> layered;
};

ChunkDecoders makeDecoders(const LaszipVlr& vlr, LazFields fields)
{
  const bool all = fields == LazFields::ALL;
  ChunkDecoders d;
  for (const Item& item : vlr.items)
    switch (item.type) {
    case ITEM_POINT10:
      d.pointwise.push_back(item.version == 1 ? makePoint10V1() : makePoint10V2());
      break;
    case ITEM_GPSTIME11:
      d.pointwise.push_back(item.version == 1 ? makeGpsTime11V1() : makeGpsTime11V2());
      break;
    case ITEM_RGB12:
      d.pointwise.push_back(item.version == 1 ? makeRgb12V1() : makeRgb12V2());
      break;
    case ITEM_BYTE:
      d.pointwise.push_back(item.version == 1 ? makeBytesV1(item.size)
                                              : makeBytesV2(item.size));
      break;
    case ITEM_POINT14:
      d.layered.push_back(makePoint14V3(!all));
      break;
    case ITEM_RGB14:
    case ITEM_RGBNIR14:
      d.layered.push_back(all ? makeRgb14V3(item.type == ITEM_RGBNIR14)
                              : makeSkippedItem(item.type == ITEM_RGBNIR14 ? 2 : 1));
      break;
    case ITEM_BYTE14:
      d.layered.push_back(all ? makeBytes14V3(item.size) : makeSkippedItem(item.size));
      break;
    case ITEM_WAVEPACKET14:
      d.layered.push_back(all ? makeWavePacket14V3() : makeSkippedItem(1));
      break;
    default: // checkItems refused the others
      break;
    }
  return d;
}

bool fail(std::string& why, const std::string& what)
{
  why = what;
  return false;
}

bool decodePointwise(const std::uint8_t* data, const std::uint8_t* end,
                     const Chunk& chunk, const LaszipVlr& vlr,
                     std::size_t record_length, LazFields fields, std::uint8_t* out,
                     std::string& why)
{
  ChunkDecoders d = makeDecoders(vlr, fields);
  std::size_t at = 0;
  for (std::size_t i = 0; i < d.pointwise.size(); ++i) {
    d.pointwise[i]->first(data + at);
    at += vlr.items[i].size;
  }
  std::memcpy(out, data, record_length);
  if (chunk.points == 1)
    return true;
  ArithmeticDecoder dec(data + record_length, end);
  for (std::uint64_t p = 1; p < chunk.points; ++p) {
    if (p % CHECK_EVERY == 0 && dec.overrun() != 0)
      break; // corrupt: said below
    std::uint8_t* record = out + p * record_length;
    for (std::size_t i = 0; i < d.pointwise.size(); ++i) {
      d.pointwise[i]->next(dec, record);
      record += vlr.items[i].size;
    }
  }
  // The encoder pads its stream so that the decoder stops on its last byte: any
  // other end means the bytes are not what was encoded. The unchunked stream runs to
  // the end of the file, so only its overrun says something.
  const bool whole_file = vlr.compressor == POINTWISE;
  if (dec.overrun() != 0 || (!whole_file && dec.unread() != 0))
    return fail(why, "its compressed stream of " +
                         std::to_string(end - data - record_length) + " bytes " +
                         (dec.overrun() != 0
                              ? "ends early"
                              : "decodes with " + std::to_string(dec.unread()) +
                                    " bytes left over") +
                         " (truncated or corrupt)");
  return true;
}

bool decodeLayered(const std::uint8_t* data, const std::uint8_t* end,
                   const Chunk& chunk, const LaszipVlr& vlr, std::size_t record_length,
                   LazFields fields, std::uint8_t* out, std::string& why)
{
  ChunkDecoders d = makeDecoders(vlr, fields);
  unsigned context = 0;
  std::size_t at = 0;
  for (std::size_t i = 0; i < d.layered.size(); ++i) {
    d.layered[i]->first(data + at, context);
    at += vlr.items[i].size;
  }
  std::memcpy(out, data, record_length);
  const std::uint8_t* p = data + record_length;
  // The point count, then every layer's byte count, then the layers in that order.
  std::size_t layer_count = 0;
  for (const auto& item : d.layered)
    layer_count += item->layers();
  if (static_cast<std::size_t>(end - p) < 4 * (1 + layer_count))
    return fail(why, "it ends inside its layer table");
  const std::uint32_t count = load<std::uint32_t>(p);
  p += 4;
  if (count != chunk.points)
    return fail(why, "it says it holds " + std::to_string(count) +
                         " points, the chunk table " + std::to_string(chunk.points));
  std::vector<std::uint32_t> sizes(layer_count);
  for (std::uint32_t& s : sizes) {
    s = load<std::uint32_t>(p);
    p += 4;
  }
  std::vector<const std::uint8_t*> starts(layer_count);
  for (std::size_t i = 0; i < layer_count; ++i) {
    if (sizes[i] > static_cast<std::size_t>(end - p))
      return fail(why, "layer " + std::to_string(i) + " claims " +
                           std::to_string(sizes[i]) + " bytes, only " +
                           std::to_string(end - p) + " are left");
    starts[i] = p;
    p += sizes[i];
  }
  std::size_t first_layer = 0;
  for (auto& item : d.layered) {
    item->startLayers(starts.data() + first_layer, sizes.data() + first_layer);
    first_layer += item->layers();
  }
  for (std::uint64_t k = 1; k < chunk.points; ++k) {
    if (k % CHECK_EVERY == 0 && overranAny(d.layered))
      break; // corrupt: said below
    std::uint8_t* record = out + k * record_length;
    for (std::size_t i = 0; i < d.layered.size(); ++i) {
      d.layered[i]->next(record, context);
      record += vlr.items[i].size;
    }
  }
  for (std::size_t i = 0; i < d.layered.size(); ++i)
    if (!d.layered[i]->consumedExactly())
      return fail(why, "the layers of its " + itemName(vlr.items[i]) +
                           " do not decode to their ends (truncated or corrupt)");
  return true;
}

} // namespace

std::string LaszipVlr::description() const
{
  std::string s = std::string(compressorName(compressor)) + " (" +
                  std::to_string(compressor) + "), LASzip " +
                  std::to_string(version_major) + "." + std::to_string(version_minor) +
                  "." + std::to_string(revision);
  if (compressor != POINTWISE)
    s += chunk_size == VARIABLE_CHUNK_SIZE
             ? ", variable chunks"
             : ", " + std::to_string(chunk_size) + " points per chunk";
  return s;
}

bool parseLaszipVlr(const std::uint8_t* data, std::size_t size, LaszipVlr& vlr,
                    std::string& why)
{
  if (size < VLR_FIXED_SIZE)
    return fail(why, "its laszip VLR has " + std::to_string(size) +
                         " bytes, at least 34 needed");
  vlr.compressor = load<std::uint16_t>(data);
  vlr.coder = load<std::uint16_t>(data + 2);
  vlr.version_major = data[4];
  vlr.version_minor = data[5];
  vlr.revision = load<std::uint16_t>(data + 6);
  vlr.options = load<std::uint32_t>(data + 8);
  vlr.chunk_size = load<std::uint32_t>(data + 12);
  const std::uint16_t item_count = load<std::uint16_t>(data + 32);
  if (size < VLR_FIXED_SIZE + 6u * item_count)
    return fail(why, "its laszip VLR lists " + std::to_string(item_count) +
                         " items but has room for " +
                         std::to_string((size - VLR_FIXED_SIZE) / 6));
  vlr.items.resize(item_count);
  for (std::size_t i = 0; i < item_count; ++i) {
    const std::uint8_t* p = data + VLR_FIXED_SIZE + 6 * i;
    vlr.items[i] = {load<std::uint16_t>(p), load<std::uint16_t>(p + 2),
                    load<std::uint16_t>(p + 4)};
  }
  if (vlr.compressor < POINTWISE || vlr.compressor > LAYERED_CHUNKED)
    return fail(why,
                "unknown LASzip compressor " + std::to_string(vlr.compressor) +
                    " (1 pointwise, 2 pointwise-chunked, 3 layered-chunked are read)");
  if (vlr.coder != 0)
    return fail(why, "unknown LASzip coder " + std::to_string(vlr.coder) +
                         " (0, arithmetic, is the only one)");
  if (vlr.compressor != POINTWISE && vlr.chunk_size == 0)
    return fail(why, "its laszip VLR gives a chunk size of 0 points");
  return true;
}

bool checkItems(const LaszipVlr& vlr, int point_format, std::size_t record_length,
                std::string& why)
{
  if (vlr.items.empty())
    return fail(why, "its laszip VLR lists no items");
  const bool layered = vlr.compressor == LAYERED_CHUNKED;
  std::size_t total = 0;
  for (std::size_t i = 0; i < vlr.items.size(); ++i) {
    const Item& item = vlr.items[i];
    total += item.size;
    const auto refuse = [&](const std::string& reason) {
      return fail(why,
                  "item " + std::to_string(i) + " " + itemName(item) + ": " + reason);
    };
    if (item.type == ITEM_WAVEPACKET13)
      return refuse("waveform packets of point formats 4 and 5 are not decoded (those "
                    "of 9 and 10 are); convert to a format without waveforms, e.g. "
                    "'las2las -set_point_type 1'");
    const bool first = i == 0;
    bool known;
    std::size_t size = item.size;
    if (layered) {
      known = (item.type == ITEM_POINT14 && first && size == 30) ||
              (item.type == ITEM_RGB14 && !first && size == 6) ||
              (item.type == ITEM_RGBNIR14 && !first && size == 8) ||
              (item.type == ITEM_BYTE14 && !first && size > 0) ||
              (item.type == ITEM_WAVEPACKET14 && !first && size == 29);
      if (known && item.version != 3)
        return refuse("version " + std::to_string(item.version) +
                      " of the layered items is not decoded (version 3 is)");
    } else {
      known = (item.type == ITEM_POINT10 && first && size == 20) ||
              (item.type == ITEM_GPSTIME11 && !first && size == 8) ||
              (item.type == ITEM_RGB12 && !first && size == 6) ||
              (item.type == ITEM_BYTE && !first && size > 0);
      if (known && item.version != 1 && item.version != 2)
        return refuse("version " + std::to_string(item.version) +
                      " of the pointwise items is not decoded (versions 1 and 2 are)");
    }
    if (!known)
      return refuse(std::string("not an item of the ") +
                    compressorName(vlr.compressor) + " scheme in that place");
  }
  if (total != record_length)
    return fail(why, "its laszip items make " + std::to_string(total) +
                         "-byte records, the header says " +
                         std::to_string(record_length));
  const bool point14 = vlr.items[0].type == ITEM_POINT14;
  if (point14 != (point_format >= 6))
    return fail(why, "point format " + std::to_string(point_format) +
                         " cannot be stored as " + itemName(vlr.items[0]));
  return true;
}

bool readChunkTable(const std::uint8_t* file, std::size_t file_size,
                    std::size_t points_begin, std::uint64_t count, const LaszipVlr& vlr,
                    std::vector<Chunk>& chunks, std::string& why)
{
  chunks.clear();
  if (vlr.compressor == POINTWISE) { // one stream to the end of the file
    if (count != 0)
      chunks.push_back({points_begin, file_size - points_begin, count});
    return true;
  }
  if (file_size - points_begin < 8)
    return fail(why, "the point data ends before the chunk table offset");
  std::int64_t table = load<std::int64_t>(file + points_begin);
  if (table == -1 && file_size >= 8) // written by a streaming writer: at the file's end
    table = load<std::int64_t>(file + file_size - 8);
  const std::size_t first_chunk = points_begin + 8;
  if (table < static_cast<std::int64_t>(first_chunk) ||
      static_cast<std::uint64_t>(table) > file_size - 8)
    return fail(why, "its chunk table offset " + std::to_string(table) +
                         " lies outside [" + std::to_string(first_chunk) + ", " +
                         std::to_string(file_size - 8) +
                         "] (file truncated, or not closed by its writer)");
  const std::uint8_t* t = file + table;
  if (load<std::uint32_t>(t) != 0)
    return fail(why, "its chunk table has version " +
                         std::to_string(load<std::uint32_t>(t)) + " (0 is read)");
  const std::uint32_t chunk_count = load<std::uint32_t>(t + 4);
  const std::uint64_t room = static_cast<std::uint64_t>(table) - first_chunk;
  const bool variable = vlr.chunk_size == LaszipVlr::VARIABLE_CHUNK_SIZE;
  const std::uint64_t expected =
      variable ? chunk_count : (count + vlr.chunk_size - 1) / vlr.chunk_size;
  if (chunk_count != expected || chunk_count > room || chunk_count > count)
    return fail(why, "its chunk table lists " + std::to_string(chunk_count) +
                         " chunks for " + std::to_string(count) + " points in " +
                         std::to_string(room) + " bytes (" +
                         (variable ? std::string("variable chunks")
                                   : std::to_string(expected) + " expected") +
                         ")");
  ArithmeticDecoder dec(t + 8, file + file_size);
  IntegerDecoder ic(32, 2);
  std::int32_t last_count = 0, last_bytes = 0;
  std::uint64_t offset = first_chunk, points_left = count;
  chunks.resize(chunk_count);
  for (Chunk& c : chunks) {
    if (variable) {
      last_count = ic.decode(dec, last_count, 0);
      c.points = static_cast<std::uint32_t>(last_count);
    } else {
      c.points = std::min<std::uint64_t>(vlr.chunk_size, points_left);
    }
    last_bytes = ic.decode(dec, last_bytes, 1);
    c.bytes = static_cast<std::uint32_t>(last_bytes);
    c.offset = offset;
    if (c.points == 0 || c.points > points_left ||
        c.bytes > room - (offset - first_chunk))
      return fail(why, "its chunk table is corrupt: chunk " +
                           std::to_string(&c - chunks.data()) + " of " +
                           std::to_string(c.points) + " points, " +
                           std::to_string(c.bytes) + " bytes at offset " +
                           std::to_string(offset) + ", with " +
                           std::to_string(points_left) + " points left before byte " +
                           std::to_string(table));
    points_left -= c.points;
    offset += c.bytes;
  }
  if (points_left != 0)
    return fail(why, "its chunks hold " + std::to_string(count - points_left) +
                         " points, the header says " + std::to_string(count));
  return true;
}

bool decodeChunk(const std::uint8_t* file, const Chunk& chunk, const LaszipVlr& vlr,
                 std::size_t record_length, std::vector<std::uint8_t>& records,
                 std::string& why, LazFields fields)
{
  records.resize(chunk.points * record_length);
  if (chunk.points == 0)
    return true;
  // A chunk of n points takes at least its raw first record; the header's count was
  // checked against the file, so n * record_length is bounded by the caller.
  if (chunk.bytes < record_length)
    return fail(why, "it has " + std::to_string(chunk.bytes) +
                         " bytes, less than its first record");
  const std::uint8_t* data = file + chunk.offset;
  const std::uint8_t* end = data + chunk.bytes;
  return vlr.compressor == LAYERED_CHUNKED
             ? decodeLayered(data, end, chunk, vlr, record_length, fields,
                             records.data(), why)
             : decodePointwise(data, end, chunk, vlr, record_length, fields,
                               records.data(), why);
}

} // namespace laz
} // namespace pcl_vts
