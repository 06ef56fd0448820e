// CRS round trips: what a file declares (LAS WKT record, LAS GeoTIFF keys, a .prj
// sidecar) is what the loader reports and what pcd_to_mesh writes into the DEM,
// the contours and the mesh's .prj; --crs overrides it; inputs that disagree fail.
#include "contour_features.h"
#include "support/temp_folder_test.h"

#include <pcl_vts/gis/gis_outputs.h>
#include <pcl_vts/io/file_crs.h>
#include <pcl_vts/io/point_cloud_loader.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>
#include <sstream>
#include <sys/wait.h>

#ifndef PCL_VTS_PCD_TO_MESH // a build without the tools: the CLI round trips skip
#define PCL_VTS_PCD_TO_MESH ""
#endif

namespace pcl_vts {
namespace {

void put(std::string& b, std::size_t at, std::uint64_t v, int bytes)
{
  for (int k = 0; k < bytes; ++k)
    b[at + k] = static_cast<char>((v >> (8 * k)) & 0xFF);
}

struct Vlr {
  std::string user;
  std::uint16_t id;
  std::string body;
};

/// LAS 1.2, point format 0, a 6x6 grid of points z = x + y, the given VLRs.
/// A LAS 1.2 file (1 cm, offset 0) with these VLRs: a 6 x 6 grid of points 1 m apart,
/// or the given points.
std::string makeLas(const std::vector<Vlr>& vlrs,
                    const std::vector<std::array<double, 3>>& points = {})
{
  std::string b(227, '\0');
  std::memcpy(&b[0], "LASF", 4);
  b[24] = 1;
  b[25] = 2;
  put(b, 94, 227, 2);
  put(b, 100, vlrs.size(), 4);
  for (const Vlr& v : vlrs) {
    std::string h(54, '\0');
    std::memcpy(&h[2], v.user.data(), v.user.size());
    put(h, 18, v.id, 2);
    put(h, 20, v.body.size(), 2);
    b += h + v.body;
  }
  put(b, 96, b.size(), 4);
  b[104] = 0;
  put(b, 105, 20, 2);
  put(b, 107, points.empty() ? 36 : points.size(), 4);
  const double scale = 0.01, offset = 0.0;
  for (int a = 0; a < 3; ++a) {
    std::uint64_t u;
    std::memcpy(&u, &scale, 8);
    put(b, 131 + 8 * a, u, 8);
    std::memcpy(&u, &offset, 8);
    put(b, 155 + 8 * a, u, 8);
  }
  const auto record = [&](double x, double y, double z) {
    std::string r(20, '\0');
    put(r, 0, static_cast<std::uint32_t>(std::llround(100 * x)), 4);
    put(r, 4, static_cast<std::uint32_t>(std::llround(100 * y)), 4);
    put(r, 8, static_cast<std::uint32_t>(std::llround(100 * z)), 4);
    r[14] = 0x09; // return 1 of 1
    r[15] = 2;
    b += r;
  };
  if (!points.empty())
    for (const auto& p : points)
      record(p[0], p[1], p[2]);
  else
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i)
        record(i, j, i + j);
  return b;
}

std::string wktOf(const char* user)
{
  std::string wkt;
  EXPECT_TRUE(normalizeCrs(user, wkt).ok());
  return wkt;
}

std::string readText(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class CrsRoundTrip : public test::TempFolderTest {
 protected:
  std::string root() const { return root_.string(); }

  /// Runs pcd_to_mesh in the temp folder; returns its exit code, stderr in err.
  int run(const std::string& args, std::string* err = nullptr) const
  {
    if (std::string(PCL_VTS_PCD_TO_MESH).empty())
      return -2;
    const std::string log = root() + "/err.txt";
    const std::string cmd = "cd '" + root() +
                            "' && timeout 120 '" PCL_VTS_PCD_TO_MESH "' " + args +
                            " > /dev/null 2> '" + log + "'";
    const int status = std::system(cmd.c_str());
    if (err)
      *err = readText(log);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  /// The CRS of a raster or vector file, read back with GDAL; empty when none.
  static std::string crsOfFile(const std::string& path)
  {
    GDALAllRegister();
    GDALDataset* ds = static_cast<GDALDataset*>(GDALOpenEx(
        path.c_str(), GDAL_OF_RASTER | GDAL_OF_VECTOR, nullptr, nullptr, nullptr));
    if (!ds)
      return "(cannot open)";
    const OGRSpatialReference* srs = ds->GetRasterCount() > 0
                                         ? ds->GetSpatialRef()
                                         : ds->GetLayer(0)->GetSpatialRef();
    std::string out;
    if (srs) {
      char* w = nullptr;
      srs->exportToWkt(&w);
      out = w ? w : "";
      CPLFree(w);
    }
    GDALClose(ds);
    return out;
  }
};

TEST_F(CrsRoundTrip, LasWktRecordReachesTheDemTheContoursAndThePrj)
{
  const std::string wkt = wktOf("EPSG:32633");
  const std::string las =
      write("in.las", makeLas({{"LASF_Projection", 2112, wkt + std::string(1, '\0')}}));
  std::string crs, source;
  ASSERT_TRUE(readLasCrs(las, crs, source).ok());
  EXPECT_EQ(crs, wkt);
  EXPECT_EQ(source, "LAS OGC WKT record");
  std::vector<double> xyz;
  CloudDescription d;
  ASSERT_TRUE(loadPointCloud(las, {}, xyz, d).ok());
  EXPECT_EQ(d.crs, wkt);

  std::string err;
  ASSERT_EQ(run("in.las out.ply --dem dem.tif --resolution 0.5 --contours c.gpkg "
                "--interval 1",
                &err),
            0)
      << err;
  EXPECT_TRUE(sameCrs(crsOfFile(root() + "/dem.tif"), "EPSG:32633"));
  EXPECT_TRUE(sameCrs(crsOfFile(root() + "/c.gpkg"), "EPSG:32633"));
  EXPECT_TRUE(sameCrs(readText(root() + "/out.prj"), "EPSG:32633"));
  EXPECT_NE(
      readText(root() + "/out.ply").find("crs: WGS 84 / UTM zone 33N (EPSG:32633)"),
      std::string::npos);
  // The DEM read back as input (GeoTIFF through GDAL) keeps its CRS to the mesh.
  ASSERT_EQ(run("dem.tif back.ply", &err), 0) << err;
  EXPECT_TRUE(sameCrs(readText(root() + "/back.prj"), "EPSG:32633"));
}

/// Band 1 of a raster as floats (empty when it cannot be read).
std::vector<float> rasterValues(const std::string& path, int& cols, int& rows)
{
  GDALAllRegister();
  GDALDataset* ds = static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly));
  if (!ds)
    return {};
  cols = ds->GetRasterXSize();
  rows = ds->GetRasterYSize();
  std::vector<float> v(static_cast<std::size_t>(cols) * static_cast<std::size_t>(rows));
  if (ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, cols, rows, v.data(), cols, rows,
                                     GDT_Float32, 0, 0) != CE_None)
    v.clear();
  GDALClose(ds);
  return v;
}

