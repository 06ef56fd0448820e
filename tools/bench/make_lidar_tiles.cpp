// make_lidar_tiles: synthetic airborne LiDAR as a folder of LAS 1.2 tiles (point
// format 1), for the scale benchmark (make bench-scale). Terrain of a few sines,
// lakes with no returns, density that varies by a factor of four across the area,
// vegetation returns (class 1) above ground (class 2). Streams: one tile's points
// at a time, never the whole set. Same arguments, same bytes.
//
//   make_lidar_tiles OUT_DIR TOTAL_POINTS [TILES_PER_SIDE] [SEED] [POINT_FORMAT]
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr double TILE_METRES = 1000.0;
constexpr double ORIGIN_X = 500000.0, ORIGIN_Y = 4100000.0; // UTM-like
constexpr double SCALE = 0.01;
/// Record length of point formats 0 and 1.
constexpr std::uint16_t RECORD_BYTES[2] = {20, 28};
constexpr std::uint32_t HEADER_BYTES = 227;

double ground(double x, double y)
{
  return 200.0 + 30.0 * std::sin(x / 700.0) * std::cos(y / 900.0) +
         8.0 * std::sin(x / 97.0 + y / 131.0) +
         1.5 * std::sin(x / 13.0) * std::sin(y / 17.0);
}

/// Relative density in (0.25, 1]: denser where flight lines overlap.
double density(double x, double y)
{
  return 0.625 + 0.375 * std::sin(x / 1500.0) * std::sin(y / 1100.0 + 0.7);
}

/// Lakes: discs of no returns, one per 2 km cell at a fixed pseudo-random place.
bool inLake(double x, double y)
{
  const double cell = 2000.0;
  const double cx = std::floor(x / cell), cy = std::floor(y / cell);
  const std::uint64_t h = static_cast<std::uint64_t>(cx * 7919 + cy * 104729 + 17);
  const double lx = (cx + 0.2 + 0.6 * static_cast<double>(h % 97) / 97.0) * cell;
  const double ly = (cy + 0.2 + 0.6 * static_cast<double>(h % 89) / 89.0) * cell;
  const double r = 60.0 + static_cast<double>(h % 113);
  return (x - lx) * (x - lx) + (y - ly) * (y - ly) < r * r;
}

template <typename T>
void put(std::vector<unsigned char>& out, std::size_t at, T v)
{
  std::memcpy(&out[at], &v, sizeof(T));
}

