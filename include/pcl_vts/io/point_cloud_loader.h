// One entry point for every input the CLI reads: the reader is chosen by the file's
// extension (any case) or, for an unknown extension, by its first bytes; the result
// is always xyz doubles plus a description for the summary. PCD goes through PCL
// (pcd_cloud_reader.h); LAS, ASCII grid, XYZ text and PLY readers are PCL-free.
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/io/export.h>
#include <pcl_vts/io/las_reader.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pcl_vts {

enum class CloudFileFormat { PCD, LAS, ASC, XYZ, PLY, GEOTIFF };

/// "PCD", "LAS", "ASCII grid", "XYZ text", "PLY", "GeoTIFF".
PCL_VTS_IO_EXPORT const char* cloudFileFormatName(CloudFileFormat format);

/// Reader by extension: .pcd, .las/.laz, .asc, .xyz/.txt/.csv, .ply, .tif/.tiff
/// (any case).
/// False for any other extension (or none).
PCL_VTS_IO_EXPORT bool cloudFileFormatFromExtension(const std::string& path,
                                                    CloudFileFormat& format);

/// Reader by content: "LASF", "ply", a PCD header keyword, an ASCII grid "ncols",
/// a TIFF byte-order mark.
/// False when none matches.
PCL_VTS_IO_EXPORT bool cloudFileFormatFromContent(const std::uint8_t* data,
                                                  std::size_t size,
                                                  CloudFileFormat& format);

struct CloudLoadOptions {
  /// LAS only: classification codes to keep (empty = all); a non-empty list on any
  /// other format is INVALID_PARAMETER.
  std::vector<std::uint8_t> classes;
  /// LAS only: returns to keep; anything but ALL on another format is
  /// INVALID_PARAMETER.
  LasReturnFilter returns = LasReturnFilter::ALL;
  /// LAZ only: chunks decoded at once, one per thread; 0 = all cores.
  unsigned threads = 1;
};

struct CloudDescription {
  CloudFileFormat format = CloudFileFormat::PCD;
  std::size_t points_read = 0; ///< points (records, valid cells, lines) in the file
  std::size_t points_kept = 0; ///< points returned (after filters, NODATA skipped)
  /// One line for the summary: "LAS 1.2, point format 3, 34-byte records; ...".
  std::string details;
  /// Extra facts worth a summary line each ("1734 NODATA cells skipped").
  std::vector<std::string> notes;
  /// The coordinate system the file declares, as found: a WKT (LAS OGC WKT record,
  /// GeoTIFF, a .prj beside the file) or "EPSG:n" (LAS GeoTIFF keys); empty when
  /// none. Not validated here (no GDAL in io's API): pcl_vts::gis parses it.
  std::string crs;
  /// Where crs came from: "LAS WKT VLR", "LAS GeoKeys VLR", "GeoTIFF", "'x.prj'".
  std::string crs_source;
};

/// Reads path into 3 doubles per kept point.
/// \return the reader's status (IO_ERROR, EMPTY_INPUT); IO_ERROR for an unknown
///         extension whose content is not recognised either; INVALID_PARAMETER for a
///         LAS-only option on another format.
PCL_VTS_IO_EXPORT Status loadPointCloud(const std::string& path,
                                        const CloudLoadOptions& options,
                                        std::vector<double>& xyz,
                                        CloudDescription& description);

/// Receives points, xyz triples in file order, a chunk at a time.
using PointChunkSink = std::function<Status(const double* xyz, std::size_t n)>;

/// Reads path like loadPointCloud, but hands the kept points to `sink`: LAS, LAZ, XYZ
/// text, ASCII grids, PLY and GeoTIFF chunk by chunk (at most chunk_points each, the
/// file's pages released behind the reader, or the raster read row by row, so memory
/// stays bounded whatever the file's size); PCD (through PCL) in one piece after
/// reading the file whole. A sink error stops the read and is returned.
PCL_VTS_IO_EXPORT Status streamPointCloud(const std::string& path,
                                          const CloudLoadOptions& options,
                                          std::size_t chunk_points,
                                          const PointChunkSink& sink,
                                          CloudDescription& description);

} // namespace pcl_vts
