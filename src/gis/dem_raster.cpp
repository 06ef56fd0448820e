// Scanline rasterization of a TIN: triangles sorted by their north edge enter the
// active list when the sweep reaches them and leave it when it has passed them, so a
// block of rows touches only the triangles that cross it and memory is one block.
#include "mapped_vertices.h"

#include <pcl_vts/core/predicates.h>
#include <pcl_vts/gis/dem_raster.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <string>

namespace pcl_vts {

namespace {

constexpr double MAX_SIDE = 2147483647.0; // pixels on a side

struct TriangleBox {
  double ymin, ymax;
};

/// Pixel index range [lo, hi] whose centres may fall in [vmin, vmax] along an axis
/// where centre(i) = origin + sign*(i + 0.5)*R; one pixel of slack on each side
/// (the exact test decides), clamped to [0, n).
bool pixelRange(double vmin, double vmax, double origin, double sign, double r,
                std::size_t n, std::size_t& lo, std::size_t& hi)
{
  double a = (vmin - origin) / r * sign - 0.5;
  double b = (vmax - origin) / r * sign - 0.5;
  if (a > b)
    std::swap(a, b);
  const double first = std::floor(a);
  const double last = std::ceil(b);
  if (last < 0.0 || first >= static_cast<double>(n))
    return false;
  lo = first < 0.0 ? 0 : static_cast<std::size_t>(first);
  hi = std::min(static_cast<double>(n - 1), last) < 0.0
           ? 0
           : static_cast<std::size_t>(std::min(static_cast<double>(n - 1), last));
  return lo <= hi;
}

/// No triangle holds this pixel centre yet.
constexpr std::uint64_t NO_OWNER = ~std::uint64_t{0};

/// Gives every pixel centre of rows [row0, row1] inside triangle t (corners p, heights
/// z) the linear interpolation there, unless a triangle of smaller id holds it (a
/// centre on a shared edge). Exact point location (orient2d); zero-area triangles
/// cover nothing. Shared by the in-memory and the out-of-core rasterizers, so both
/// give the same pixels.
void paintTriangle(std::array<Point2, 3> p, std::array<double, 3> z, std::uint64_t t,
                   const DemGrid& grid, std::size_t row0, std::size_t row1,
                   std::size_t col0, std::size_t col1, float* values,
                   std::uint64_t* owner)
{
  const Sign turn = orient2d(p[0], p[1], p[2]);
  if (turn == Sign::ZERO)
    return;
  if (turn == Sign::NEGATIVE) {
    std::swap(p[1], p[2]);
    std::swap(z[1], z[2]);
  }
  const Point2 &a = p[0], &b = p[1], &c = p[2];
  const double r = grid.resolution;
  std::size_t rlo = 0, rhi = 0, clo = 0, chi = 0;
  if (!pixelRange(std::min({a.y, b.y, c.y}), std::max({a.y, b.y, c.y}), grid.y1, -1.0,
                  r, grid.rows, rlo, rhi))
    return;
  rlo = std::max(rlo, row0);
  rhi = std::min(rhi, row1);
  const double xmin = std::min({a.x, b.x, c.x}), xmax = std::max({a.x, b.x, c.x});
  if (rlo > rhi || !pixelRange(xmin, xmax, grid.x0, 1.0, r, grid.cols, clo, chi))
    return;
  clo = std::max(clo, col0);
  chi = std::min(chi, col1);
  if (clo > chi)
    return;
  const std::size_t stride = col1 - col0 + 1;
  const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
  const double det = bx * cy - cx * by;
  const double dzb = z[1] - z[0], dzc = z[2] - z[0];
  for (std::size_t row = rlo; row <= rhi; ++row) {
    const double py = grid.centreY(row);
    for (std::size_t col = clo; col <= chi; ++col) {
      const std::size_t i = (row - row0) * stride + (col - col0);
      if (owner[i] < t)
        continue; // an earlier triangle holds this centre (a shared edge)
      const Point2 q{grid.centreX(col), py};
      if (orient2d(a, b, q) == Sign::NEGATIVE || orient2d(b, c, q) == Sign::NEGATIVE ||
          orient2d(c, a, q) == Sign::NEGATIVE)
        continue;
      const double px = q.x - a.x, qy = q.y - a.y;
      const double lb = (px * cy - cx * qy) / det;
      const double lc = (bx * qy - px * by) / det;
      values[i] = static_cast<float>(z[0] + lb * dzb + lc * dzc);
      owner[i] = t;
    }
  }
}

} // namespace

Status demGridForMesh(const TriangleMesh& mesh, double resolution, DemGrid& grid)
{
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    return demGridForExtent(0, 0, 0, 0, resolution, grid); // says what is wrong
  if (mesh.xy.empty() || mesh.triangles.empty())
    return Status::error(StatusCode::EMPTY_INPUT, "no triangle to rasterize");
  double xmin = mesh.xy[0].x, xmax = xmin, ymin = mesh.xy[0].y, ymax = ymin;
  for (const Point2& p : mesh.xy) {
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  }
  return demGridForExtent(xmin, ymin, xmax, ymax, resolution, grid);
}

Status demGridForExtent(double xmin, double ymin, double xmax, double ymax,
                        double resolution, DemGrid& grid)
{
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "DEM resolution must be a positive number, not " +
                             formatValue(resolution));
  const double x0 = std::floor(xmin / resolution) * resolution;
  const double y0 = std::floor(ymin / resolution) * resolution;
  double x1 = std::ceil(xmax / resolution) * resolution;
  double y1 = std::ceil(ymax / resolution) * resolution;
  // A mesh edge lying exactly on a multiple of R still gets its centres.
  if (x1 == x0)
    x1 += resolution;
  if (y1 == y0)
    y1 += resolution;
  return demGridForBounds(x0, y0, x1, y1, resolution, grid);
}

