// The GDAL side of the GIS products: a GeoTIFF filled block by block from
// rasterizeDem, OGR layers filled line by line from traceContours, and the CRS
// helpers. Files appear whole or not at all: written to a temporary name, renamed.
#include <pcl_vts/gis/gis_outputs.h>

#include <cerrno>
#include <cmath>
#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <memory>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>
#include <unistd.h>

namespace pcl_vts {

namespace {

constexpr std::size_t DEM_BLOCK = 256;

std::string lower(std::string s)
{
  for (char& c : s)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool endsWith(const std::string& s, const std::string& tail)
{
  return s.size() >= tail.size() && lower(s.substr(s.size() - tail.size())) == tail;
}

std::string lastGdalError()
{
  const char* m = CPLGetLastErrorMsg();
  return m && *m ? std::string(": ") + m : std::string();
}

/// ".<name>.tmp.<pid><ext>" in path's folder: GDAL drivers pick by extension too.
std::string tempPath(const std::string& path, const std::string& ext)
{
  const std::size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  return dir + "." + name + ".tmp." + std::to_string(::getpid()) + ext;
}

Status ioError(const std::string& what)
{
  return Status::error(StatusCode::IO_ERROR, what + lastGdalError());
}

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

} // namespace

Status validateGisOptions(const GisOutputOptions& o)
{
  auto bad = [](const std::string& m) {
    return Status::error(StatusCode::INVALID_PARAMETER, m);
  };
  if (!o.dem.empty() && !(o.resolution > 0.0))
    return bad("a DEM needs a resolution > 0 (the pixel edge in input units)");
  if (o.dem.empty() &&
      (o.resolution > 0.0 || o.bounds_given || o.overviews || !o.hillshade.empty()))
    return bad("the resolution, the DEM bounds, the overviews and the hillshade are "
               "settings of a DEM, and no DEM path is given");
  if (!o.dem.empty() && !endsWith(o.dem, ".tif") && !endsWith(o.dem, ".tiff"))
    return bad("the DEM path '" + o.dem + "' does not end in .tif or .tiff");
  if (!o.hillshade.empty() && !endsWith(o.hillshade, ".png"))
    return bad("the hillshade path '" + o.hillshade + "' does not end in .png");
  if (!o.contours.empty() && !(o.interval > 0.0))
    return bad("contour lines need an interval > 0 (the elevation step)");
  if (o.contours.empty() && o.interval > 0.0)
    return bad("a contour interval is given, and no contour path");
  if (!o.contours.empty() && !endsWith(o.contours, ".gpkg") &&
      !endsWith(o.contours, ".shp"))
    return bad("the contour path '" + o.contours + "' does not end in .gpkg or .shp");
  if (o.bounds_given) {
    DemGrid grid;
    if (Status s = demGridForBounds(o.bounds[0], o.bounds[1], o.bounds[2], o.bounds[3],
                                    o.resolution, grid);
        !s.ok())
      return bad(s.message); // "DEM bounds ..."
  }
  if (!o.crs.empty()) {
    std::string wkt;
    if (Status s = normalizeCrs(o.crs, wkt); !s.ok())
      return bad(s.message); // "'...' is not a coordinate system ..."
  }
  return Status::success();
}

Status normalizeCrs(const std::string& text, std::string& wkt)
{
  OGRSpatialReference srs;
  CPLErrorReset();
  if (srs.SetFromUserInput(text.c_str()) != OGRERR_NONE)
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "'" + text.substr(0, 80) +
                             "' is not a coordinate system GDAL knows" +
                             lastGdalError());
  char* out = nullptr;
  const char* opts[] = {"FORMAT=WKT2_2019", "MULTILINE=NO", nullptr};
  if (srs.exportToWkt(&out, opts) != OGRERR_NONE || !out) {
    CPLFree(out);
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "'" + text.substr(0, 80) + "' cannot be written as WKT");
  }
  wkt = out;
  CPLFree(out);
  return Status::success();
}

