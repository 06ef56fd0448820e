// The GIS products of a mesh, written through GDAL: a Float32 GeoTIFF DEM (tiled,
// DEFLATE, optional overviews), a hillshade PNG, contour lines as GeoPackage or
// Shapefile, every one in the input's coordinate system; and the CRS helpers
// (parse, compare, .prj sidecar). The geometry lives in dem_raster.h and
// contour_lines.h; only this layer knows GDAL, and no GDAL type crosses it.
#pragma once

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/gis/contour_lines.h>
#include <pcl_vts/gis/dem_raster.h>
#include <pcl_vts/gis/export.h>

#include <string>
#include <utility>
#include <vector>

namespace pcl_vts {

/// The value of DEM pixels outside the mesh.
constexpr float DEM_NODATA = -9999.0f;

struct GisOutputOptions {
  std::string dem;         ///< GeoTIFF path (.tif, .tiff), empty = no DEM
  double resolution = 0.0; ///< DEM pixel edge, input XY units (> 0 with a DEM)
  bool bounds_given = false;
  double bounds[4] = {0, 0, 0, 0}; ///< DEM extent X0,Y0,X1,Y1 (whole pixels)
  bool overviews = false;          ///< also build the DEM's internal overviews
  std::string hillshade;           ///< PNG path of the DEM's hillshade (needs dem)
  std::string contours;            ///< .gpkg or .shp path, empty = no contour lines
  double interval = 0.0;           ///< contour step (> 0 with contours)
  double contour_base = 0.0;       ///< levels are contour_base + k * interval
  std::string crs;                 ///< EPSG:XXXX or WKT, overrides the input's

  bool any() const { return !dem.empty() || !contours.empty(); }
};

/// Checks the combination (a resolution with a DEM, an interval with contours, no DEM
/// setting without a DEM, the extensions, the bounds, the CRS parses).
/// INVALID_PARAMETER naming the problem in these fields' words (a tool names its
/// flags itself: tools/gis_cli.cpp).
PCL_VTS_GIS_EXPORT Status validateGisOptions(const GisOutputOptions& options);

/// A CRS from what a user or a file gives: "EPSG:2056", a WKT, a PROJ string,
/// anything OGRSpatialReference::SetFromUserInput reads. Out: its WKT2 form.
PCL_VTS_GIS_EXPORT Status normalizeCrs(const std::string& text, std::string& wkt);

/// True when both describe the same CRS (OGR's IsSame; equal text is always same).
PCL_VTS_GIS_EXPORT bool sameCrs(const std::string& a, const std::string& b);

/// The one CRS of several inputs: (file, crs text) pairs, an empty text meaning
/// "none given". Files without a CRS take the others'; two files whose CRSs differ
/// are INVALID_PARAMETER naming both. Out: the common CRS, empty when none had one.
PCL_VTS_GIS_EXPORT Status commonCrs(
    const std::vector<std::pair<std::string, std::string>>& inputs, std::string& crs);

/// Writes `wkt` (ESRI-flavoured WKT1, as GIS software expects in .prj) beside
/// `path`: "mesh.ply" -> "mesh.prj".
PCL_VTS_GIS_EXPORT Status writePrjSidecar(const std::string& path,
                                          const std::string& wkt);

/// Writes the DEM of mesh over grid: Float32, NODATA DEM_NODATA, 256x256 tiles,
/// DEFLATE with a floating-point predictor, AREA_OR_POINT=Area, the CRS attached
/// when wkt is not empty; rows computed and written 256 at a time.
PCL_VTS_GIS_EXPORT Status writeDemGeoTiff(const std::string& path,
                                          const TriangleMesh& mesh, const DemGrid& grid,
                                          const std::string& wkt, bool overviews,
                                          DemRasterStats* stats = nullptr);

/// The same for a mesh that is not held (the tiled path's): rasterizeDemOutOfCore
/// with its files in temp_folder.
PCL_VTS_GIS_EXPORT Status writeDemGeoTiff(const std::string& path,
                                          const MeshStream& mesh, const DemGrid& grid,
                                          const std::string& wkt, bool overviews,
                                          const std::string& temp_folder,
                                          DemRasterStats* stats = nullptr);

/// Writes the contour lines of mesh as LineString features with a Real field
/// "elev" (and "closed", 0/1): GeoPackage for .gpkg, ESRI Shapefile for .shp.
PCL_VTS_GIS_EXPORT Status writeContourFile(const std::string& path,
                                           const TriangleMesh& mesh, double interval,
                                           double base, const std::string& wkt,
                                           ContourStats* stats = nullptr);

/// The same for a mesh that is not held (the tiled path's): traceContoursOutOfCore
/// with its file in temp_folder; the same features in the same order as for the
/// mesh held.
PCL_VTS_GIS_EXPORT Status writeContourFile(const std::string& path,
                                           const MeshStream& mesh, double interval,
                                           double base, const std::string& wkt,
                                           const std::string& temp_folder,
                                           ContourStats* stats = nullptr);

/// Every product asked for in options, in the CRS wkt (options.crs already applied
/// by the caller). One line per product for the caller's summary.
PCL_VTS_GIS_EXPORT Status writeGisOutputs(const TriangleMesh& mesh,
                                          const std::string& wkt,
                                          const GisOutputOptions& options,
                                          std::vector<std::string>& summary);

/// writeGisOutputs for a mesh that is not held: the DEM (and its hillshade) and the
/// contours out of core, with files in temp_folder and DEM windows within `memory`
/// bytes (the contours hold their segments: memory grows with their output).
PCL_VTS_GIS_EXPORT Status writeGisOutputsOutOfCore(const MeshStream& mesh,
                                                   const std::string& wkt,
                                                   const GisOutputOptions& options,
                                                   std::uint64_t memory,
                                                   const std::string& temp_folder,
                                                   std::vector<std::string>& summary);

} // namespace pcl_vts
