#include "grid_internals.h"

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <utility>

namespace pcl_vts {
namespace {

constexpr double EPS = std::numeric_limits<double>::epsilon();
// Hard ceiling on grid cells, whatever the cell size asked for.
constexpr double MAX_CELLS_PER_POINT = 64.0;
constexpr double MAX_CELLS_FLOOR = 1 << 22;
constexpr double MAX_CELLS_ABSOLUTE = 1u << 30;

/// Counts the cells of side `size` anchored at (xmin, ymin) that hold a point: the
/// input of refinedCellSize.
std::size_t countOccupiedCells(const std::vector<Point2>& points, double xmin,
                               double ymin, double width, double height, double size)
{
  const auto nx = detail::occupancyColumns(width, size);
  const auto ny = detail::occupancyColumns(height, size);
  std::vector<bool> occupied(nx * ny, false);
  std::size_t count = 0;
  const double inv = 1.0 / size;
  for (const Point2& p : points) {
    const auto i = std::min(static_cast<std::size_t>((p.x - xmin) * inv), nx - 1);
    const auto j = std::min(static_cast<std::size_t>((p.y - ymin) * inv), ny - 1);
    if (!occupied[j * nx + i]) {
      occupied[j * nx + i] = true;
      ++count;
    }
  }
  return count;
}

/// Sorts slots [first, last) of a grid lexicographically (ties by input index),
/// carrying `order` along.
void sortCell(std::vector<Point2>& points, std::vector<std::uint32_t>& order,
              std::size_t first, std::size_t last)
{
  constexpr std::size_t INSERTION_SORT_MAX = 16;
  if (last - first > INSERTION_SORT_MAX) {
    std::vector<std::pair<Point2, std::uint32_t>> cell;
    cell.reserve(last - first);
    for (std::size_t k = first; k < last; ++k)
      cell.emplace_back(points[k], order[k]);
    std::sort(cell.begin(), cell.end(), [](const auto& a, const auto& b) {
      return lexLess(a.first, b.first) || (a.first == b.first && a.second < b.second);
    });
    for (std::size_t k = first; k < last; ++k)
      std::tie(points[k], order[k]) = cell[k - first];
    return;
  }
  for (std::size_t k = first + 1; k < last; ++k) {
    const Point2 p = points[k];
    const std::uint32_t o = order[k];
    std::size_t m = k;
    for (; m > first; --m) {
      const Point2& q = points[m - 1];
      if (!(lexLess(p, q) || (p == q && o < order[m - 1])))
        break;
      points[m] = q;
      order[m] = order[m - 1];
    }
    points[m] = p;
    order[m] = o;
  }
}

} // namespace

double defaultCellSize(double width, double height, std::size_t n)
{
  const double k = DEFAULT_POINTS_PER_CELL;
  const double count = static_cast<double>(std::max<std::size_t>(n, 1));
  const double by_area = std::sqrt(width * height * k / count);
  const double by_length = std::max(width, height) * k / count;
  const double size = std::max(by_area, by_length);
  return size > 0.0 ? size : 1.0;
}

namespace detail {

std::size_t occupancyColumns(double extent, double size)
{
  return static_cast<std::size_t>(extent / size) + 1;
}

double initialCellSize(double cell_size, double width, double height, std::size_t n)
{
  // A cell wider than the data is one cell either way: clamp, so cell indices and
  // circle bounds stay in the data's range.
  const double extent = std::max(width, height);
  return cell_size > 0.0 ? (extent > 0.0 ? std::min(cell_size, extent) : cell_size)
                         : defaultCellSize(width, height, n);
}

/// Refines an area-based cell size for clustered data: when the points occupy only a
/// fraction of the bounding box, the occupied cells hold many more than k points.
/// Shrinking the cells so that occupied cells hold about k points keeps the edge
/// rectangles small; the total number of cells is kept below
/// MAX_REFINED_CELLS_PER_POINT * n.
double refinedCellSize(double width, double height, std::size_t n, double size,
                       std::size_t occupied)
{
  constexpr double MAX_REFINED_CELLS_PER_POINT = 4.0;
  // Inputs below 2^16 points keep the area-based size: with cache blocks the finer
  // cells cost more than the searches they shorten (more cells, and more blocks, so
  // more triangles left to the search at block borders). Clustered 1e3 (37 x 39 cells
  // refined, 23 x 23 not: one block), a repeated call 315 -> 222 us; 1e4 3652 -> 3118
  // us (1e5 40.7 -> 38.1 ms, 1e6 a wash: left to the measurements at those sizes).
  if (n < REFINE_MIN_POINTS)
    return size;
  const double per_cell = static_cast<double>(n) / static_cast<double>(occupied);
  if (per_cell <= 2.0 * DEFAULT_POINTS_PER_CELL)
    return size;
  const double refined = size * std::sqrt(DEFAULT_POINTS_PER_CELL / per_cell);
  const double floor = std::sqrt(
      width * height / (MAX_REFINED_CELLS_PER_POINT * static_cast<double>(n)));
  return std::max(refined, floor);
}

Status setGridGeometry(double xmin, double ymin, double width, double height,
                       std::size_t n, double size, CellGrid& grid)
{
  const double nx = std::floor(width / size) + 1.0;
  const double ny = std::floor(height / size) + 1.0;
  const double limit =
      std::min(MAX_CELLS_ABSOLUTE,
               std::max(MAX_CELLS_FLOOR, MAX_CELLS_PER_POINT * static_cast<double>(n)));
  if (!(nx * ny <= limit))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "cell_size = " + formatValue(size) + " gives " +
                             formatValue(nx * ny) + " cells for " + std::to_string(n) +
                             " points (limit " + formatValue(limit) +
                             "); use a larger cell size, or 0 for automatic");

