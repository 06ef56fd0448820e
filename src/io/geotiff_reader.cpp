#include <pcl_vts/io/geotiff_reader.h>

#include <algorithm>
#include <cmath>
#include <limits>

#ifdef PCL_VTS_HAVE_GDAL
#include <gdal.h>
#endif

namespace pcl_vts {

#ifndef PCL_VTS_HAVE_GDAL

bool geoTiffSupported()
{
  return false;
}

Status readGeoTiffChunks(const std::string& path, std::size_t, const GeoTiffChunkSink&,
                         GeoTiffInfo& info)
{
  info = GeoTiffInfo{};
  return Status::error(StatusCode::IO_ERROR,
                       "'" + path +
                           "': this build reads rasters only with GDAL, which was not "
                           "found; convert it with `gdal_translate -of AAIGrid in.tif "
                           "out.asc` and read the .asc");
}

#else

bool geoTiffSupported()
{
  return true;
}

Status readGeoTiffChunks(const std::string& path, std::size_t chunk_points,
                         const GeoTiffChunkSink& sink, GeoTiffInfo& info)
{
  info = GeoTiffInfo{};
  chunk_points = std::max<std::size_t>(chunk_points, 1);
  std::vector<double> xyz;
  GDALAllRegister();
  CPLPushErrorHandler(CPLQuietErrorHandler);
  GDALDatasetH dataset = GDALOpen(path.c_str(), GA_ReadOnly);
  CPLPopErrorHandler();
  if (dataset == nullptr)
    return Status::error(StatusCode::IO_ERROR,
                         "'" + path + "': GDAL cannot open it as a raster");
  struct Closer {
    GDALDatasetH d;
    ~Closer() { GDALClose(d); }
  } closer{dataset};
  if (GDALGetRasterCount(dataset) < 1)
    return Status::error(StatusCode::IO_ERROR,
                         "'" + path + "': the raster has no band");
  double gt[6];
  if (GDALGetGeoTransform(dataset, gt) != CE_None)
    return Status::error(StatusCode::IO_ERROR,
                         "'" + path + "': the raster has no geotransform");
  GDALRasterBandH band = GDALGetRasterBand(dataset, 1);
  info.columns = static_cast<std::size_t>(GDALGetRasterXSize(dataset));
  info.rows = static_cast<std::size_t>(GDALGetRasterYSize(dataset));
  info.pixel_width = gt[1];
  info.pixel_height = gt[5];
  info.driver = GDALGetDriverShortName(GDALGetDatasetDriver(dataset));
  if (const char* wkt = GDALGetProjectionRef(dataset))
    info.crs_wkt = wkt;
  int has_nodata = 0;
  info.nodata = GDALGetRasterNoDataValue(band, &has_nodata);
  info.has_nodata = has_nodata != 0;
  std::vector<double> row(info.columns);
  for (std::size_t r = 0; r < info.rows; ++r) {
    if (xyz.size() >= 3 * chunk_points) { // rows read: hand them over
      if (Status s = sink(xyz.data(), xyz.size() / 3); !s.ok())
        return s;
      xyz.clear();
    }
    if (GDALRasterIO(band, GF_Read, 0, static_cast<int>(r),
                     static_cast<int>(info.columns), 1, row.data(),
                     static_cast<int>(info.columns), 1, GDT_Float64, 0, 0) != CE_None)
      return Status::error(StatusCode::IO_ERROR, "'" + path + "': cannot read row " +
                                                     std::to_string(r) + " of band 1");
    for (std::size_t c = 0; c < info.columns; ++c) {
      const double z = row[c];
      if ((info.has_nodata && z == info.nodata) || !std::isfinite(z)) {
        ++info.nodata_cells;
        continue;
      }
      const double u = static_cast<double>(c) + 0.5, v = static_cast<double>(r) + 0.5;
      xyz.push_back(gt[0] + u * gt[1] + v * gt[2]);
      xyz.push_back(gt[3] + u * gt[4] + v * gt[5]);
      xyz.push_back(z);
      ++info.valid_cells;
    }
  }
  if (info.valid_cells == 0)
    return Status::error(StatusCode::EMPTY_INPUT,
                         "'" + path + "': every cell of band 1 is NODATA");
  return xyz.empty() ? Status::success() : sink(xyz.data(), xyz.size() / 3);
}

#endif

Status readGeoTiff(const std::string& path, std::vector<double>& xyz, GeoTiffInfo& info)
{
  xyz.clear();
  const Status s = readGeoTiffChunks(
      path, std::numeric_limits<std::size_t>::max() / 4,
      [&](const double* chunk, std::size_t n) {
        xyz.insert(xyz.end(), chunk, chunk + 3 * n);
        return Status::success();
      },
      info);
  if (!s.ok())
    xyz.clear();
  return s;
}

} // namespace pcl_vts