/// 20000 points of a terrain with a hill and a round void, in UTM.
std::vector<std::array<double, 3>> terrainWithVoid()
{
  std::vector<std::array<double, 3>> points;
  std::uint64_t state = 7;
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  while (points.size() < 20000) {
    const double x = 200.0 * next(), y = 150.0 * next();
    if ((x - 120) * (x - 120) + (y - 60) * (y - 60) < 900)
      continue; // a round void
    points.push_back(
        {500000.0 + x, 4100000.0 + y,
         300.0 + 0.1 * x + 5 * std::sin(y / 9) +
             4 * std::exp(-((x - 50) * (x - 50) + (y - 100) * (y - 100)) / 200)});
  }
  return points;
}

TEST_F(CrsRoundTrip, TiledRunWritesTheInMemoryDem)
{
  // The terrain meshed in memory and in 16 tiles: the DEM of the tiled run
  // (rasterized out of core from the tile results, in windows of 32 pixels under a
  // small limit) equals the in-memory one pixel for pixel, CRS too.
  const std::string wkt = wktOf("EPSG:32633");
  write("t.las", makeLas({{"LASF_Projection", 2112, wkt + std::string(1, '\0')}},
                         terrainWithVoid()));
  std::string err;
  ASSERT_EQ(
      run("t.las memory.ply --no-trim --no-fill --dem memory.tif --resolution 0.7",
          &err),
      0)
      << err;
  ASSERT_EQ(run("t.las tiled.ply --no-trim --no-fill --dem tiled.tif --resolution 0.7 "
                "--tile-level 2 --memory-limit 16M --temp-dir . --hillshade tiled.png",
                &err),
            0)
      << err;
  int c1 = 0, r1 = 0, c2 = 0, r2 = 0;
  const std::vector<float> memory = rasterValues(root() + "/memory.tif", c1, r1);
  const std::vector<float> tiled = rasterValues(root() + "/tiled.tif", c2, r2);
  ASSERT_FALSE(memory.empty());
  EXPECT_EQ(c1, c2);
  EXPECT_EQ(r1, r2);
  EXPECT_TRUE(memory == tiled);
  EXPECT_GT(std::count(memory.begin(), memory.end(), DEM_NODATA), 1000); // the void
  EXPECT_TRUE(sameCrs(crsOfFile(root() + "/tiled.tif"), "EPSG:32633"));
  EXPECT_TRUE(sameCrs(readText(root() + "/tiled.prj"), "EPSG:32633"));
  EXPECT_FALSE(readText(root() + "/tiled.png").empty());
}

