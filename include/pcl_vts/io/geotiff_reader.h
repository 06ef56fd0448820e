// GeoTIFF (and any single-band raster GDAL reads) as points at the cell centres,
// NODATA cells skipped. GDAL is an optional dependency: without it (the build did not
// find GDAL) the reader refuses with a message saying how to convert to an ASCII grid.
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/io/export.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace pcl_vts {

struct GeoTiffInfo {
  std::size_t columns = 0, rows = 0;
  std::size_t valid_cells = 0;
  std::size_t nodata_cells = 0;
  bool has_nodata = false;
  double nodata = 0.0;
  double pixel_width = 0.0, pixel_height = 0.0; ///< geotransform [1] and [5]
  std::string driver;                           ///< GDAL driver, e.g. "GTiff"
  std::string crs_wkt; ///< the raster's coordinate system, empty when it has none
};

/// True when this build reads rasters through GDAL.
PCL_VTS_IO_EXPORT bool geoTiffSupported();

/// Reads band 1 of a raster: one point per valid cell centre, x and y from the
/// geotransform (rotation terms included), z the cell value, in double.
/// \return IO_ERROR (cannot open, no GDAL in this build), EMPTY_INPUT (every cell
///         NODATA)
PCL_VTS_IO_EXPORT Status readGeoTiff(const std::string& path, std::vector<double>& xyz,
                                     GeoTiffInfo& info);

/// Receives points, xyz triples in row order, a chunk at a time.
using GeoTiffChunkSink = std::function<Status(const double* xyz, std::size_t n)>;

/// Same as readGeoTiff, but the valid cells go to `sink` in chunks of about
/// chunk_points (whole rows), read row by row: memory stays bounded by the chunk
/// whatever the raster's size. A sink error stops the read and is returned.
PCL_VTS_IO_EXPORT Status readGeoTiffChunks(const std::string& path,
                                           std::size_t chunk_points,
                                           const GeoTiffChunkSink& sink,
                                           GeoTiffInfo& info);

} // namespace pcl_vts