bool writeTile(const std::string& path, std::uint64_t points, double x0, double y0,
               int format, std::mt19937_64& rng)
{
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr)
    return false;
  std::vector<unsigned char> header(HEADER_BYTES, 0);
  std::fwrite(header.data(), 1, header.size(), f); // rewritten at the end
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL},
         hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  std::uint32_t by_return[5] = {0, 0, 0, 0, 0};
  std::vector<unsigned char> record(RECORD_BYTES[format]);
  for (std::uint64_t written = 0; written < points;) {
    const double x = x0 + TILE_METRES * u(rng), y = y0 + TILE_METRES * u(rng);
    if (inLake(x, y) || u(rng) > density(x, y))
      continue;
    const bool vegetation =
        std::sin(x / 55.0) * std::cos(y / 45.0) > 0.6 && u(rng) < 0.5;
    const double z = ground(x, y) + (vegetation ? 2.0 + 15.0 * u(rng) : 0.05 * u(rng));
    const std::int32_t ix =
        static_cast<std::int32_t>(std::lround((x - ORIGIN_X) / SCALE));
    const std::int32_t iy =
        static_cast<std::int32_t>(std::lround((y - ORIGIN_Y) / SCALE));
    const std::int32_t iz = static_cast<std::int32_t>(std::lround(z / SCALE));
    const double q[3] = {ORIGIN_X + ix * SCALE, ORIGIN_Y + iy * SCALE, iz * SCALE};
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], q[k]);
      hi[k] = std::max(hi[k], q[k]);
    }
    const int return_number = vegetation ? 1 : 1 + static_cast<int>(u(rng) < 0.2);
    ++by_return[return_number - 1];
    std::fill(record.begin(), record.end(), 0);
    put(record, 0, ix);
    put(record, 4, iy);
    put(record, 8, iz);
    put(record, 12, static_cast<std::uint16_t>(100 + 50 * u(rng)));
    record[14] = static_cast<unsigned char>(return_number | (2 << 3)); // of 2 returns
    record[15] = vegetation ? 1 : 2;
    if (format == 1)
      put(record, 20, static_cast<double>(written));
    if (std::fwrite(record.data(), 1, record.size(), f) != record.size()) {
      std::fclose(f);
      return false;
    }
    ++written;
  }
  std::memcpy(&header[0], "LASF", 4);
  header[24] = 1; // version 1.2
  header[25] = 2;
  std::memcpy(&header[26], "make_lidar_tiles", 16);
  std::memcpy(&header[58], "pcl_vts bench", 13);
  put(header, 94, static_cast<std::uint16_t>(HEADER_BYTES));
  put(header, 96, HEADER_BYTES); // offset to point data
  put(header, 100, std::uint32_t{0});
  header[104] = static_cast<unsigned char>(format);
  put(header, 105, RECORD_BYTES[format]);
  put(header, 107, static_cast<std::uint32_t>(points));
  for (int k = 0; k < 5; ++k)
    put(header, 111 + 4 * static_cast<std::size_t>(k), by_return[k]);
  for (int k = 0; k < 3; ++k)
    put(header, 131 + 8 * static_cast<std::size_t>(k), SCALE);
  put(header, 155, ORIGIN_X);
  put(header, 163, ORIGIN_Y);
  put(header, 171, 0.0);
  const std::size_t bounds[6] = {179, 187, 195, 203, 211, 219}; // max x, min x, ...
  for (int k = 0; k < 3; ++k) {
    put(header, bounds[2 * k], hi[k]);
    put(header, bounds[2 * k + 1], lo[k]);
  }
  const bool ok = std::fseek(f, 0, SEEK_SET) == 0 &&
                  std::fwrite(header.data(), 1, header.size(), f) == header.size();
  return std::fclose(f) == 0 && ok;
}

} // namespace

int main(int argc, char** argv)
{
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: make_lidar_tiles OUT_DIR TOTAL_POINTS [TILES_PER_SIDE] [SEED] "
                 "[POINT_FORMAT 0|1]\n");
    return 1;
  }
  const std::string out = argv[1];
  const std::uint64_t total = std::strtoull(argv[2], nullptr, 10);
  // TILES_PER_SIDE 0 or absent: about 4e6 points a tile.
  const int side_arg = argc > 3 ? std::atoi(argv[3]) : 0;
  const int side = side_arg != 0 ? side_arg
                                 : std::max(1, static_cast<int>(std::lround(std::sqrt(
                                                   static_cast<double>(total) / 4e6))));
  const std::uint64_t seed = argc > 4 ? std::strtoull(argv[4], nullptr, 10) : 1;
  const int format = argc > 5 ? std::atoi(argv[5]) : 1;
  if (total == 0 || side <= 0 || (format != 0 && format != 1)) {
    std::fprintf(
        stderr, "make_lidar_tiles: bad TOTAL_POINTS, TILES_PER_SIDE or POINT_FORMAT\n");
    return 1;
  }
  const std::uint64_t tiles =
      static_cast<std::uint64_t>(side) * static_cast<std::uint64_t>(side);
  for (int ty = 0; ty < side; ++ty)
    for (int tx = 0; tx < side; ++tx) {
      const std::uint64_t k =
          static_cast<std::uint64_t>(ty) * static_cast<std::uint64_t>(side) +
          static_cast<std::uint64_t>(tx);
      const std::uint64_t points = total * (k + 1) / tiles - total * k / tiles;
      std::mt19937_64 rng(seed * 1000003 + k);
      char name[64];
      std::snprintf(name, sizeof(name), "/tile_%03d_%03d.las", tx, ty);
      if (!writeTile(out + name, points, ORIGIN_X + tx * TILE_METRES,
                     ORIGIN_Y + ty * TILE_METRES, format, rng)) {
        std::fprintf(stderr, "make_lidar_tiles: cannot write %s%s\n", out.c_str(),
                     name);
        return 2;
      }
    }
  std::printf("%llu points in %llu tiles of %.0f m in %s\n",
              static_cast<unsigned long long>(total),
              static_cast<unsigned long long>(tiles), TILE_METRES, out.c_str());
  return 0;
}