  grid.origin_x = xmin;
  grid.origin_y = ymin;
  grid.cell_size = size;
  grid.inv_cell_size = 1.0 / size;
  grid.nx = static_cast<std::uint32_t>(nx);
  grid.ny = static_cast<std::uint32_t>(ny);
  // Rounding in (x - origin) * inv and in origin + i * size stays within a few ulps
  // of the largest magnitude involved.
  grid.slack =
      8.0 * EPS * (std::fabs(xmin) + std::fabs(ymin) + width + height + 2.0 * size);
  return Status::success();
}

} // namespace detail

Status buildCellGrid(const std::vector<Point2>& points, double cell_size,
                     CellGrid& grid, std::vector<std::uint32_t>& order,
                     unsigned threads)
{
  const std::size_t n = points.size();
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin;
  double xmax = -xmin, ymax = -xmin;
  for (const Point2& p : points) {
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  }
  if (n == 0)
    xmin = xmax = ymin = ymax = 0.0;
  const double width = xmax - xmin, height = ymax - ymin;
  double size = detail::initialCellSize(cell_size, width, height, n);
  if (cell_size == 0.0 && n > 0 && width > 0.0 && height > 0.0)
    size = detail::refinedCellSize(
        width, height, n, size,
        countOccupiedCells(points, xmin, ymin, width, height, size));
  if (Status s = detail::setGridGeometry(xmin, ymin, width, height, n, size, grid);
      !s.ok())
    return s;

  // Counting sort by cell.
  std::vector<CellId> cell_of(n);
  grid.cell_start.assign(grid.cellCount() + 1, 0);
  for (std::size_t k = 0; k < n; ++k) {
    cell_of[k] = grid.cellOf(points[k]);
    ++grid.cell_start[cell_of[k] + 1];
  }
  for (std::size_t c = 0; c < grid.cellCount(); ++c)
    grid.cell_start[c + 1] += grid.cell_start[c];
  order.resize(n);
  {
    std::vector<std::uint32_t> fill(grid.cell_start.begin(), grid.cell_start.end() - 1);
    for (std::size_t k = 0; k < n; ++k)
      order[fill[cell_of[k]]++] = static_cast<std::uint32_t>(k);
  }
  grid.points.resize(n);
  parallelFor(threads, n, [&](std::size_t k) { grid.points[k] = points[order[k]]; });
  // Lexicographic inside each cell, on the gathered copy (no random reads), carrying
  // `order` along: insertion sort for the usual handful of points, std::sort for
  // crowded cells.
  parallelFor(threads, grid.cellCount(), [&](std::size_t c) {
    sortCell(grid.points, order, grid.cell_start[c], grid.cell_start[c + 1]);
  });
  return Status::success();
}

void compactCellStarts(CellGrid& grid)
{
  const std::size_t cells = grid.cellCount();
  if (grid.cell_start.size() != cells + 1 || cells <= 2 * grid.points.size())
    return;
  constexpr std::size_t BLOCK = 16;
  const std::size_t blocks = (cells >> 4) + 1; // the end slot's block too
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t last = std::min(cells, b * BLOCK + BLOCK - 1);
    if (grid.cell_start[last] - grid.cell_start[b * BLOCK] > 255)
      return;
  }
  std::vector<std::uint32_t> block_start(blocks);
  std::vector<std::uint8_t> cell_offset(cells + 1);
  for (std::size_t b = 0; b < blocks; ++b)
    block_start[b] = grid.cell_start[b * BLOCK];
  for (std::size_t c = 0; c <= cells; ++c)
    cell_offset[c] =
        static_cast<std::uint8_t>(grid.cell_start[c] - block_start[c >> 4]);
  grid.block_start = std::move(block_start);
  grid.cell_offset = std::move(cell_offset);
  std::vector<std::uint32_t>().swap(grid.cell_start);
}

} // namespace pcl_vts
