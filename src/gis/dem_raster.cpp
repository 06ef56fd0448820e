// Scanline rasterization of a TIN: triangles sorted by their north edge enter the
// active list when the sweep reaches them and leave it when it has passed them, so a
// block of rows touches only the triangles that cross it and memory is one block.
#include <pcl_vts/core/predicates.h>
#include <pcl_vts/gis/dem_raster.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

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

} // namespace

Status demGridForMesh(const TriangleMesh& mesh, double resolution, DemGrid& grid)
{
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "DEM resolution must be a positive number, not " +
                             formatValue(resolution));
  if (mesh.xy.empty() || mesh.triangles.empty())
    return Status::error(StatusCode::EMPTY_INPUT, "no triangle to rasterize");
  double xmin = mesh.xy[0].x, xmax = xmin, ymin = mesh.xy[0].y, ymax = ymin;
  for (const Point2& p : mesh.xy) {
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  }
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
  std::vector<TriangleId> owner(values.size());
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
    std::fill(owner.begin(), owner.begin() + count * grid.cols, INVALID_ID);

    for (TriangleId t : active) {
      VertexId ia = mesh.triangles[3 * t], ib = mesh.triangles[3 * t + 1],
               ic = mesh.triangles[3 * t + 2];
      const Sign turn = orient2d(mesh.xy[ia], mesh.xy[ib], mesh.xy[ic]);
      if (turn == Sign::ZERO)
        continue;
      if (turn == Sign::NEGATIVE)
        std::swap(ib, ic);
      const Point2 &a = mesh.xy[ia], &b = mesh.xy[ib], &c = mesh.xy[ic];
      std::size_t rlo = 0, rhi = 0, clo = 0, chi = 0;
      if (!pixelRange(box[t].ymin, box[t].ymax, grid.y1, -1.0, r, grid.rows, rlo, rhi))
        continue;
      rlo = std::max(rlo, row0);
      rhi = std::min(rhi, row1);
      const double xmin = std::min({a.x, b.x, c.x}), xmax = std::max({a.x, b.x, c.x});
      if (rlo > rhi || !pixelRange(xmin, xmax, grid.x0, 1.0, r, grid.cols, clo, chi))
        continue;
      const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
      const double det = bx * cy - cx * by;
      const double dzb = mesh.z[ib] - mesh.z[ia], dzc = mesh.z[ic] - mesh.z[ia];
      for (std::size_t row = rlo; row <= rhi; ++row) {
        const double py = grid.centreY(row);
        for (std::size_t col = clo; col <= chi; ++col) {
          const std::size_t i = (row - row0) * grid.cols + col;
          if (owner[i] < t)
            continue; // an earlier triangle holds this centre (a shared edge)
          const Point2 p{grid.centreX(col), py};
          if (orient2d(a, b, p) == Sign::NEGATIVE ||
              orient2d(b, c, p) == Sign::NEGATIVE ||
              orient2d(c, a, p) == Sign::NEGATIVE)
            continue;
          const double px = p.x - a.x, qy = p.y - a.y;
          const double lb = (px * cy - cx * qy) / det;
          const double lc = (bx * qy - px * by) / det;
          values[i] = static_cast<float>(mesh.z[ia] + lb * dzb + lc * dzc);
          owner[i] = t;
        }
      }
    }
    for (std::size_t i = 0; i < count * grid.cols; ++i)
      local.pixels_inside += owner[i] != INVALID_ID;
    ++local.blocks;
    if (Status s = sink(row0, count, values.data()); !s.ok())
      return s;
  }
  if (stats)
    *stats = local;
  return Status::success();
}

} // namespace pcl_vts
