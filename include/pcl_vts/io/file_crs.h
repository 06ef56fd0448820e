// The coordinate system an input file declares, found without GDAL: LAS projection
// records (the OGC WKT record, or the GeoTIFF keys' EPSG code) and a .prj sidecar
// beside any file. The text is returned as found; pcl_vts::gis parses it.
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/io/export.h>

#include <string>

namespace pcl_vts {

/// The CRS of a LAS file: the "LASF_Projection" record 2112 (OGC WKT, in a VLR or
/// a LAS 1.4 EVLR) when present, else "EPSG:n" from the GeoKeyDirectory record
/// 34735 (ProjectedCSTypeGeoKey 3072, else GeographicTypeGeoKey 2048; user-defined
/// 32767 is not a code). crs stays empty when the file declares none; source names
/// the record used. Records that do not fit the file are ignored, never trusted.
/// \return IO_ERROR only when the file cannot be opened or read.
PCL_VTS_IO_EXPORT Status readLasCrs(const std::string& path, std::string& crs,
                                    std::string& source);

/// The text of the .prj beside path ("dir/x.asc" -> "dir/x.prj", any case of .prj),
/// trimmed; empty when there is none. source gets the .prj's path.
PCL_VTS_IO_EXPORT Status readPrjSidecar(const std::string& path, std::string& crs,
                                        std::string& source);

} // namespace pcl_vts