bool sameCrs(const std::string& a, const std::string& b)
{
  if (a == b)
    return true;
  OGRSpatialReference sa, sb;
  if (sa.SetFromUserInput(a.c_str()) != OGRERR_NONE ||
      sb.SetFromUserInput(b.c_str()) != OGRERR_NONE)
    return false;
  const char* opts[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", nullptr};
  return sa.IsSame(&sb, opts) != 0;
}

Status commonCrs(const std::vector<std::pair<std::string, std::string>>& inputs,
                 std::string& crs)
{
  crs.clear();
  std::string first_file;
  for (const auto& [file, text] : inputs) {
    if (text.empty())
      continue;
    if (crs.empty()) {
      crs = text;
      first_file = file;
    } else if (!sameCrs(crs, text))
      return Status::error(StatusCode::INVALID_PARAMETER,
                           "'" + first_file + "' and '" + file +
                               "' are in different coordinate systems; reproject one "
                               "(gdalwarp, pdal translate) or set the one to use");
  }
  return Status::success();
}

Status writePrjSidecar(const std::string& path, const std::string& wkt)
{
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  const std::string prj =
      (dot == std::string::npos || (slash != std::string::npos && dot < slash)
           ? path
           : path.substr(0, dot)) +
      ".prj";
  OGRSpatialReference srs;
  if (srs.SetFromUserInput(wkt.c_str()) != OGRERR_NONE)
    return Status::error(StatusCode::INVALID_PARAMETER,
                         "not a CRS: " + wkt.substr(0, 80));
  char* out = nullptr;
  const char* opts[] = {"FORMAT=WKT1_ESRI", nullptr};
  std::string text;
  if (srs.exportToWkt(&out, opts) == OGRERR_NONE && out)
    text = out;
  else { // no ESRI form (e.g. a compound CRS): the plain WKT
    CPLFree(out);
    out = nullptr;
    if (srs.exportToWkt(&out) != OGRERR_NONE || !out) {
      CPLFree(out);
      return Status::error(StatusCode::INVALID_PARAMETER,
                           "CRS cannot be written as WKT");
    }
    text = out;
  }
  CPLFree(out);
  std::ofstream f(prj, std::ios::binary | std::ios::trunc);
  f << text << '\n';
  f.close();
  if (!f)
    return Status::error(StatusCode::IO_ERROR, "cannot write '" + prj + "'");
  return Status::success();
}

/// The GeoTIFF of a grid whose windows `rasterize` hands to the sink it is given.
Status writeDemTiff(const std::string& path, const DemGrid& grid,
                    const std::string& wkt, bool overviews,
                    const std::function<Status(const DemWindowSink&)>& rasterize)
{
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver)
    return Status::error(StatusCode::IO_ERROR, "GDAL has no GTiff driver");
  if (grid.cols > 2147483647u || grid.rows > 2147483647u)
    return Status::error(StatusCode::COORDINATE_RANGE, "DEM too large for GDAL");
  const std::string tmp = tempPath(path, ".tif");
  const char* create[] = {
      "TILED=YES",   "BLOCKXSIZE=256",   "BLOCKYSIZE=256", "COMPRESS=DEFLATE",
      "PREDICTOR=3", "BIGTIFF=IF_SAFER", nullptr};
  CPLErrorReset();
  DatasetPtr ds(driver->Create(tmp.c_str(), static_cast<int>(grid.cols),
                               static_cast<int>(grid.rows), 1, GDT_Float32,
                               const_cast<char**>(create)));
  if (!ds)
    return ioError("cannot create '" + path + "'");
  auto fail = [&](Status s) {
    ds.reset();
    VSIUnlink(tmp.c_str());
    return s;
  };
  double transform[6] = {grid.x0, grid.resolution, 0.0, grid.y1, 0.0, -grid.resolution};
  ds->SetGeoTransform(transform);
  ds->SetMetadataItem("AREA_OR_POINT", "Area");
  if (!wkt.empty()) {
    OGRSpatialReference srs;
    if (srs.SetFromUserInput(wkt.c_str()) != OGRERR_NONE ||
        ds->SetSpatialRef(&srs) != CE_None)
      return fail(
          Status::error(StatusCode::INVALID_PARAMETER,
                        "the CRS cannot be attached to the GeoTIFF" + lastGdalError()));
  }
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(DEM_NODATA);
  Status s = rasterize([&](std::size_t row0, std::size_t col0, std::size_t rows,
                           std::size_t cols, const float* values) {
    if (band->RasterIO(GF_Write, static_cast<int>(col0), static_cast<int>(row0),
                       static_cast<int>(cols), static_cast<int>(rows),
                       const_cast<float*>(values), static_cast<int>(cols),
                       static_cast<int>(rows), GDT_Float32, 0, 0) != CE_None)
      return ioError("cannot write '" + path + "'");
    return Status::success();
  });
  if (!s.ok())
    return fail(s);
  if (overviews) {
    std::vector<int> levels;
    for (std::size_t f = 2; grid.cols / f >= 128 || grid.rows / f >= 128; f *= 2)
      levels.push_back(static_cast<int>(f));
    if (levels.empty())
      levels.push_back(2);
    CPLSetThreadLocalConfigOption("COMPRESS_OVERVIEW", "DEFLATE");
    const CPLErr e = ds->BuildOverviews("AVERAGE", static_cast<int>(levels.size()),
                                        levels.data(), 0, nullptr, nullptr, nullptr);
    CPLSetThreadLocalConfigOption("COMPRESS_OVERVIEW", nullptr);
    if (e != CE_None)
      return fail(ioError("cannot build the overviews of '" + path + "'"));
  }
  ds->FlushCache();
  CPLErrorReset();
  GDALClose(ds.release());
  if (CPLGetLastErrorType() == CE_Failure) {
    VSIUnlink(tmp.c_str());
    return ioError("cannot write '" + path + "'");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    VSIUnlink(tmp.c_str());
    return Status::error(StatusCode::IO_ERROR,
                         "cannot rename to '" + path + "': " + std::strerror(err));
  }
  return Status::success();
}