Status demGridForBounds(double x0, double y0, double x1, double y1, double resolution,
                        DemGrid& grid)
{
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "DEM resolution must be a positive number, not " +
                             formatValue(resolution));
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) ||
      !std::isfinite(y1) || !(x1 > x0) || !(y1 > y0))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "DEM bounds must be finite with X0 < X1 and Y0 < Y1, not " +
                             formatValue(x0) + "," + formatValue(y0) + "," +
                             formatValue(x1) + "," + formatValue(y1));
  const double wc = (x1 - x0) / resolution, hc = (y1 - y0) / resolution;
  const double cols = std::round(wc), rows = std::round(hc);
  if (std::abs(wc - cols) > 1e-9 * std::max(1.0, wc) ||
      std::abs(hc - rows) > 1e-9 * std::max(1.0, hc))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "DEM bounds are not a whole number of " +
                             formatValue(resolution) + " pixels: " + formatValue(wc) +
                             " x " + formatValue(hc));
  if (cols > MAX_SIDE || rows > MAX_SIDE)
    return Status::error(StatusCode::COORDINATE_RANGE, "DEM of " + formatValue(cols) +
                                                           " x " + formatValue(rows) +
                                                           " pixels is too large");
  grid.x0 = x0;
  grid.y1 = y1;
  grid.resolution = resolution;
  grid.cols = static_cast<std::size_t>(cols);
  grid.rows = static_cast<std::size_t>(rows);
  return Status::success();
}

Status rasterizeDem(const TriangleMesh& mesh, const DemGrid& grid, float nodata,
                    std::size_t block_rows, const DemBlockSink& sink,
                    DemRasterStats* stats)
{
  if (block_rows == 0 || grid.cols == 0 || grid.rows == 0 || !(grid.resolution > 0.0))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "empty DEM grid or block of 0 rows");
  const std::size_t n_tri = mesh.triangleCount();
  for (VertexId v : mesh.triangles)
    if (v >= mesh.vertexCount() || mesh.xy.size() != mesh.z.size())
      return Status::error(StatusCode::INVALID_PARAMETER,
                           "triangle vertex out of range");
  std::vector<TriangleBox> box(n_tri);
  for (std::size_t t = 0; t < n_tri; ++t) {
    const Point2& a = mesh.xy[mesh.triangles[3 * t]];
    const Point2& b = mesh.xy[mesh.triangles[3 * t + 1]];
    const Point2& c = mesh.xy[mesh.triangles[3 * t + 2]];
    box[t] = {std::min({a.y, b.y, c.y}), std::max({a.y, b.y, c.y})};
  }
  // North edges first: the sweep runs north to south like the rows.
  std::vector<TriangleId> order(n_tri);
  std::iota(order.begin(), order.end(), TriangleId{0});
  std::sort(order.begin(), order.end(), [&](TriangleId l, TriangleId r) {
    return box[l].ymax > box[r].ymax || (box[l].ymax == box[r].ymax && l < r);
  });

  const double r = grid.resolution;
  std::vector<float> values(grid.cols * std::min(block_rows, grid.rows));
  std::vector<std::uint64_t> owner(values.size());
  std::vector<TriangleId> active;
  std::size_t next = 0;
  DemRasterStats local;
  for (std::size_t row0 = 0; row0 < grid.rows; row0 += block_rows) {
    const std::size_t count = std::min(block_rows, grid.rows - row0);
    const std::size_t row1 = row0 + count - 1;
    // Slack of a pixel: the exact test below decides, the range only prunes.
    const double top = grid.centreY(row0) + r, bottom = grid.centreY(row1) - r;
    while (next < n_tri && box[order[next]].ymax >= bottom)
      active.push_back(order[next++]);
    active.erase(std::remove_if(active.begin(), active.end(),
                                [&](TriangleId t) { return box[t].ymin > top; }),
                 active.end());
    std::fill(values.begin(), values.begin() + count * grid.cols, nodata);
    std::fill(owner.begin(), owner.begin() + count * grid.cols, NO_OWNER);

    for (TriangleId t : active) {
      const VertexId* v = &mesh.triangles[3 * t];
      paintTriangle({mesh.xy[v[0]], mesh.xy[v[1]], mesh.xy[v[2]]},
                    {mesh.z[v[0]], mesh.z[v[1]], mesh.z[v[2]]}, t, grid, row0, row1, 0,
                    grid.cols - 1, values.data(), owner.data());
    }
    for (std::size_t i = 0; i < count * grid.cols; ++i)
      local.pixels_inside += owner[i] != NO_OWNER;
    ++local.blocks;
    if (Status s = sink(row0, count, values.data()); !s.ok())
      return s;
  }
  if (stats)
    *stats = local;
  return Status::success();
}

} // namespace pcl_vts

