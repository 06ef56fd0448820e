// The zlib stream inside a PNG's IDAT chunks, written here so that the library needs
// no zlib: one fixed-Huffman deflate block with LZ77 matches from hash chains over the
// 32 KiB window (RFC 1950/1951). Rendered pictures are flat colour areas with long
// repeats, so fixed codes come within ~20% of zlib's level 6 at a fraction of the code.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace png_detail {

/// Adler-32 of data, as the zlib trailer needs it.
std::uint32_t adler32(const std::uint8_t* data, std::size_t size);

/// A complete zlib stream (header, deflate data, Adler-32) holding data.
std::vector<std::uint8_t> zlibCompress(const std::uint8_t* data, std::size_t size);

} // namespace png_detail
} // namespace pcl_vts