Status writeDemGeoTiff(const std::string& path, const TriangleMesh& mesh,
                       const DemGrid& grid, const std::string& wkt, bool overviews,
                       DemRasterStats* stats)
{
  return writeDemTiff(path, grid, wkt, overviews, [&](const DemWindowSink& sink) {
    return rasterizeDem(
        mesh, grid, DEM_NODATA, DEM_BLOCK,
        [&](std::size_t row0, std::size_t count, const float* values) {
          return sink(row0, 0, count, grid.cols, values);
        },
        stats);
  });
}

Status writeDemGeoTiff(const std::string& path, const MeshStream& mesh,
                       const DemGrid& grid, const std::string& wkt, bool overviews,
                       std::uint64_t memory, const std::string& temp_folder,
                       DemRasterStats* stats)
{
  return writeDemTiff(path, grid, wkt, overviews, [&](const DemWindowSink& sink) {
    return rasterizeDemOutOfCore(mesh, grid, DEM_NODATA, DEM_BLOCK, memory, temp_folder,
                                 sink, stats);
  });
}

namespace {

Status writeHillshade(const std::string& dem, const std::string& png)
{
  DatasetPtr src(static_cast<GDALDataset*>(GDALOpen(dem.c_str(), GA_ReadOnly)));
  if (!src)
    return ioError("cannot reopen '" + dem + "'");
  const char* argv[] = {"-of", "PNG", "-compute_edges", "-multidirectional", nullptr};
  GDALDEMProcessingOptions* opts =
      GDALDEMProcessingOptionsNew(const_cast<char**>(argv), nullptr);
  int usage_error = 0;
  GDALDatasetH out = GDALDEMProcessing(png.c_str(), src.get(), "hillshade", nullptr,
                                       opts, &usage_error);
  GDALDEMProcessingOptionsFree(opts);
  if (!out)
    return ioError("cannot write '" + png + "'");
  GDALClose(out);
  VSIUnlink((png + ".aux.xml").c_str()); // the PNG is a picture, not a raster product
  return Status::success();
}

} // namespace

