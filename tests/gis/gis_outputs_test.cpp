// The GDAL products read back with GDAL: the GeoTIFF's pixels, georeferencing,
// NODATA, tiling and CRS; the contour layer's features and CRS; the CRS helpers.
#include "gis_test_mesh.h"

#include <pcl_vts/gis/gis_outputs.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace pcl_vts {
namespace {

std::string tempDir()
{
  char tmpl[] = "/tmp/pcl_vts_gis_XXXXXX";
  const char* d = ::mkdtemp(tmpl);
  return d ? d : "/tmp";
}

std::string wktOf(const char* user)
{
  std::string wkt;
  EXPECT_TRUE(normalizeCrs(user, wkt).ok());
  return wkt;
}

TEST(GisOutputs, GeoTiffHoldsTheRasterGeoreferencingAndCrs)
{
  GDALAllRegister();
  auto f = [](double x, double y) { return 0.01 * x - 0.02 * y + 0.001 * x * y; };
  // 600 x 300 pixels: more than one 256-row block and tile.
  const TriangleMesh mesh = test::gridMesh(30, 15, 400000.3, 5100000.6, 10.0, 10.0, f);
  DemGrid grid;
  ASSERT_TRUE(demGridForMesh(mesh, 0.5, grid).ok());
  std::vector<float> expected(grid.cols * grid.rows);
  ASSERT_TRUE(rasterizeDem(mesh, grid, DEM_NODATA, 1000,
                           [&](std::size_t row0, std::size_t n, const float* v) {
                             std::copy(v, v + n * grid.cols,
                                       expected.begin() + row0 * grid.cols);
                             return Status::success();
                           })
                  .ok());
  const std::string dir = tempDir(), path = dir + "/dem.tif";
  const std::string wkt = wktOf("EPSG:32633");
  DemRasterStats stats;
  Status s = writeDemGeoTiff(path, mesh, grid, wkt, true, &stats);
  ASSERT_TRUE(s.ok()) << s.toString();
  GDALDataset* ds = static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly));
  ASSERT_NE(ds, nullptr);
  EXPECT_EQ(static_cast<std::size_t>(ds->GetRasterXSize()), grid.cols);
  EXPECT_EQ(static_cast<std::size_t>(ds->GetRasterYSize()), grid.rows);
  double gt[6];
  ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
  EXPECT_EQ(gt[0], grid.x0);
  EXPECT_EQ(gt[1], 0.5);
  EXPECT_EQ(gt[3], grid.y1);
  EXPECT_EQ(gt[5], -0.5);
  EXPECT_STREQ(ds->GetMetadataItem("AREA_OR_POINT"), "Area");
  const OGRSpatialReference* srs = ds->GetSpatialRef();
  ASSERT_NE(srs, nullptr);
  EXPECT_STREQ(srs->GetAuthorityCode(nullptr), "32633");
  EXPECT_TRUE(sameCrs(wkt, "EPSG:32633"));
  GDALRasterBand* band = ds->GetRasterBand(1);
  EXPECT_EQ(band->GetRasterDataType(), GDT_Float32);
  int has = 0;
  EXPECT_EQ(band->GetNoDataValue(&has), DEM_NODATA);
  EXPECT_TRUE(has);
  int bx = 0, by = 0;
  band->GetBlockSize(&bx, &by);
  EXPECT_EQ(bx, 256);
  EXPECT_EQ(by, 256);
  EXPECT_STREQ(ds->GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE"), "DEFLATE");
  EXPECT_GE(band->GetOverviewCount(), 1);
  std::vector<float> got(grid.cols * grid.rows);
  ASSERT_EQ(band->RasterIO(GF_Read, 0, 0, static_cast<int>(grid.cols),
                           static_cast<int>(grid.rows), got.data(),
                           static_cast<int>(grid.cols), static_cast<int>(grid.rows),
                           GDT_Float32, 0, 0),
            CE_None);
  EXPECT_EQ(got, expected);
  EXPECT_GT(stats.pixels_inside, grid.cols * grid.rows / 2);
  GDALClose(ds);
  std::remove(path.c_str());
  ::rmdir(dir.c_str());
}