TEST_F(CrsRoundTrip, TiledRunWritesTheInMemoryContours)
{
  // The terrain meshed, trimmed and filled (the void is a hole the fill leaves, its
  // rim an inner boundary) in memory and in 4, 16 and 64 tiles: the contours of
  // the tiled runs (traced out of core from the tile results) are the in-memory
  // features, in the same order, CRS too; with and without the post-passes.
  const std::string wkt = wktOf("EPSG:32633");
  write("t.las", makeLas({{"LASF_Projection", 2112, wkt + std::string(1, '\0')}},
                         terrainWithVoid()));
  for (const char* post : {"", " --no-trim --no-fill"}) {
    SCOPED_TRACE(post);
    std::string err;
    ASSERT_EQ(
        run(std::string("t.las memory.ply --contours memory.gpkg --interval 0.5") +
                post,
            &err),
        0)
        << err;
    const auto expected = test::contourFeatures(root() + "/memory.gpkg");
    EXPECT_GT(expected.size(), 30u);
    EXPECT_TRUE(
        std::any_of(expected.begin(), expected.end(),
                    [](const test::ContourFeature& f) { return std::get<1>(f); }));
    for (const char* level : {"1", "2", "3"}) {
      if (*post && *level != '2')
        continue; // without the post-passes: one tiling
      SCOPED_TRACE(level);
      ASSERT_EQ(run(std::string("t.las tiled.ply --contours tiled.gpkg --interval 0.5 "
                                "--memory-limit 16M --temp-dir . --tile-level ") +
                        level + post,
                    &err),
                0)
          << err;
      EXPECT_EQ(readText(root() + "/memory.ply"), readText(root() + "/tiled.ply"));
      EXPECT_TRUE(test::contourFeatures(root() + "/tiled.gpkg") == expected);
      EXPECT_TRUE(sameCrs(crsOfFile(root() + "/tiled.gpkg"), "EPSG:32633"));
    }
  }
  // A product that fails after the tiled mesh is written: the error, no contour file,
  // no temporary file.
  std::string err;
  EXPECT_EQ(run("t.las bad.ply --contours bad.gpkg --interval 1e-14 --tile-level 1 "
                "--temp-dir .",
                &err),
            1);
  EXPECT_NE(err.find("contour interval 1e-14 is too small"), std::string::npos) << err;
  EXPECT_EQ(readText(root() + "/bad.gpkg"), "");
  // The same failure in memory: the same exit code and message.
  err.clear();
  EXPECT_EQ(run("t.las bad.ply --contours bad.gpkg --interval 1e-14", &err), 1);
  EXPECT_NE(err.find("contour interval 1e-14 is too small"), std::string::npos) << err;
  EXPECT_EQ(readText(root() + "/bad.gpkg"), "");
  for (const auto& entry : std::filesystem::directory_iterator(root()))
    EXPECT_NE(entry.path().filename().string()[0], '.') << entry.path();
}