namespace {

/// The contour layer of path, filled by trace(sink): the same file for a mesh held
/// and one streamed.
template <typename Trace>
Status writeContourLayer(const std::string& path, const std::string& wkt,
                         const Trace& trace)
{
  GDALAllRegister();
  const bool shp = endsWith(path, ".shp");
  GDALDriver* driver =
      GetGDALDriverManager()->GetDriverByName(shp ? "ESRI Shapefile" : "GPKG");
  if (!driver)
    return Status::error(StatusCode::IO_ERROR, std::string("GDAL has no ") +
                                                   (shp ? "Shapefile" : "GeoPackage") +
                                                   " driver");
  // A Shapefile is several files named after it: write it in place, no rename.
  const std::string target = shp ? path : tempPath(path, ".gpkg");
  VSIStatBufL st;
  if (shp && VSIStatL(path.c_str(), &st) == 0)
    driver->Delete(path.c_str()); // replace, as the other outputs do
  CPLErrorReset();
  DatasetPtr ds(driver->Create(target.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!ds)
    return ioError("cannot create '" + path + "'");
  auto fail = [&](Status s) {
    ds.reset();
    driver->Delete(target.c_str());
    return s;
  };
  std::unique_ptr<OGRSpatialReference> srs;
  if (!wkt.empty()) {
    srs = std::make_unique<OGRSpatialReference>();
    if (srs->SetFromUserInput(wkt.c_str()) != OGRERR_NONE)
      return fail(Status::error(StatusCode::INVALID_PARAMETER,
                                "not a CRS: " + wkt.substr(0, 80)));
    srs->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  }
  OGRLayer* layer = ds->CreateLayer("contours", srs.get(), wkbLineString, nullptr);
  if (!layer)
    return fail(ioError("cannot create the layer of '" + path + "'"));
  OGRFieldDefn elev("elev", OFTReal);
  OGRFieldDefn closed("closed", OFTInteger);
  if (layer->CreateField(&elev) != OGRERR_NONE ||
      layer->CreateField(&closed) != OGRERR_NONE)
    return fail(ioError("cannot create the fields of '" + path + "'"));
  const bool transactions = !shp && ds->StartTransaction() == OGRERR_NONE;
  Status s = trace([&](const ContourLine& line) {
    OGRFeature feature(layer->GetLayerDefn());
    feature.SetField("elev", line.level);
    feature.SetField("closed", line.closed ? 1 : 0);
    OGRLineString geometry;
    geometry.setNumPoints(static_cast<int>(line.points.size()), false);
    for (std::size_t i = 0; i < line.points.size(); ++i)
      geometry.setPoint(static_cast<int>(i), line.points[i].x, line.points[i].y);
    feature.SetGeometry(&geometry);
    if (layer->CreateFeature(&feature) != OGRERR_NONE)
      return ioError("cannot write a contour to '" + path + "'");
    return Status::success();
  });
  if (!s.ok())
    return fail(s);
  if (transactions && ds->CommitTransaction() != OGRERR_NONE)
    return fail(ioError("cannot write '" + path + "'"));
  CPLErrorReset();
  GDALClose(ds.release());
  if (CPLGetLastErrorType() == CE_Failure) {
    driver->Delete(target.c_str());
    return ioError("cannot write '" + path + "'");
  }
  if (!shp && std::rename(target.c_str(), path.c_str()) != 0) {
    const int err = errno;
    driver->Delete(target.c_str());
    return Status::error(StatusCode::IO_ERROR,
                         "cannot rename to '" + path + "': " + std::strerror(err));
  }
  return Status::success();
}

} // namespace

Status writeContourFile(const std::string& path, const TriangleMesh& mesh,
                        double interval, double base, const std::string& wkt,
                        ContourStats* stats)
{
  return writeContourLayer(path, wkt, [&](const ContourSink& sink) {
    return traceContours(mesh, interval, base, sink, stats);
  });
}

Status writeContourFile(const std::string& path, const MeshStream& mesh,
                        double interval, double base, const std::string& wkt,
                        const std::string& temp_folder, ContourStats* stats)
{
  return writeContourLayer(path, wkt, [&](const ContourSink& sink) {
    return traceContoursOutOfCore(mesh, interval, base, temp_folder, sink, stats);
  });
}

namespace {

/// The summary line of contours.
std::string contourSummary(const ContourStats& stats, const GisOutputOptions& options,
                           const std::string& wkt)
{
  char line[512];
  std::snprintf(line, sizeof line,
                "%zu contour lines (%zu closed) on %zu levels every %.6g%s",
                stats.lines, stats.closed, stats.levels, options.interval,
                wkt.empty() ? ", no CRS" : "");
  return line;
}

/// The summary line of a DEM, then its hillshade when asked for.
Status finishDem(const DemGrid& grid, const DemRasterStats& stats,
                 const std::string& wkt, const GisOutputOptions& options,
                 std::vector<std::string>& summary)
{
  char line[512];
  std::snprintf(
      line, sizeof line,
      "DEM %zu x %zu pixels of %.6g (%zu with a value), origin %.10g,%.10g%s%s",
      grid.cols, grid.rows, grid.resolution, stats.pixels_inside, grid.x0, grid.y1,
      options.overviews ? ", overviews" : "", wkt.empty() ? ", no CRS" : "");
  summary.emplace_back(line);
  if (!options.hillshade.empty()) {
    if (Status s = writeHillshade(options.dem, options.hillshade); !s.ok())
      return s;
    summary.emplace_back("hillshade of the DEM in " + options.hillshade);
  }
  return Status::success();
}

/// --dem-bounds when given, else `from_mesh`.
template <typename FromMesh>
Status gridFor(const GisOutputOptions& options, DemGrid& grid,
               const FromMesh& from_mesh)
{
  return options.bounds_given
             ? demGridForBounds(options.bounds[0], options.bounds[1], options.bounds[2],
                                options.bounds[3], options.resolution, grid)
             : from_mesh();
}

/// The DEM of a mesh that is not held, and its summary lines.
Status writeDemOutOfCore(const MeshStream& mesh, const std::string& wkt,
                         const GisOutputOptions& options, std::uint64_t memory,
                         const std::string& temp_folder,
                         std::vector<std::string>& summary)
{
  DemGrid grid;
  Status s = gridFor(options, grid, [&] {
    double low[2] = {HUGE_VAL, HUGE_VAL}, high[2] = {-HUGE_VAL, -HUGE_VAL};
    if (Status v = mesh.vertices([&](double x, double y, double) {
          low[0] = std::min(low[0], x);
          low[1] = std::min(low[1], y);
          high[0] = std::max(high[0], x);
          high[1] = std::max(high[1], y);
        });
        !v.ok())
      return v;
    if (!(low[0] <= high[0]))
      return Status::error(StatusCode::EMPTY_INPUT, "no triangle to rasterize");
    return demGridForExtent(low[0], low[1], high[0], high[1], options.resolution, grid);
  });
  if (!s.ok())
    return s;
  DemRasterStats stats;
  if (s = writeDemGeoTiff(options.dem, mesh, grid, wkt, options.overviews, memory,
                          temp_folder, &stats);
      !s.ok())
    return s;
  return finishDem(grid, stats, wkt, options, summary);
}

} // namespace

Status writeGisOutputs(const TriangleMesh& mesh, const std::string& wkt,
                       const GisOutputOptions& options,
                       std::vector<std::string>& summary)
{
  if (!options.dem.empty()) {
    DemGrid grid;
    Status s = gridFor(options, grid,
                       [&] { return demGridForMesh(mesh, options.resolution, grid); });
    if (!s.ok())
      return s;
    DemRasterStats stats;
    if (s = writeDemGeoTiff(options.dem, mesh, grid, wkt, options.overviews, &stats);
        !s.ok())
      return s;
    if (s = finishDem(grid, stats, wkt, options, summary); !s.ok())
      return s;
  }
  if (!options.contours.empty()) {
    TriangleMesh copy;
    const TriangleMesh* m = &mesh;
    if (mesh.halfedges.size() != mesh.triangles.size()) {
      copy = mesh;
      if (!copy.rebuildHalfedges())
        return Status::error(StatusCode::INTERNAL_ERROR,
                             "the mesh is not a manifold: no contours");
      m = &copy;
    }
    ContourStats stats;
    if (Status s = writeContourFile(options.contours, *m, options.interval,
                                    options.contour_base, wkt, &stats);
        !s.ok())
      return s;
    summary.push_back(contourSummary(stats, options, wkt));
  }
  return Status::success();
}

Status writeGisOutputsOutOfCore(const MeshStream& mesh, const std::string& wkt,
                                const GisOutputOptions& options, std::uint64_t memory,
                                const std::string& temp_folder,
                                std::vector<std::string>& summary)
{
  if (!options.dem.empty())
    if (Status s = writeDemOutOfCore(mesh, wkt, options, memory, temp_folder, summary);
        !s.ok())
      return s;
  if (!options.contours.empty()) {
    ContourStats stats;
    if (Status s = writeContourFile(options.contours, mesh, options.interval,
                                    options.contour_base, wkt, temp_folder, &stats);
        !s.ok())
      return s;
    summary.push_back(contourSummary(stats, options, wkt));
  }
  return Status::success();
}

} // namespace pcl_vts