namespace pcl_vts {
namespace {

/// A triangle as the out-of-core rasterizer files it: corners, heights, its id in the
/// mesh (ties on shared edges go to the smaller).
struct FiledTriangle {
  double x[3], y[3], z[3];
  std::uint64_t id;
};

Status ioFailure(const std::string& what, const std::string& path)
{
  return Status::error(StatusCode::IO_ERROR, "DEM: cannot " + what + " '" + path +
                                                 "': " + std::strerror(errno));
}

/// Appends n bytes to the file at path (created when missing).
Status appendTo(const std::string& path, const void* data, std::size_t n)
{
  std::FILE* f = std::fopen(path.c_str(), "ab");
  if (!f)
    return ioFailure("create", path);
  const bool ok = std::fwrite(data, 1, n, f) == n;
  if (std::fclose(f) != 0 || !ok)
    return ioFailure("write (is the temporary folder full?)", path);
  return Status::success();
}

/// The temporary files of one out-of-core rasterization, removed when it ends.
struct DemTempFiles {
  std::string folder;
  std::size_t windows = 0;
  std::string vertices() const { return folder + "/dem_vertices.bin"; }
  std::string window(std::size_t w) const
  {
    return folder + "/dem_window_" + std::to_string(w) + ".bin";
  }
  ~DemTempFiles()
  {
    for (std::size_t w = 0; w < windows; ++w)
      std::remove(window(w).c_str());
  }
};

} // namespace

Status rasterizeDemOutOfCore(const MeshStream& mesh, const DemGrid& grid, float nodata,
                             std::size_t window, std::uint64_t memory,
                             const std::string& temp_folder, const DemWindowSink& sink,
                             DemRasterStats* stats)
{
  if (window == 0 || grid.cols == 0 || grid.rows == 0 || !(grid.resolution > 0.0))
    return Status::error(StatusCode::INVALID_PARAMETER, "empty DEM grid or window");
  DemTempFiles files;
  files.folder = temp_folder;

  // 1. The vertices into a file, then mapped: triangles look their corners up by id.
  MappedVertices vertices;
  if (Status s = vertices.map(mesh, files.vertices(), "DEM"); !s.ok())
    return s;
  const std::uint64_t n = vertices.count();
  if (n == 0)
    return Status::error(StatusCode::EMPTY_INPUT, "no vertex to rasterize");

  // Square windows as large as keeps the triangles filed for one (about two per
  // vertex, spread over the grid) within `memory`: a multiple of `window` pixels when
  // that fits, else of 32 (a coarse DEM of dense points has many triangles a pixel).
  const double per_pixel =
      2.0 * static_cast<double>(n) /
      (static_cast<double>(grid.cols) * static_cast<double>(grid.rows));
  const double fit = std::sqrt(static_cast<double>(memory) /
                               (sizeof(FiledTriangle) * std::max(per_pixel, 1e-9)));
  const std::size_t step = fit >= static_cast<double>(window) ? window : 32;
  const std::size_t side =
      step * std::max<std::size_t>(
                 1, static_cast<std::size_t>(fit / static_cast<double>(step)));
  const std::size_t across = (grid.cols + side - 1) / side;
  const std::size_t down = (grid.rows + side - 1) / side;
  files.windows = across * down;

  // 2. Each triangle, with its corners, into the file of every window it reaches.
  std::vector<std::vector<FiledTriangle>> pending(files.windows);
  std::size_t pending_count = 0;
  Status filed = Status::success();
  const auto flushAll = [&] {
    for (std::size_t w = 0; w < files.windows; ++w) {
      if (filed.ok() && !pending[w].empty())
        filed = appendTo(files.window(w), pending[w].data(),
                         pending[w].size() * sizeof(FiledTriangle));
      std::vector<FiledTriangle>().swap(pending[w]);
    }
    pending_count = 0;
  };
  // Buffered triangles: a quarter of the memory, then all are written out.
  const std::size_t buffer_limit =
      std::max<std::size_t>(1024, memory / 4 / sizeof(FiledTriangle));
  std::uint64_t id = 0;
  bool bad_id = false;
  const double r = grid.resolution;
  Status s = mesh.triangles([&](VertexId a, VertexId b, VertexId c) {
    const std::uint64_t t = id++;
    if (a >= n || b >= n || c >= n) {
      bad_id = true;
      return;
    }
    FiledTriangle f;
    const VertexId v[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const double* p = vertices.xyz(v[k]);
      f.x[k] = p[0];
      f.y[k] = p[1];
      f.z[k] = p[2];
    }
    f.id = t;
    std::size_t rlo = 0, rhi = 0, clo = 0, chi = 0;
    if (!pixelRange(std::min({f.y[0], f.y[1], f.y[2]}),
                    std::max({f.y[0], f.y[1], f.y[2]}), grid.y1, -1.0, r, grid.rows,
                    rlo, rhi) ||
        !pixelRange(std::min({f.x[0], f.x[1], f.x[2]}),
                    std::max({f.x[0], f.x[1], f.x[2]}), grid.x0, 1.0, r, grid.cols, clo,
                    chi))
      return;
    for (std::size_t wy = rlo / side; wy <= rhi / side; ++wy)
      for (std::size_t wx = clo / side; wx <= chi / side; ++wx) {
        pending[wy * across + wx].push_back(f);
        ++pending_count;
      }
    if (pending_count >= buffer_limit)
      flushAll();
    if ((t & 0x3FFFF) == 0x3FFFF) // pages of corners already used: out of memory
      vertices.dropPages();
  });
  flushAll();
  vertices.release();
  if (!s.ok())
    return s;
  if (!filed.ok())
    return filed;
  if (bad_id)
    return Status::error(StatusCode::INVALID_PARAMETER, "triangle vertex out of range");

  // 3. Window by window, rows of windows north to south.
  std::vector<float> values;
  std::vector<std::uint64_t> owner;
  std::vector<FiledTriangle> here;
  DemRasterStats local;
  for (std::size_t w = 0; w < files.windows; ++w) {
    const std::size_t row0 = (w / across) * side, col0 = (w % across) * side;
    const std::size_t rows = std::min(side, grid.rows - row0);
    const std::size_t cols = std::min(side, grid.cols - col0);
    here.clear();
    if (std::FILE* in = std::fopen(files.window(w).c_str(), "rb")) {
      // Sized from the file: a growing vector would take up to twice the memory.
      bool failed = std::fseek(in, 0, SEEK_END) != 0;
      const long bytes = failed ? 0 : std::ftell(in);
      failed = failed || bytes < 0 || std::fseek(in, 0, SEEK_SET) != 0;
      if (!failed) {
        std::vector<FiledTriangle>(static_cast<std::size_t>(bytes) /
                                   sizeof(FiledTriangle))
            .swap(here);
        failed = std::fread(here.data(), sizeof(FiledTriangle), here.size(), in) !=
                 here.size();
      }
      std::fclose(in);
      std::remove(files.window(w).c_str());
      if (failed)
        return ioFailure("read back", files.window(w));
    }
    values.assign(rows * cols, nodata);
    owner.assign(rows * cols, NO_OWNER);
    for (const FiledTriangle& f : here)
      paintTriangle(
          {Point2{f.x[0], f.y[0]}, Point2{f.x[1], f.y[1]}, Point2{f.x[2], f.y[2]}},
          {f.z[0], f.z[1], f.z[2]}, f.id, grid, row0, row0 + rows - 1, col0,
          col0 + cols - 1, values.data(), owner.data());
    for (std::uint64_t o : owner)
      local.pixels_inside += o != NO_OWNER;
    ++local.blocks;
    if (Status t = sink(row0, col0, rows, cols, values.data()); !t.ok())
      return t;
  }
  if (stats)
    *stats = local;
  return Status::success();
}

} // namespace pcl_vts
