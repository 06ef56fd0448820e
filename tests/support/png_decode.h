// A PNG reader for the tests, on zlib (an independent inflate and CRC): checks the
// signature, every chunk CRC, 8-bit truecolour, then undoes the row filters.
#pragma once

#include <pcl_vts/picture/mesh_picture.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>
#include <zlib.h>

namespace pcl_vts {
namespace test {

/// Decodes the PNG file at path into picture; false with error set on any defect.
inline bool decodePng(const std::string& path, Picture& picture, std::string& error)
{
  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> file((std::istreambuf_iterator<char>(in)),
                                       std::istreambuf_iterator<char>());
  const std::uint8_t signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  if (file.size() < 8 || !std::equal(signature, signature + 8, file.begin())) {
    error = "no PNG signature";
    return false;
  }
  auto be32 = [&](std::size_t at) {
    return (std::uint32_t{file[at]} << 24) | (std::uint32_t{file[at + 1]} << 16) |
           (std::uint32_t{file[at + 2]} << 8) | file[at + 3];
  };
  std::vector<std::uint8_t> idat;
  bool ended = false;
  std::size_t at = 8;
  while (at + 12 <= file.size() && !ended) {
    const std::uint32_t length = be32(at);
    if (at + 12 + length > file.size()) {
      error = "chunk runs past the end of the file";
      return false;
    }
    const std::string type(file.begin() + at + 4, file.begin() + at + 8);
    const std::uint8_t* data = file.data() + at + 8;
    const uLong crc = ::crc32(0, file.data() + at + 4, length + 4);
    if (crc != be32(at + 8 + length)) {
      error = "bad CRC in chunk " + type;
      return false;
    }
    if (type == "IHDR") {
      picture.width = static_cast<int>(be32(at + 8));
      picture.height = static_cast<int>(be32(at + 12));
      if (length != 13 || data[8] != 8 || data[9] != 2 || data[12] != 0) {
        error = "not 8-bit non-interlaced truecolour";
        return false;
      }
    } else if (type == "IDAT")
      idat.insert(idat.end(), data, data + length);
    else if (type == "IEND")
      ended = true;
    at += 12 + length;
  }
  if (!ended || picture.width <= 0 || picture.height <= 0) {
    error = "no IHDR or IEND";
    return false;
  }
  const std::size_t row = 3 * static_cast<std::size_t>(picture.width);
  std::vector<std::uint8_t> raw((row + 1) * picture.height);
  uLongf raw_size = raw.size();
  if (::uncompress(raw.data(), &raw_size, idat.data(), idat.size()) != Z_OK ||
      raw_size != raw.size()) {
    error = "zlib cannot inflate IDAT to the expected size";
    return false;
  }
  picture.rgb.assign(row * picture.height, 0);
  for (int y = 0; y < picture.height; ++y) {
    const std::uint8_t filter = raw[y * (row + 1)];
    const std::uint8_t* src = raw.data() + y * (row + 1) + 1;
    std::uint8_t* out = picture.rgb.data() + y * row;
    const std::uint8_t* up = y > 0 ? out - row : nullptr;
    for (std::size_t i = 0; i < row; ++i) {
      const int a = i >= 3 ? out[i - 3] : 0, b = up ? up[i] : 0,
                c = (up && i >= 3) ? up[i - 3] : 0;
      int predictor = 0;
      if (filter == 1)
        predictor = a;
      else if (filter == 2)
        predictor = b;
      else if (filter == 3)
        predictor = (a + b) / 2;
      else if (filter == 4) {
        const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b),
                  pc = std::abs(p - c);
        predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      } else if (filter != 0) {
        error = "unknown filter " + std::to_string(filter);
        return false;
      }
      out[i] = static_cast<std::uint8_t>(src[i] + predictor);
    }
  }
  return true;
}

} // namespace test
} // namespace pcl_vts