TEST_F(CrsRoundTrip, LasGeoKeysGiveTheEpsgCode)
{
  // GeoKeyDirectory: version 1.1.0, 3 keys; 1024 model type, 3072 projected CS.
  std::string keys(8 * 4, '\0');
  const std::uint16_t v[] = {1,    1, 0, 3,    1024, 0, 1, 1,
                             3072, 0, 1, 2056, 3076, 0, 1, 9001};
  for (int i = 0; i < 16; ++i)
    put(keys, 2 * i, v[i], 2);
  const std::string las =
      write("keys.las", makeLas({{"LASF_Projection", 34735, keys}}));
  std::string crs, source;
  ASSERT_TRUE(readLasCrs(las, crs, source).ok());
  EXPECT_EQ(crs, "EPSG:2056");
  EXPECT_EQ(source, "LAS GeoTIFF keys");
  // No record at all: no CRS. A record longer than the file: ignored, not trusted.
  ASSERT_TRUE(readLasCrs(write("none.las", makeLas({})), crs, source).ok());
  EXPECT_TRUE(crs.empty());
  std::string bad = makeLas({{"LASF_Projection", 2112, "GEOGCS"}});
  put(bad, 227 + 20, 60000, 2);
  ASSERT_TRUE(readLasCrs(write("bad.las", bad), crs, source).ok());
  EXPECT_TRUE(crs.empty());
}

TEST_F(CrsRoundTrip, PrjSidecarOverrideAndConflict)
{
  std::string xyz;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i)
      xyz += std::to_string(i) + " " + std::to_string(j) + " " + std::to_string(i * j) +
             "\n";
  write("a.xyz", xyz);
  write("b.xyz", xyz);
  write("a.prj", wktOf("EPSG:25832"));
  std::vector<double> pts;
  CloudDescription d;
  ASSERT_TRUE(loadPointCloud(root() + "/a.xyz", {}, pts, d).ok());
  EXPECT_TRUE(sameCrs(d.crs, "EPSG:25832"));
  EXPECT_EQ(d.crs_source, "'" + root() + "/a.prj'");

  std::string err;
  ASSERT_EQ(run("a.xyz m.obj --dem d.tif --resolution 1", &err), 0) << err;
  EXPECT_TRUE(sameCrs(crsOfFile(root() + "/d.tif"), "EPSG:25832"));
  EXPECT_TRUE(sameCrs(readText(root() + "/m.prj"), "EPSG:25832"));
  // --crs wins over the sidecar.
  ASSERT_EQ(run("a.xyz m2.vtk --dem d2.tif --resolution 1 --crs EPSG:2056", &err), 0)
      << err;
  EXPECT_TRUE(sameCrs(crsOfFile(root() + "/d2.tif"), "EPSG:2056"));
  EXPECT_TRUE(sameCrs(readText(root() + "/m2.prj"), "EPSG:2056"));
  // No CRS anywhere: no .prj, a DEM without one.
  ASSERT_EQ(run("b.xyz m3.ply --dem d3.tif --resolution 1", &err), 0) << err;
  EXPECT_EQ(crsOfFile(root() + "/d3.tif"), "");
  EXPECT_EQ(readText(root() + "/m3.prj"), "");
  // b.xyz has none, a.xyz has one: one CRS. Then b gets a different one: an error
  // naming both files (exit 2), unless --crs settles it.
  ASSERT_EQ(run("a.xyz b.xyz m4.ply", &err), 0) << err;
  write("b.prj", wktOf("EPSG:4326"));
  EXPECT_EQ(run("a.xyz b.xyz m5.ply", &err), 2);
  EXPECT_NE(err.find("a.xyz"), std::string::npos) << err;
  EXPECT_NE(err.find("b.xyz"), std::string::npos) << err;
  EXPECT_NE(err.find("different coordinate systems"), std::string::npos) << err;
  EXPECT_NE(err.find("set the one to use with --crs"), std::string::npos) << err;
  EXPECT_EQ(run("a.xyz b.xyz m6.ply --crs EPSG:25832", &err), 0) << err;
  // A file's CRS GDAL cannot parse (PDAL's warsaw_small.las has a WKT of "''") is
  // ignored with a note, not an error; the tiled run writes the .prj too.
  write("c.xyz", xyz);
  write("c.prj", "''");
  ASSERT_EQ(run("c.xyz m8.ply", &err), 0) << err;
  EXPECT_EQ(readText(root() + "/m8.prj"), "");
  ASSERT_EQ(run("a.xyz m9.ply --no-trim --no-fill --tile-level 1", &err), 0) << err;
  EXPECT_TRUE(sameCrs(readText(root() + "/m9.prj"), "EPSG:25832"));
  // A --crs GDAL does not know is a usage error.
  EXPECT_EQ(run("a.xyz m7.ply --crs EPSG:1", &err), 1);
  EXPECT_NE(err.find("--crs"), std::string::npos) << err;
}

