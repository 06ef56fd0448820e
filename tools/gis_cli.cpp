// See gis_cli.h. The GDAL half compiles only with PCL_VTS_HAVE_GIS (pcl_vts::gis).
#include "cli_words.h"
#include "command_line.h"
#include "gis_cli.h"

#ifdef PCL_VTS_HAVE_GIS
#include <pcl_vts/gis/gis_outputs.h>
#include <pcl_vts/io/file_crs.h>
#include <pcl_vts/io/point_cloud_loader.h>

#include <gdal.h>
#include <ogr_spatialref.h>
#endif

#include <algorithm>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace pcl_vts::tools {

void GisCli::describe(CommandLine& cli)
{
  const auto set = [this](const char* name) {
    return [this, name](const std::string& value, std::string& error) {
      return parse(std::string("--") + name, value, error);
    };
  };
  cli.group("GIS outputs, after the mesh in its CRS ("
#ifdef PCL_VTS_HAVE_GIS
            "available in this build"
#else
            "NOT available: built without GDAL"
#endif
            ")")
      .value("dem", "FILE.tif",
             "DEM of the final mesh: Float32 GeoTIFF, 256x256 tiles, DEFLATE, NODATA "
             "-9999 outside the mesh; each pixel centre gets the linear interpolation "
             "in the triangle holding it",
             set("dem"))
      .value("resolution", "R",
             "DEM pixel edge in XY units (needed by --dem); pixel-is-area, edges on "
             "multiples of R, so centres at k*R + R/2",
             set("resolution"))
      .value("dem-bounds", "X0,Y0,X1,Y1",
             "DEM extent instead (a whole number of pixels), e.g. a tile of a tiling "
             "scheme",
             set("dem-bounds"))
      .flag("dem-overviews", "also build internal overviews (2x, 4x, ... averages)",
            [this] {
              std::string error;
              parse("--dem-overviews", "", error);
            })
      .value("hillshade", "FILE.png", "a multidirectional hillshade of the DEM (GDAL)",
             set("hillshade"))
      .value("contours", "FILE",
             "contour lines: .gpkg (GeoPackage) or .shp (Shapefile), one LineString "
             "per line, fields elev and closed",
             set("contours"))
      .value("interval", "I", "contour step (needed by --contours); levels k*I + base",
             set("interval"))
      .value("contour-base", "B", "base of the contour levels (default: 0)",
             set("contour-base"))
      .value("crs", "CRS",
             "coordinate system of the input, EPSG:XXXX or WKT; sets or overrides what "
             "the input says (LAS WKT/GeoTIFF keys, GeoTIFF, a .prj beside the input). "
             "Meshes get a .prj sidecar and, in PLY, a comment line",
             set("crs"));
}

#ifdef PCL_VTS_HAVE_GIS
struct GisCli::Impl {
  GisOutputOptions options;
};
#else
struct GisCli::Impl {
  std::string first; ///< first GIS option given: refused by validate()
};
#endif

GisCli::GisCli()
    : impl_(new Impl)
{}
GisCli::~GisCli()
{
  delete impl_;
}
GisCli::GisCli(const GisCli& o)
    : impl_(new Impl(*o.impl_))
    , crs_(o.crs_)
{}
GisCli& GisCli::operator=(const GisCli& o)
{
  *impl_ = *o.impl_;
  crs_ = o.crs_;
  return *this;
}

#ifdef PCL_VTS_HAVE_GIS

bool GisCli::parse(const std::string& name, const std::string& value,
                   std::string& error)
{
  GisOutputOptions& o = impl_->options;
  if (name == "--dem")
    o.dem = value;
  else if (name == "--hillshade")
    o.hillshade = value;
  else if (name == "--contours")
    o.contours = value;
  else if (name == "--crs")
    o.crs = value;
  else if (name == "--dem-overviews")
    o.overviews = true;
  else if (name == "--resolution" || name == "--interval") {
    double v = 0.0;
    if (!parseFiniteNumber(value, v) || !(v > 0.0)) {
      error = name + ": '" + value + "' is not a positive number";
      return false;
    }
    (name == "--resolution" ? o.resolution : o.interval) = v;
  } else if (name == "--contour-base") {
    if (!parseFiniteNumber(value, o.contour_base)) {
      error = name + ": '" + value + "' is not a number";
      return false;
    }
  } else if (name == "--dem-bounds") {
    std::vector<double> n;
    if (!parseNumberList(value, 4, n)) {
      error = "--dem-bounds: '" + value + "' is not X0,Y0,X1,Y1";
      return false;
    }
    std::copy(n.begin(), n.end(), o.bounds);
    o.bounds_given = true;
  } else {
    error = "internal: '" + name + "' is not a GIS option";
    return false;
  }
  return true;
}

bool GisCli::anyProduct() const
{
  return impl_->options.any();
}

