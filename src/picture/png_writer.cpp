// writePng: truecolour PNG (IHDR, IDAT, IEND) with per-row adaptive filters, deflated
// and checksummed by zlib (compress2, crc32_z: on every machine that has PCL, through
// VTK), written through AtomicFile (core/atomic_file.h) as meshes are.
#include <pcl_vts/core/atomic_file.h>
#include <pcl_vts/picture/image.h>

#include <array>
#include <cstdlib>
#include <string>
#include <zlib.h>

namespace pcl_vts {

namespace {

void putBigEndian(std::vector<std::uint8_t>& out, std::uint32_t value)
{
  for (int k = 3; k >= 0; --k)
    out.push_back(static_cast<std::uint8_t>(value >> (8 * k)));
}

void putChunk(std::vector<std::uint8_t>& out, const char* type,
              const std::vector<std::uint8_t>& data)
{
  putBigEndian(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  putBigEndian(out, static_cast<std::uint32_t>(
                        crc32_z(0, out.data() + start, out.size() - start)));
}

std::uint8_t paeth(int a, int b, int c)
{
  const int p = a + b - c;
  const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return static_cast<std::uint8_t>(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

/// Scanlines, each prefixed by the filter (None, Sub, Up, Average, Paeth) whose
/// output has the smallest sum of |signed bytes|: libpng's heuristic, which turns
/// smooth shading into runs of small values that deflate well.
std::vector<std::uint8_t> filteredScanlines(const Picture& picture)
{
  const std::size_t row_bytes = 3 * static_cast<std::size_t>(picture.width);
  std::vector<std::uint8_t> out;
  out.reserve((row_bytes + 1) * static_cast<std::size_t>(picture.height));
  const std::vector<std::uint8_t> zero_row(row_bytes, 0);
  std::array<std::vector<std::uint8_t>, 5> candidate;
  for (auto& c : candidate)
    c.resize(row_bytes);
  for (int y = 0; y < picture.height; ++y) {
    const std::uint8_t* row = picture.rgb.data() + y * row_bytes;
    const std::uint8_t* up = y > 0 ? row - row_bytes : zero_row.data();
    std::size_t best = 0;
    long best_cost = -1;
    for (std::size_t f = 0; f < 5; ++f) {
      long cost = 0;
      for (std::size_t i = 0; i < row_bytes; ++i) {
        const int a = i >= 3 ? row[i - 3] : 0, b = up[i], c = i >= 3 ? up[i - 3] : 0;
        const int predictor = f == 0   ? 0
                              : f == 1 ? a
                              : f == 2 ? b
                              : f == 3 ? (a + b) / 2
                                       : paeth(a, b, c);
        const auto v = static_cast<std::uint8_t>(row[i] - predictor);
        candidate[f][i] = v;
        cost += v < 128 ? v : 256 - v;
      }
      if (best_cost < 0 || cost < best_cost) {
        best_cost = cost;
        best = f;
      }
    }
    out.push_back(static_cast<std::uint8_t>(best));
    out.insert(out.end(), candidate[best].begin(), candidate[best].end());
  }
  return out;
}

} // namespace

Status writePng(const std::string& path, const Picture& picture)
{
  if (picture.width < 1 || picture.height < 1 ||
      picture.rgb.size() != 3 * static_cast<std::size_t>(picture.width) *
                                static_cast<std::size_t>(picture.height))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "cannot write '" + path + "': picture of " +
                             std::to_string(picture.width) + " x " +
                             std::to_string(picture.height) + " pixels with " +
                             std::to_string(picture.rgb.size()) + " rgb bytes");
  std::vector<std::uint8_t> png = {137, 80, 78, 71, 13, 10, 26, 10};
  std::vector<std::uint8_t> header;
  putBigEndian(header, static_cast<std::uint32_t>(picture.width));
  putBigEndian(header, static_cast<std::uint32_t>(picture.height));
  header.insert(header.end(),
                {8, 2, 0, 0, 0}); // 8-bit RGB, deflate, filters, no interlace
  putChunk(png, "IHDR", header);
  const std::vector<std::uint8_t> raw = filteredScanlines(picture);
  std::vector<std::uint8_t> deflated(compressBound(raw.size()));
  uLongf deflated_size = deflated.size();
  // Level 6: zlib's default trade of size for time.
  if (const int z =
          compress2(deflated.data(), &deflated_size, raw.data(), raw.size(), 6);
      z != Z_OK)
    return Status::error(z == Z_MEM_ERROR ? StatusCode::IO_ERROR
                                          : StatusCode::INTERNAL_ERROR,
                         "cannot write '" + path + "': zlib compress2 failed (" +
                             std::to_string(z) + ")");
  deflated.resize(deflated_size);
  putChunk(png, "IDAT", deflated);
  putChunk(png, "IEND", {});
  return writeFileAtomically(path, png.data(), png.size());
}

} // namespace pcl_vts
