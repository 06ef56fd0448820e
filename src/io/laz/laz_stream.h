// The compressed point data of a LAZ file: the laszip VLR (which items, which
// compressor), the chunk table, and the decoding of one chunk into plain LAS point
// records. Chunks are independent, so callers decode them on as many threads as they
// like. Every size and count the file states is checked before it is trusted.
#pragma once

#include "item_decoder.h"

#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {
namespace laz {

/// Item types of the laszip VLR.
enum ItemType : std::uint16_t {
  ITEM_BYTE = 0,
  ITEM_POINT10 = 6,
  ITEM_GPSTIME11 = 7,
  ITEM_RGB12 = 8,
  ITEM_WAVEPACKET13 = 9,
  ITEM_POINT14 = 10,
  ITEM_RGB14 = 11,
  ITEM_RGBNIR14 = 12,
  ITEM_WAVEPACKET14 = 13,
  ITEM_BYTE14 = 14
};

enum Compressor : std::uint16_t {
  POINTWISE = 1,
  POINTWISE_CHUNKED = 2,
  LAYERED_CHUNKED = 3
};

struct Item {
  std::uint16_t type = 0, size = 0, version = 0;
};

/// The "laszip encoded" VLR (record 22204).
struct LaszipVlr {
  std::uint16_t compressor = 0, coder = 0;
  int version_major = 0, version_minor = 0, revision = 0;
  std::uint32_t options = 0;
  std::uint32_t chunk_size = 0; ///< points per chunk; 0xFFFFFFFF: variable
  std::vector<Item> items;

  static constexpr std::uint32_t VARIABLE_CHUNK_SIZE = 0xFFFFFFFFu;

  /// "pointwise-chunked (2), LASzip 2.2.0, 50000 points per chunk".
  std::string description() const;
};

/// Parses the VLR payload; on failure why says what is wrong.
bool parseLaszipVlr(const std::uint8_t* data, std::size_t size, LaszipVlr& vlr,
                    std::string& why);

/// Checks that the items describe records of record_length bytes of this point format
/// and that this reader decodes them; why says which item it does not.
bool checkItems(const LaszipVlr& vlr, int point_format, std::size_t record_length,
                std::string& why);

struct Chunk {
  std::uint64_t offset = 0; ///< first byte in the file
  std::uint64_t bytes = 0;
  std::uint64_t points = 0;
};

/// Finds the chunks of the point data [points_begin, points_end) holding `count`
/// points: reads the chunk table (or, for the unchunked compressor, makes one chunk).
bool readChunkTable(const std::uint8_t* file, std::size_t file_size,
                    std::size_t points_begin, std::uint64_t count, const LaszipVlr& vlr,
                    std::vector<Chunk>& chunks, std::string& why);

/// Which fields of the records a decoding must give.
enum class LazFields {
  ALL,                   ///< every byte of every record
  POSITION_CLASS_RETURNS ///< x, y, z, return numbers, class: the layered scheme then
                         ///< leaves the other layers undecoded (the pointwise one
                         ///< cannot: its fields share one stream)
};

/// Decodes one chunk into chunk.points records of record_length bytes; with
/// POSITION_CLASS_RETURNS the other bytes are unspecified.
bool decodeChunk(const std::uint8_t* file, const Chunk& chunk, const LaszipVlr& vlr,
                 std::size_t record_length, std::vector<std::uint8_t>& records,
                 std::string& why, LazFields fields = LazFields::ALL);

} // namespace laz
} // namespace pcl_vts