Status GisCli::validate() const
{
  const GisOutputOptions& o = impl_->options;
  const auto usage = [](std::string message) {
    return Status::error(StatusCode::INVALID_PARAMETER, std::move(message));
  };
  // Which flags need which: the tool's rules, in its words (the library checks the
  // same pairs in the fields' words).
  if (!o.dem.empty() && !(o.resolution > 0.0))
    return usage("--dem needs --resolution R (pixel edge in input units)");
  if (o.dem.empty() &&
      (o.resolution > 0.0 || o.bounds_given || o.overviews || !o.hillshade.empty()))
    return usage(
        "--resolution, --dem-bounds, --dem-overviews and --hillshade need --dem");
  if (!o.contours.empty() && !(o.interval > 0.0))
    return usage("--contours needs --interval I (elevation step)");
  if (o.contours.empty() && o.interval > 0.0)
    return usage("--interval needs --contours");
  // Each value by the library, the flags added one at a time: the first step that
  // fails names its flag in front of the library's words.
  const std::pair<const char*, std::function<void(GisOutputOptions&)>> steps[] = {
      {"--dem",
       [&o](GisOutputOptions& c) {
         c.dem = o.dem;
         c.resolution = o.resolution;
         c.overviews = o.overviews;
       }},
      {"--dem-bounds",
       [&o](GisOutputOptions& c) {
         c.bounds_given = o.bounds_given;
         std::copy(o.bounds, o.bounds + 4, c.bounds);
       }},
      {"--hillshade", [&o](GisOutputOptions& c) { c.hillshade = o.hillshade; }},
      {"--contours",
       [&o](GisOutputOptions& c) {
         c.contours = o.contours;
         c.interval = o.interval;
         c.contour_base = o.contour_base;
       }},
      {"--crs", [&o](GisOutputOptions& c) { c.crs = o.crs; }},
  };
  GisOutputOptions checked;
  for (const auto& [flag, set] : steps) {
    set(checked);
    if (Status s = validateGisOptions(checked); !s.ok())
      return usage(std::string(flag) + ": " + s.message);
  }
  return Status::success();
}

namespace {

/// What path declares: LAS records, a GeoTIFF's projection, else a .prj beside it.
std::string declaredCrs(const std::string& path)
{
  std::string crs, source;
  CloudFileFormat format = CloudFileFormat::PCD;
  if (!cloudFileFormatFromExtension(path, format))
    format = CloudFileFormat::PCD;
  if (format == CloudFileFormat::LAS && !readLasCrs(path, crs, source).ok())
    crs.clear();
  if (format == CloudFileFormat::GEOTIFF) {
    GDALAllRegister();
    if (GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly)) {
      if (const char* wkt = GDALGetProjectionRef(ds))
        crs = wkt;
      GDALClose(ds);
    }
  }
  if (crs.empty() && !readPrjSidecar(path, crs, source).ok())
    crs.clear();
  return crs;
}

} // namespace

Status GisCli::resolveCrs(const std::vector<std::string>& files,
                          std::vector<std::string>& notes)
{
  crs_.clear();
  if (!impl_->options.crs.empty()) // --crs wins over the files
    return normalizeCrs(impl_->options.crs, crs_);
  std::vector<std::pair<std::string, std::string>> declared;
  for (const std::string& file : files) {
    std::string wkt;
    const std::string text = declaredCrs(file);
    if (text.empty())
      continue;
    if (Status s = normalizeCrs(text, wkt); !s.ok()) {
      notes.push_back("'" + file +
                      "': its coordinate system is not understood, ignored (" +
                      s.message + ")");
      continue;
    }
    declared.emplace_back(file, wkt);
  }
  Status s = commonCrs(declared, crs_);
  if (!s.ok()) // "... or set the one to use": the tool's way to set it
    s.message += " with --crs";
  return s;
}

std::string GisCli::crsName() const
{
  if (crs_.empty())
    return {};
  OGRSpatialReference srs;
  if (srs.SetFromUserInput(crs_.c_str()) != OGRERR_NONE)
    return {};
  const char* name = srs.GetName();
  const char* auth = srs.GetAuthorityName(nullptr);
  const char* code = srs.GetAuthorityCode(nullptr);
  std::string out = name ? name : "unnamed CRS";
  if (auth && code)
    out += std::string(" (") + auth + ":" + code + ")";
  return out;
}

Status GisCli::write(const TriangleMesh& mesh, const std::string& mesh_path,
                     std::vector<std::string>& summary) const
{
  if (!crs_.empty()) {
    if (Status s = writePrjSidecar(mesh_path, crs_); !s.ok())
      return s;
  }
  return writeGisOutputs(mesh, crs_, impl_->options, summary);
}

Status GisCli::writePrj(const std::string& mesh_path) const
{
  return crs_.empty() ? Status::success() : writePrjSidecar(mesh_path, crs_);
}

Status GisCli::writeOutOfCore(const MeshSource& mesh, std::uint64_t memory,
                              const std::string& temp_folder,
                              std::vector<std::string>& summary) const
{
  MeshStream stream;
  stream.vertices = [&](const std::function<void(double, double, double)>& visit) {
    return mesh.forEachVertex(
        [&](double x, double y, double z, bool) { visit(x, y, z); });
  };
  stream.triangles =
      [&](const std::function<void(VertexId, VertexId, VertexId)>& visit) {
        return mesh.forEachTriangle(visit);
      };
  return writeGisOutputsOutOfCore(stream, crs_, impl_->options, memory, temp_folder,
                                  summary);
}

#else

bool GisCli::parse(const std::string& name, const std::string&, std::string&)
{
  if (impl_->first.empty())
    impl_->first = name;
  return true;
}

bool GisCli::anyProduct() const
{
  return false;
}

Status GisCli::validate() const
{
  if (impl_->first.empty())
    return Status::success();
  return Status::error(StatusCode::INVALID_PARAMETER,
                       impl_->first +
                           " needs GDAL: this pcd_to_mesh was built without it "
                           "(Debian: libgdal-dev, then rebuild)");
}

Status GisCli::resolveCrs(const std::vector<std::string>&, std::vector<std::string>&)
{
  return Status::success();
}

std::string GisCli::crsName() const
{
  return {};
}

Status GisCli::write(const TriangleMesh&, const std::string&,
                     std::vector<std::string>&) const
{
  return Status::success();
}

Status GisCli::writeOutOfCore(const MeshSource&, std::uint64_t, const std::string&,
                              std::vector<std::string>&) const
{
  return Status::success();
}

Status GisCli::writePrj(const std::string&) const
{
  return Status::success();
}

#endif

} // namespace pcl_vts::tools
