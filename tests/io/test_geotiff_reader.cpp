// GeoTIFF input through GDAL: the two shared GeoTIFF DEMs give exactly the points of
// their lossless ASCII-grid copies (gdal_translate -of AAIGrid, see the data README).
#include <pcl_vts/io/asc_grid_reader.h>
#include <pcl_vts/io/geotiff_reader.h>
#include <pcl_vts/io/point_cloud_loader.h>

#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <set>
#include <string>

namespace pcl_vts {
namespace {

std::set<std::array<double, 3>> asSet(const std::vector<double>& xyz)
{
  std::set<std::array<double, 3>> out;
  for (std::size_t k = 0; k + 2 < xyz.size(); k += 3)
    out.insert({xyz[k], xyz[k + 1], xyz[k + 2]});
  return out;
}

TEST(GeoTiffReader, SharedDemsMatchTheirAsciiGridCopies)
{
  if (!geoTiffSupported())
    GTEST_SKIP() << "this build has no GDAL";
  const std::string root = PCL_VTS_SHARED_DATA_DIR;
  for (const std::string stem :
       {"dem/topotoolbox/srtm_bigtujunga30m_utm11", "dem/pysheds/dem"}) {
    SCOPED_TRACE(stem);
    const std::string tif = root + "/" + stem + ".tif",
                      asc = root + "/" + stem + ".derived.asc";
    if (!std::filesystem::exists(tif) || !std::filesystem::exists(asc))
      GTEST_SKIP() << "shared data absent: " << tif;
    std::vector<double> from_tif, from_asc;
    CloudDescription dt, da;
    ASSERT_TRUE(loadPointCloud(tif, {}, from_tif, dt).ok());
    ASSERT_TRUE(loadPointCloud(asc, {}, from_asc, da).ok());
    EXPECT_EQ(dt.format, CloudFileFormat::GEOTIFF);
    EXPECT_EQ(dt.points_kept, da.points_kept);
    // Cell centres agree to rounding of the two geotransform forms; z exactly.
    ASSERT_EQ(from_tif.size(), from_asc.size());
    const auto a = asSet(from_tif), b = asSet(from_asc);
    auto ia = a.begin(), ib = b.begin();
    std::size_t far = 0;
    for (; ia != a.end() && ib != b.end(); ++ia, ++ib)
      far += std::abs((*ia)[0] - (*ib)[0]) > 1e-6 ||
             std::abs((*ia)[1] - (*ib)[1]) > 1e-6 || (*ia)[2] != (*ib)[2];
    EXPECT_EQ(far, 0u);
  }
}

TEST(GeoTiffReader, StreamedRowsEqualTheWholeRead)
{
  if (!geoTiffSupported())
    GTEST_SKIP() << "this build has no GDAL";
  const std::string tif =
      std::string(PCL_VTS_SHARED_DATA_DIR) + "/dem/pysheds/dem.tif"; // with NODATA
  if (!std::filesystem::exists(tif))
    GTEST_SKIP() << "shared data absent: " << tif;
  std::vector<double> whole;
  GeoTiffInfo whole_info;
  ASSERT_TRUE(readGeoTiff(tif, whole, whole_info).ok());
  for (const std::size_t chunk :
       {std::size_t{1}, std::size_t{1000}, std::size_t{1} << 30}) {
    SCOPED_TRACE(chunk);
    std::vector<double> streamed;
    std::size_t calls = 0;
    GeoTiffInfo info;
    const Status s = readGeoTiffChunks(
        tif, chunk,
        [&](const double* xyz, std::size_t n) {
          // Whole rows: a chunk passes its size by less than one row.
          EXPECT_LT(n, chunk + whole_info.columns);
          streamed.insert(streamed.end(), xyz, xyz + 3 * n);
          ++calls;
          return Status::success();
        },
        info);
    ASSERT_TRUE(s.ok()) << s.toString();
    EXPECT_TRUE(streamed == whole);
    EXPECT_EQ(info.valid_cells, whole_info.valid_cells);
    EXPECT_EQ(info.nodata_cells, whole_info.nodata_cells);
    EXPECT_EQ(calls > 1, chunk < whole.size() / 3);
  }
}

TEST(GeoTiffReader, UnreadableRasterIsAnInputError)
{
  std::vector<double> xyz;
  GeoTiffInfo info;
  const Status s = readGeoTiff("/nonexistent/dem.tif", xyz, info);
  EXPECT_EQ(s.code, StatusCode::IO_ERROR);
  EXPECT_NE(s.message.find("dem.tif"), std::string::npos) << s.message;
}

} // namespace
} // namespace pcl_vts
