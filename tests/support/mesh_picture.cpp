// Mesh pictures and a minimal PNG writer. See mesh_picture.h.
#include "support/mesh_picture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>

namespace pcl_vts {
namespace test {

namespace {

std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc = 0)
{
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k)
        c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t i = 0; i < size; ++i)
    crc = table[(crc ^ data[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

class BitWriter {
 public:
  std::vector<std::uint8_t> bytes;
  void put(std::uint32_t value, int count) // LSB first
  {
    for (int i = 0; i < count; ++i) {
      if (bit_ == 0)
        bytes.push_back(0);
      if ((value >> i) & 1)
        bytes.back() |= static_cast<std::uint8_t>(1 << bit_);
      bit_ = (bit_ + 1) % 8;
    }
  }
  void putHuffman(std::uint32_t code, int length) // MSB first
  {
    for (int i = length - 1; i >= 0; --i)
      put((code >> i) & 1, 1);
  }

 private:
  int bit_ = 0;
};

void putLiteral(BitWriter& w, int symbol) // fixed Huffman literal/length code
{
  if (symbol < 144)
    w.putHuffman(static_cast<std::uint32_t>(0x30 + symbol), 8);
  else if (symbol < 256)
    w.putHuffman(static_cast<std::uint32_t>(0x190 + symbol - 144), 9);
  else if (symbol < 280)
    w.putHuffman(static_cast<std::uint32_t>(symbol - 256), 7);
  else
    w.putHuffman(static_cast<std::uint32_t>(0xC0 + symbol - 280), 8);
}

void putLength(BitWriter& w, int length) // 3..258
{
  static const int base[] = {3,  4,  5,  6,   7,   8,   9,   10,  11, 13,
                             15, 17, 19, 23,  27,  31,  35,  43,  51, 59,
                             67, 83, 99, 115, 131, 163, 195, 227, 258};
  static const int extra[] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                              2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
  int code = 28;
  while (base[code] > length)
    --code;
  putLiteral(w, 257 + code);
  w.put(static_cast<std::uint32_t>(length - base[code]), extra[code]);
}

/// zlib stream of data: one fixed-Huffman block, matches only at distance 1 (runs).
std::vector<std::uint8_t> deflateRuns(const std::vector<std::uint8_t>& data)
{
  BitWriter w;
  w.put(0x78, 8);
  w.put(0x01, 8);
  w.put(1, 1); // final block
  w.put(1, 2); // fixed Huffman
  std::size_t i = 0;
  while (i < data.size()) {
    std::size_t run = 0;
    if (i > 0)
      while (i + run < data.size() && run < 258 && data[i + run] == data[i - 1])
        ++run;
    if (run >= 3) {
      putLength(w, static_cast<int>(run));
      w.putHuffman(0, 5); // distance code 0 = distance 1
      i += run;
    } else {
      putLiteral(w, data[i]);
      ++i;
    }
  }
  putLiteral(w, 256);
  std::uint32_t a = 1, b = 0;
  for (const std::uint8_t byte : data) {
    a = (a + byte) % 65521;
    b = (b + a) % 65521;
  }
  std::vector<std::uint8_t> out = w.bytes;
  const std::uint32_t adler = (b << 16) | a;
  for (int k = 3; k >= 0; --k)
    out.push_back(static_cast<std::uint8_t>(adler >> (8 * k)));
  return out;
}

void putChunk(std::ofstream& out, const char* type,
              const std::vector<std::uint8_t>& data)
{
  std::vector<std::uint8_t> chunk(type, type + 4);
  chunk.insert(chunk.end(), data.begin(), data.end());
  const auto size = static_cast<std::uint32_t>(data.size());
  const std::uint8_t len[4] = {
      static_cast<std::uint8_t>(size >> 24), static_cast<std::uint8_t>(size >> 16),
      static_cast<std::uint8_t>(size >> 8), static_cast<std::uint8_t>(size)};
  out.write(reinterpret_cast<const char*>(len), 4);
  out.write(reinterpret_cast<const char*>(chunk.data()),
            static_cast<std::streamsize>(chunk.size()));
  const std::uint32_t crc = crc32(chunk.data(), chunk.size());
  const std::uint8_t c[4] = {
      static_cast<std::uint8_t>(crc >> 24), static_cast<std::uint8_t>(crc >> 16),
      static_cast<std::uint8_t>(crc >> 8), static_cast<std::uint8_t>(crc)};
  out.write(reinterpret_cast<const char*>(c), 4);
}

} // namespace

bool writePalettePng(const std::string& path, int width, int height,
                     const std::vector<std::uint8_t>& pixels,
                     const std::vector<std::uint8_t>& rgb)
{
  std::ofstream out(path, std::ios::binary);
  if (!out)
    return false;
  const std::uint8_t signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  out.write(reinterpret_cast<const char*>(signature), 8);
  auto be32 = [](std::vector<std::uint8_t>& v, std::uint32_t x) {
    for (int k = 3; k >= 0; --k)
      v.push_back(static_cast<std::uint8_t>(x >> (8 * k)));
  };
  std::vector<std::uint8_t> header;
  be32(header, static_cast<std::uint32_t>(width));
  be32(header, static_cast<std::uint32_t>(height));
  header.insert(header.end(), {8, 3, 0, 0, 0}); // 8 bit, palette
  putChunk(out, "IHDR", header);
  putChunk(out, "PLTE", rgb);
  std::vector<std::uint8_t> raw;
  raw.reserve(static_cast<std::size_t>(height) * (static_cast<std::size_t>(width) + 1));
  for (int y = 0; y < height; ++y) {
    raw.push_back(0); // filter: none
    const auto row = pixels.begin() + static_cast<std::ptrdiff_t>(y) * width;
    raw.insert(raw.end(), row, row + width);
  }
  putChunk(out, "IDAT", deflateRuns(raw));
  putChunk(out, "IEND", {});
  return static_cast<bool>(out);
}

bool writeMeshPicture(const std::string& path, const TriangleMesh& mesh,
                      const std::vector<TriangleClass>& classes,
                      const std::vector<std::uint8_t>& marks, int width)
{
  constexpr int SHADES = 32;
  // Palette: 0 background, 1 mark, then 3 classes x SHADES.
  std::vector<std::uint8_t> rgb = {255, 255, 255, 20, 20, 20};
  const double base[3][3] = {{200, 200, 200}, {230, 60, 50}, {70, 120, 235}};
  for (const auto& colour : base)
    for (int s = 0; s < SHADES; ++s) {
      const double f = 0.35 + 0.65 * s / (SHADES - 1.0);
      for (const double c : colour)
        rgb.push_back(static_cast<std::uint8_t>(std::min(255.0, c * f)));
    }
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300, z0 = 1e300, z1 = -1e300;
  for (const VertexId v : mesh.triangles) {
    x0 = std::min(x0, mesh.xy[v].x);
    x1 = std::max(x1, mesh.xy[v].x);
    y0 = std::min(y0, mesh.xy[v].y);
    y1 = std::max(y1, mesh.xy[v].y);
    z0 = std::min(z0, mesh.z[v]);
    z1 = std::max(z1, mesh.z[v]);
  }
  if (!(x1 > x0 && y1 > y0))
    return false;
  const double scale = (width - 1) / (x1 - x0);
  const int height = static_cast<int>((y1 - y0) * scale) + 1;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * height, 0);
  // Vertical exaggeration so that low-relief terrain still shows its shape.
  const double exaggeration = std::max(1.0, 0.1 * (x1 - x0) / std::max(z1 - z0, 1e-9));
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const VertexId ia = mesh.triangles[3 * t], ib = mesh.triangles[3 * t + 1],
                   ic = mesh.triangles[3 * t + 2];
    const double ax = (mesh.xy[ia].x - x0) * scale, ay = (y1 - mesh.xy[ia].y) * scale;
    const double bx = (mesh.xy[ib].x - x0) * scale, by = (y1 - mesh.xy[ib].y) * scale;
    const double cx = (mesh.xy[ic].x - x0) * scale, cy = (y1 - mesh.xy[ic].y) * scale;
    // Lambert shading with light from the north-west.
    const double ux = mesh.xy[ib].x - mesh.xy[ia].x, uy = mesh.xy[ib].y - mesh.xy[ia].y,
                 uz = (mesh.z[ib] - mesh.z[ia]) * exaggeration;
    const double vx = mesh.xy[ic].x - mesh.xy[ia].x, vy = mesh.xy[ic].y - mesh.xy[ia].y,
                 vz = (mesh.z[ic] - mesh.z[ia]) * exaggeration;
    double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
    nx /= len;
    ny /= len;
    nz /= len;
    const double light = std::clamp(-0.5 * nx + 0.5 * ny + 0.707 * nz, 0.0, 1.0);
    const auto shade = static_cast<int>(light * (SHADES - 1) + 0.5);
    const auto index =
        static_cast<std::uint8_t>(2 + static_cast<int>(classes[t]) * SHADES + shade);
    const int px0 = std::max(0, static_cast<int>(std::floor(std::min({ax, bx, cx}))));
    const int px1 =
        std::min(width - 1, static_cast<int>(std::ceil(std::max({ax, bx, cx}))));
    const int py0 = std::max(0, static_cast<int>(std::floor(std::min({ay, by, cy}))));
    const int py1 =
        std::min(height - 1, static_cast<int>(std::ceil(std::max({ay, by, cy}))));
    for (int py = py0; py <= py1; ++py)
      for (int px = px0; px <= px1; ++px) {
        const double x = px + 0.5, y = py + 0.5;
        // Image y points down: the triangle is clockwise here.
        const double e0 = (bx - ax) * (y - ay) - (by - ay) * (x - ax);
        const double e1 = (cx - bx) * (y - by) - (cy - by) * (x - bx);
        const double e2 = (ax - cx) * (y - cy) - (ay - cy) * (x - cx);
        if (e0 <= 0 && e1 <= 0 && e2 <= 0)
          pixels[static_cast<std::size_t>(py) * width + px] = index;
      }
  }
  for (std::size_t v = 0; v < marks.size() && v < mesh.vertexCount(); ++v) {
    if (!marks[v])
      continue;
    const int px = static_cast<int>((mesh.xy[v].x - x0) * scale);
    const int py = static_cast<int>((y1 - mesh.xy[v].y) * scale);
    if (px >= 0 && px < width && py >= 0 && py < height)
      pixels[static_cast<std::size_t>(py) * width + px] = 1;
  }
  return writePalettePng(path, width, height, pixels, rgb);
}

} // namespace test
} // namespace pcl_vts