TEST(GisOutputs, ContoursOnAPlaneAreStraightBoundaryToBoundaryAndUnique)
{
  // z = 0.5x + 0.25y on [0,10]x[0,8]; vertices land exactly on levels too.
  const double a = 0.5, b = 0.25;
  const TriangleMesh mesh = test::gridMesh(
      10, 8, 0.0, 0.0, 1.0, 1.0, [&](double x, double y) { return a * x + b * y; });
  std::vector<ContourLine> lines;
  ContourStats stats;
  ASSERT_TRUE(traceContours(
                  mesh, 0.5, 0.0,
                  [&](const ContourLine& l) {
                    lines.push_back(l);
                    return Status::success();
                  },
                  &stats)
                  .ok());
  // Levels L with zmin = 0 < L <= zmax = 7: 0.5 .. 6.5 one straight line each; 7.0
  // touches only the corner vertex (10, 8): a point, not a line.
  ASSERT_EQ(lines.size(), 13u);
  EXPECT_EQ(stats.levels, 14u);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const ContourLine& l = lines[i];
    EXPECT_EQ(l.level, 0.5 * static_cast<double>(i + 1));
    EXPECT_FALSE(l.closed);
    ASSERT_GE(l.points.size(), 2u);
    for (const Point2& p : l.points)
      EXPECT_NEAR(a * p.x + b * p.y, l.level, 1e-12) << "level " << l.level;
    auto onBoundary = [](const Point2& p) {
      return p.x == 0.0 || p.x == 10.0 || p.y == 0.0 || p.y == 8.0;
    };
    EXPECT_TRUE(onBoundary(l.points.front()));
    EXPECT_TRUE(onBoundary(l.points.back()));
    // Straight: every point on the line through the ends, and ordered along it.
    const Point2 p0 = l.points.front(), p1 = l.points.back();
    double last = -1.0;
    for (const Point2& p : l.points) {
      const double cross = (p1.x - p0.x) * (p.y - p0.y) - (p1.y - p0.y) * (p.x - p0.x);
      EXPECT_NEAR(cross, 0.0, 1e-9);
      const double along = (p.x - p0.x) * (p1.x - p0.x) + (p.y - p0.y) * (p1.y - p0.y);
      EXPECT_GT(along, last); // no point repeated, no back-tracking
      last = along;
    }
    // Higher ground on the left of the direction of travel.
    const double dx = p1.x - p0.x, dy = p1.y - p0.y;
    EXPECT_GT(a * -dy + b * dx, 0.0);
  }
}

TEST(GisOutputs, ContoursOfABowlAreClosedLoops)
{
  auto bowl = [](double x, double y) { return x * x + y * y; };
  const TriangleMesh mesh = test::gridMesh(20, 20, -5.05, -5.05, 0.5, 0.5, bowl);
  std::vector<ContourLine> lines;
  ASSERT_TRUE(traceContours(mesh, 2.0, 0.0, [&](const ContourLine& l) {
                lines.push_back(l);
                return Status::success();
              }).ok());
  std::size_t closed = 0;
  for (const ContourLine& l : lines) {
    if (l.level < 25.0) { // inside the square's inscribed circle: a loop
      EXPECT_TRUE(l.closed) << l.level;
      ++closed;
    }
    if (l.closed) {
      EXPECT_EQ(l.points.front().x, l.points.back().x);
      EXPECT_EQ(l.points.front().y, l.points.back().y);
    }
  }
  EXPECT_EQ(closed, 12u); // levels 2, 4, ..., 24
}

TEST(GisOutputs, ContourFileHasFeaturesElevationAndCrs)
{
  GDALAllRegister();
  const TriangleMesh mesh = test::gridMesh(10, 10, 600000, 200000, 5.0, 5.0,
                                           [](double x, double) { return x - 600000; });
  const std::string dir = tempDir();
  for (const char* name : {"/c.gpkg", "/c.shp"}) {
    const std::string path = dir + name;
    ContourStats stats;
    Status s = writeContourFile(path, mesh, 10.0, 0.0, wktOf("EPSG:2056"), &stats);
    ASSERT_TRUE(s.ok()) << s.toString();
    GDALDataset* ds = static_cast<GDALDataset*>(
        GDALOpenEx(path.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr));
    ASSERT_NE(ds, nullptr) << path;
    OGRLayer* layer = ds->GetLayer(0);
    ASSERT_NE(layer, nullptr);
    EXPECT_EQ(layer->GetFeatureCount(), 5); // x = 10, 20, 30, 40, 50
    ASSERT_NE(layer->GetSpatialRef(), nullptr);
    EXPECT_STREQ(layer->GetSpatialRef()->GetAuthorityCode(nullptr), "2056") << path;
    std::vector<double> levels;
    layer->ResetReading();
    while (OGRFeature* feat = layer->GetNextFeature()) {
      levels.push_back(feat->GetFieldAsDouble("elev"));
      const OGRLineString* ls = feat->GetGeometryRef()->toLineString();
      for (int i = 0; i < ls->getNumPoints(); ++i)
        EXPECT_EQ(ls->getX(i) - 600000, levels.back());
      OGRFeature::DestroyFeature(feat);
    }
    EXPECT_EQ(levels, (std::vector<double>{10, 20, 30, 40, 50}));
    GDALClose(ds);
  }
  std::system(("rm -rf " + dir).c_str());
}