TEST_F(CrsRoundTrip, BadGisOptionValuesAreUsageErrorsNamingTheOption)
{
  std::string xyz;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      xyz += std::to_string(i) + " " + std::to_string(j) + " 1\n";
  write("a.xyz", xyz);
  const char* const bad[][2] = {
      {"--resolution -1", "--resolution: '-1' is not a positive number"},
      {"--resolution 1e999", "--resolution: '1e999' is not a positive number"},
      {"--interval x", "--interval: 'x' is not a positive number"},
      {"--contour-base 2m", "--contour-base: '2m' is not a number"},
      {"--dem-bounds 1,2,3", "--dem-bounds: '1,2,3' is not X0,Y0,X1,Y1"},
      {"--dem-bounds 1,2,3,4,5", "--dem-bounds: '1,2,3,4,5' is not X0,Y0,X1,Y1"},
      {"--dem-bounds 0,0,10.2,5 --dem d.tif --resolution 1",
       "--dem-bounds: DEM bounds are not a whole number"},
      // The combinations: the tool's flags in front of or in place of the library's
      // words (tools/gis_cli.cpp).
      {"--dem d.tif", "--dem needs --resolution R"},
      {"--hillshade h.png", "--resolution, --dem-bounds, --dem-overviews and "
                            "--hillshade need --dem"},
      {"--contours c.gpkg", "--contours needs --interval I"},
      {"--interval 2", "--interval needs --contours"},
      {"--dem d.jpg --resolution 1",
       "--dem: the DEM path 'd.jpg' does not end in .tif"},
      {"--dem d.tif --resolution 1 --hillshade h.jpg",
       "--hillshade: the hillshade path"},
      {"--contours c.kml --interval 1", "--contours: the contour path 'c.kml'"},
      {"--crs EPSG:1", "--crs: 'EPSG:1' is not a coordinate system"},
  };
  for (const auto& c : bad) {
    SCOPED_TRACE(c[0]);
    std::string err;
    EXPECT_EQ(run(std::string("a.xyz m.ply ") + c[0], &err), 1);
    EXPECT_NE(err.find(c[1]), std::string::npos) << err;
  }
  std::string err;
  ASSERT_EQ(run("a.xyz m.ply --dem d.tif --resolution 1 --dem-bounds -1,0,2,3 "
                "--contour-base -0.5",
                &err),
            0)
      << err;
  EXPECT_TRUE(std::ifstream(root() + "/d.tif").good()) << "the DEM of the given bounds";
}

TEST_F(CrsRoundTrip, RealLasFilesDeclareTheirCrs)
{
  // Publishers' files (PDAL's test data): a WKT record, GeoTIFF keys, none.
  const std::string dir = PCL_VTS_SHARED_DATA_DIR "/las/pdal/";
  if (!std::ifstream(dir + "autzen_trim.las"))
    GTEST_SKIP() << dir << " missing";
  std::string crs, source, wkt;
  ASSERT_TRUE(readLasCrs(dir + "autzen_trim.las", crs, source).ok());
  EXPECT_EQ(source, "LAS OGC WKT record");
  ASSERT_TRUE(normalizeCrs(crs, wkt).ok()) << crs;
  EXPECT_NE(wkt.find("Lambert Conic Conformal"), std::string::npos)
      << wkt.substr(0, 300);
  ASSERT_TRUE(readLasCrs(dir + "epsg_4326.las", crs, source).ok());
  EXPECT_EQ(crs, "EPSG:4326");
  ASSERT_TRUE(readLasCrs(dir + "4_6_crop.las", crs, source).ok());
  EXPECT_EQ(crs, "EPSG:2903");
  ASSERT_TRUE(readLasCrs(dir + "simple.las", crs, source).ok());
  EXPECT_EQ(crs, "");
}

} // namespace
} // namespace pcl_vts
