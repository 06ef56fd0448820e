// The DEM of a TIN, as geometry only (no GDAL, no PCL): a north-up grid of square
// pixels, each pixel centre given the linear interpolation of z in the triangle
// containing it, NODATA outside the mesh. Produced row block by row block, so the
// raster is never held whole; a writer (dem_geotiff.h) stores the blocks.
#pragma once

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/gis/export.h>
#include <pcl_vts/gis/mesh_stream.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pcl_vts {

/// Pixel-is-area grid: pixel (col, row) covers [x0 + col*R, x0 + (col+1)*R] x
/// [y1 - (row+1)*R, y1 - row*R]; its value is sampled at the centre
/// (x0 + (col+0.5)*R, y1 - (row+0.5)*R). Row 0 is the north edge.
struct DemGrid {
  double x0 = 0.0;         ///< west edge
  double y1 = 0.0;         ///< north edge
  double resolution = 1.0; ///< pixel edge length R
  std::size_t cols = 0;
  std::size_t rows = 0;

  double centreX(std::size_t col) const
  {
    return x0 + (static_cast<double>(col) + 0.5) * resolution;
  }
  double centreY(std::size_t row) const
  {
    return y1 - (static_cast<double>(row) + 0.5) * resolution;
  }
};

/// The default grid for a mesh: edges snapped outward to multiples of R, so pixel
/// centres sit at multiples of R plus R/2 and tiles of adjacent runs line up.
/// \return INVALID_PARAMETER for R <= 0 or non-finite, EMPTY_INPUT for no vertex,
///         COORDINATE_RANGE for more than 2^31 pixels on a side.
PCL_VTS_GIS_EXPORT Status demGridForMesh(const TriangleMesh& mesh, double resolution,
                                         DemGrid& grid);

/// The same for vertices spanning [xmin, xmax] x [ymin, ymax].
PCL_VTS_GIS_EXPORT Status demGridForExtent(double xmin, double ymin, double xmax,
                                           double ymax, double resolution,
                                           DemGrid& grid);

/// The grid for explicit bounds X0,Y0,X1,Y1 (west, south, east, north): their
/// extent must be a whole number of pixels (within 1e-9 relative).
PCL_VTS_GIS_EXPORT Status demGridForBounds(double x0, double y0, double x1, double y1,
                                           double resolution, DemGrid& grid);

/// Receives rows [first_row, first_row + row_count) of values, row-major
/// (grid.cols per row); pixels outside the mesh hold `nodata`.
using DemBlockSink = std::function<Status(std::size_t first_row, std::size_t row_count,
                                          const float* values)>;

struct DemRasterStats {
  std::size_t pixels_inside = 0; ///< pixels that got a value
  std::size_t blocks = 0;
};

/// Rasterizes the mesh over grid, block_rows rows at a time (triangles swept in
/// order of their north edge, so each block sees only the triangles that cross
/// it). Point location is exact (orient2d): a pixel centre strictly inside a
/// triangle, or on its edge or vertex, belongs to it; a centre on an edge shared by
/// two triangles takes the value of the first in the mesh's triangle order (both
/// interpolate the same line there, up to rounding). Degenerate (zero-area)
/// triangles cover nothing. z is interpolated in double and stored as float.
PCL_VTS_GIS_EXPORT Status rasterizeDem(const TriangleMesh& mesh, const DemGrid& grid,
                                       float nodata, std::size_t block_rows,
                                       const DemBlockSink& sink,
                                       DemRasterStats* stats = nullptr);

/// Receives the window rows [row0, row0 + rows) x cols [col0, col0 + cols), row-major.
using DemWindowSink =
    std::function<Status(std::size_t row0, std::size_t col0, std::size_t rows,
                         std::size_t cols, const float* values)>;

/// rasterizeDem for a mesh that is not held: the same pixels. The vertices go to a
/// file in temp_folder (24 B each, mapped while the triangles pass), each triangle
/// with its corners to the file of every square window it reaches (80 B), then the
/// windows are rasterized one by one, in rows of windows from the north. A window is
/// as large as keeps its triangles within `memory` bytes (at the mean density: two
/// triangles per vertex over the grid), a multiple of `window` pixels on a side when
/// that fits, else of 32.
/// The files are removed.
PCL_VTS_GIS_EXPORT Status rasterizeDemOutOfCore(
    const MeshStream& mesh, const DemGrid& grid, float nodata, std::size_t window,
    std::uint64_t memory, const std::string& temp_folder, const DemWindowSink& sink,
    DemRasterStats* stats = nullptr);

} // namespace pcl_vts