TEST(GisCrs, NormalizeCompareCommonAndPrj)
{
  std::string wkt;
  EXPECT_TRUE(normalizeCrs("EPSG:2056", wkt).ok());
  EXPECT_NE(wkt.find("CH1903+"), std::string::npos);
  EXPECT_FALSE(normalizeCrs("EPSG:99999999", wkt).ok());
  EXPECT_FALSE(normalizeCrs("not a crs", wkt).ok());
  EXPECT_TRUE(sameCrs(wktOf("EPSG:32633"), "EPSG:32633"));
  EXPECT_FALSE(sameCrs("EPSG:32633", "EPSG:32632"));
  std::string crs;
  ASSERT_TRUE(
      commonCrs(
          {{"a.las", "EPSG:32633"}, {"b.las", ""}, {"c.las", wktOf("EPSG:32633")}}, crs)
          .ok());
  EXPECT_EQ(crs, "EPSG:32633");
  Status s =
      commonCrs({{"a.las", "EPSG:32633"}, {"b.las", ""}, {"c.las", "EPSG:25833"}}, crs);
  EXPECT_EQ(s.code, StatusCode::INVALID_PARAMETER);
  EXPECT_NE(s.message.find("'a.las'"), std::string::npos);
  EXPECT_NE(s.message.find("'c.las'"), std::string::npos);
  ASSERT_TRUE(commonCrs({{"a", ""}}, crs).ok());
  EXPECT_TRUE(crs.empty());

  const std::string dir = tempDir();
  ASSERT_TRUE(writePrjSidecar(dir + "/mesh.ply", wktOf("EPSG:32633")).ok());
  std::ifstream f(dir + "/mesh.prj");
  std::stringstream text;
  text << f.rdbuf();
  EXPECT_NE(text.str().find("WGS_1984_UTM_Zone_33N"), std::string::npos) << text.str();
  EXPECT_TRUE(sameCrs(text.str(), "EPSG:32633"));
  std::system(("rm -rf " + dir).c_str());
}

TEST(GisOptions, ValidateChecksTheCombination)
{
  GisOutputOptions o;
  o.dem = "out.tif";
  EXPECT_FALSE(validateGisOptions(o).ok()); // no resolution
  o.resolution = 0.5;
  EXPECT_TRUE(validateGisOptions(o).ok());
  o.bounds_given = true;
  const double whole[4] = {0, 0, 10, 5};
  std::copy(whole, whole + 4, o.bounds);
  EXPECT_TRUE(validateGisOptions(o).ok());
  o.bounds[2] = 10.2;
  EXPECT_FALSE(validateGisOptions(o).ok()); // not whole pixels
  GisOutputOptions c;
  c.contours = "x.kml";
  c.interval = 1.0;
  EXPECT_FALSE(validateGisOptions(c).ok()); // extension
  c.contours = "x.gpkg";
  EXPECT_TRUE(validateGisOptions(c).ok());
  c.crs = "EPSG:0";
  EXPECT_FALSE(validateGisOptions(c).ok());
  // The library's words name the settings, never a tool's flags.
  GisOutputOptions d;
  d.dem = "out.tif";
  Status s = validateGisOptions(d);
  EXPECT_NE(s.message.find("a DEM needs a resolution > 0"), std::string::npos)
      << s.message;
  d.dem.clear();
  d.interval = 1.0;
  s = validateGisOptions(d);
  EXPECT_NE(s.message.find("no contour path"), std::string::npos) << s.message;
  for (const Status& t : {s, validateGisOptions(o), validateGisOptions(c)})
    EXPECT_EQ(t.message.find("--"), std::string::npos) << t.message;
}

} // namespace
} // namespace pcl_vts
