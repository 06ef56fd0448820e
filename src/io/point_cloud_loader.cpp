// Extension first (users name their files), content second (for odd names); each
// reader's info is folded into one CloudDescription so the CLI prints one shape.
#include <pcl_vts/core/parallel_for.h>
#include <pcl_vts/io/asc_grid_reader.h>
#include <pcl_vts/io/file_crs.h>
#include <pcl_vts/io/geotiff_reader.h>
#include <pcl_vts/io/pcd_cloud_reader.h>
#include <pcl_vts/io/ply_point_reader.h>
#include <pcl_vts/io/point_cloud_loader.h>
#include <pcl_vts/io/xyz_text_reader.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

namespace pcl_vts {
namespace {

std::string lowerExtension(const std::string& path)
{
  const std::size_t slash = path.rfind('/');
  const std::size_t dot = path.rfind('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
    return {};
  std::string ext = path.substr(dot);
  for (char& c : ext)
    if (c >= 'A' && c <= 'Z')
      c = static_cast<char>(c - 'A' + 'a');
  return ext;
}

bool startsWith(const std::uint8_t* data, std::size_t size, const char* prefix)
{
  const std::size_t n = std::strlen(prefix);
  return size >= n && std::memcmp(data, prefix, n) == 0;
}

std::string fmt(double v)
{
  return formatValue(v);
}

} // namespace

const char* cloudFileFormatName(CloudFileFormat format)
{
  switch (format) {
  case CloudFileFormat::PCD:
    return "PCD";
  case CloudFileFormat::LAS:
    return "LAS";
  case CloudFileFormat::ASC:
    return "ASCII grid";
  case CloudFileFormat::XYZ:
    return "XYZ text";
  case CloudFileFormat::PLY:
    return "PLY";
  case CloudFileFormat::GEOTIFF:
    return "GeoTIFF";
  }
  return "unknown";
}

bool cloudFileFormatFromExtension(const std::string& path, CloudFileFormat& format)
{
  const std::string ext = lowerExtension(path);
  if (ext == ".pcd")
    format = CloudFileFormat::PCD;
  else if (ext == ".las" || ext == ".laz")
    format = CloudFileFormat::LAS;
  else if (ext == ".asc")
    format = CloudFileFormat::ASC;
  else if (ext == ".xyz" || ext == ".txt" || ext == ".csv")
    format = CloudFileFormat::XYZ;
  else if (ext == ".ply")
    format = CloudFileFormat::PLY;
  else if (ext == ".tif" || ext == ".tiff")
    format = CloudFileFormat::GEOTIFF;
  else
    return false;
  return true;
}

bool cloudFileFormatFromContent(const std::uint8_t* data, std::size_t size,
                                CloudFileFormat& format)
{
  std::size_t skip = 0; // leading blanks and comment lines of a PCD header
  if (startsWith(data, size, "LASF"))
    format = CloudFileFormat::LAS;
  else if (startsWith(data, size, "ply\n") || startsWith(data, size, "ply\r"))
    format = CloudFileFormat::PLY;
  else if (size >= 4 &&
           ((data[0] == 'I' && data[1] == 'I' && data[2] == 42 && data[3] == 0) ||
            (data[0] == 'M' && data[1] == 'M' && data[2] == 0 && data[3] == 42)))
    format = CloudFileFormat::GEOTIFF;
  else {
    while (skip < size && data[skip] == '#') {
      while (skip < size && data[skip] != '\n')
        ++skip;
      ++skip;
    }
    const std::uint8_t* p = data + std::min(skip, size);
    const std::size_t n = size - std::min(skip, size);
    std::string word;
    for (std::size_t i = 0; i < n && i < 16; ++i) {
      const char c = static_cast<char>(p[i]);
      if (c == ' ' || c == '\t' || c == '\r' || c == '\n')
        break;
      word += static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    }
    if (word == "version" || word == "fields")
      format = CloudFileFormat::PCD;
    else if (word == "ncols" || word == "nrows")
      format = CloudFileFormat::ASC;
    else
      return false;
  }
  return true;
}

/// The summary's words for a LAS file.
static void describeLas(const LasInfo& info, const CloudLoadOptions& options,
                        CloudDescription& d)
{
  d.points_read = static_cast<std::size_t>(info.points_read);
  d.points_kept = static_cast<std::size_t>(info.points_kept);
  d.details = std::to_string(info.version_major) + "." +
              std::to_string(info.version_minor) + ", point format " +
              std::to_string(info.point_format) + ", " +
              std::to_string(info.record_length) + "-byte records";
  std::string classes;
  for (std::size_t c = 0; c < info.class_counts.size(); ++c)
    if (info.class_counts[c] != 0)
      classes += (classes.empty() ? "" : ", ") + std::to_string(c) + ": " +
                 std::to_string(info.class_counts[c]);
  d.notes.push_back("classes in file: " + classes);
  d.notes.push_back("scale " + fmt(info.scale[0]) + " " + fmt(info.scale[1]) + " " +
                    fmt(info.scale[2]) + ", offset " + fmt(info.offset[0]) + " " +
                    fmt(info.offset[1]) + " " + fmt(info.offset[2]));
  if (!options.classes.empty() || options.returns != LasReturnFilter::ALL) {
    std::string filter;
    for (std::uint8_t c : options.classes)
      filter += (filter.empty() ? "classes " : ",") + std::to_string(c);
    if (options.returns != LasReturnFilter::ALL)
      filter += std::string(filter.empty() ? "" : ", ") +
                lasReturnFilterName(options.returns) + " returns";
    d.notes.push_back("filter " + filter + ": " + std::to_string(d.points_kept) +
                      " of " + std::to_string(d.points_read) + " points kept");
  }
}

namespace {

/// The CRS the file declares (LAS records; GeoTIFF's, already in d), else the text
/// of a .prj beside it.
Status describeCrs(const std::string& path, CloudDescription& d)
{
  if (d.format == CloudFileFormat::LAS)
    if (Status s = readLasCrs(path, d.crs, d.crs_source); !s.ok())
      return s;
  if (d.crs.empty())
    return readPrjSidecar(path, d.crs, d.crs_source);
  return Status::success();
}

} // namespace

/// The summary of a PCD file.
static void describePcd(const PcdCloudInfo& info, CloudDescription& d)
{
  d.points_read = d.points_kept = info.points;
  d.details = info.data_format + ", " + info.xyzDescription();
}

/// The summary of an ASCII grid.
static void describeAsc(const AscGridInfo& info, CloudDescription& d)
{
  d.points_read = info.ncols * info.nrows;
  d.points_kept = info.points;
  d.details =
      std::to_string(info.ncols) + " x " + std::to_string(info.nrows) + " cells of " +
      fmt(info.cell_dx) +
      (info.cell_dx == info.cell_dy ? std::string() : " x " + fmt(info.cell_dy)) +
      (info.centre_registered ? ", xllcenter" : ", xllcorner");
  d.notes.push_back(std::to_string(info.nodata_cells) + " NODATA cells skipped" +
                    (info.has_nodata ? " (NODATA = " + fmt(info.nodata) + ")"
                                     : std::string(" (no NODATA_value)")));
}

/// The summary of a raster read through GDAL, its CRS included.
static void describeGeoTiff(const GeoTiffInfo& info, CloudDescription& d)
{
  d.points_read = info.columns * info.rows;
  d.points_kept = info.valid_cells;
  d.details = info.driver + ", " + std::to_string(info.columns) + " x " +
              std::to_string(info.rows) + " cells";
  d.notes.push_back(std::to_string(info.nodata_cells) + " NODATA cells skipped");
  d.crs = info.crs_wkt;
  if (!d.crs.empty())
    d.crs_source = "GeoTIFF";
}

/// The summary of a PLY's vertices.
static void describePly(const PlyPointInfo& info, CloudDescription& d)
{
  d.points_read = d.points_kept = info.vertices;
  d.details =
      info.format + ", x y z " + info.xyz_types[0] +
      (info.xyz_types[0] == info.xyz_types[1] && info.xyz_types[1] == info.xyz_types[2]
           ? std::string()
           : " " + info.xyz_types[1] + " " + info.xyz_types[2]) +
      (info.faces ? ", " + std::to_string(info.faces) + " faces ignored"
                  : std::string());
}

/// The summary of a text table.
static void describeXyz(const XyzTextInfo& info, CloudDescription& d)
{
  d.points_read = d.points_kept = info.points;
  d.details = "columns " + std::to_string(info.column[0] + 1) + " " +
              std::to_string(info.column[1] + 1) + " " +
              std::to_string(info.column[2] + 1) +
              (info.header.empty() ? ", no header" : ", header line");
}

namespace {

/// What one read asks for: the whole file into xyz, or chunk_points at a time to
/// *sink when sink is set.
struct CloudRead {
  const std::string& path;
  std::size_t chunk_points;
  const PointChunkSink* sink;
  std::vector<double>& xyz;
};

/// One format's reader, whole or in chunks as read asks, then on success its summary.
template <typename Info, typename Whole, typename Chunks, typename Describe>
Status readAs(const CloudRead& read, const Whole& whole, const Chunks& chunks,
              const Describe& describe)
{
  Info info;
  const Status s = read.sink != nullptr
                       ? chunks(read.path, read.chunk_points, *read.sink, info)
                       : whole(read.path, read.xyz, info);
  if (s.ok())
    describe(info);
  return s;
}

/// The reader of format, and the description of what it read (the CRS aside).
Status readCloud(CloudFileFormat format, const CloudLoadOptions& options,
                 const CloudRead& read, CloudDescription& d)
{
  const auto into = [&d](auto describe) {
    return [&d, describe](const auto& info) { describe(info, d); };
  };
  switch (format) {
  case CloudFileFormat::PCD:
    return readAs<PcdCloudInfo>(read, readPcdCloud, readPcdCloudChunks,
                                into(describePcd));
  case CloudFileFormat::LAS: {
    LasReadOptions las;
    las.classes = options.classes;
    las.returns = options.returns;
    las.threads = options.threads == 0 ? allCores() : options.threads;
    return readAs<LasInfo>(
        read,
        [&las](const std::string& path, std::vector<double>& xyz, LasInfo& info) {
          return readLasCloud(path, las, xyz, info);
        },
        [&las](const std::string& path, std::size_t chunk_points,
               const PointChunkSink& sink, LasInfo& info) {
          return readLasCloudChunks(path, las, chunk_points, sink, info);
        },
        [&](const LasInfo& info) { describeLas(info, options, d); });
  }
  case CloudFileFormat::ASC:
    return readAs<AscGridInfo>(read, readAscGrid, readAscGridChunks, into(describeAsc));
  case CloudFileFormat::XYZ:
    return readAs<XyzTextInfo>(read, readXyzText, readXyzTextChunks, into(describeXyz));
  case CloudFileFormat::PLY:
    return readAs<PlyPointInfo>(read, readPlyPoints, readPlyPointChunks,
                                into(describePly));
  case CloudFileFormat::GEOTIFF:
    return readAs<GeoTiffInfo>(read, readGeoTiff, readGeoTiffChunks,
                               into(describeGeoTiff));
  }
  return Status::error(StatusCode::INTERNAL_ERROR, "unknown cloud file format");
}

} // namespace

Status loadPointCloud(const std::string& path, const CloudLoadOptions& options,
                      std::vector<double>& xyz, CloudDescription& d)
{
  d = CloudDescription();
  xyz.clear();
  if (!cloudFileFormatFromExtension(path, d.format)) {
    std::ifstream in(path, std::ios::binary);
    if (!in)
      return Status::error(StatusCode::IO_ERROR,
                           "'" + path + "': cannot open: " + std::strerror(errno));
    std::uint8_t head[256] = {};
    in.read(reinterpret_cast<char*>(head), sizeof(head));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (!cloudFileFormatFromContent(head, got, d.format))
      return Status::error(
          StatusCode::IO_ERROR,
          "'" + path + "': unknown input format: the extension '" +
              lowerExtension(path) +
              "' is none of .pcd .las .laz .asc .xyz .txt .csv .ply .tif and the "
              "content "
              "is not recognised");
  }
  if (d.format != CloudFileFormat::LAS &&
      (!options.classes.empty() || options.returns != LasReturnFilter::ALL))
    return Status::error(StatusCode::INVALID_PARAMETER,
                         std::string("class and return filters apply to LAS input "
                                     "only; '") +
                             path + "' is " + cloudFileFormatName(d.format));
  if (Status s = readCloud(d.format, options, {path, 0, nullptr, xyz}, d); !s.ok())
    return s;
  return describeCrs(path, d);
}

Status streamPointCloud(const std::string& path, const CloudLoadOptions& options,
                        std::size_t chunk_points, const PointChunkSink& sink,
                        CloudDescription& description)
{
  CloudFileFormat format = CloudFileFormat::PCD;
  const bool las_filters =
      !options.classes.empty() || options.returns != LasReturnFilter::ALL;
  // A file without a known extension (recognised by content) and any format but LAS
  // with LAS filters go through loadPointCloud (which refuses the filters).
  if (!cloudFileFormatFromExtension(path, format) ||
      (format != CloudFileFormat::LAS && las_filters)) {
    std::vector<double> xyz;
    if (Status s = loadPointCloud(path, options, xyz, description); !s.ok())
      return s;
    return sink(xyz.data(), xyz.size() / 3);
  }
  description = CloudDescription();
  description.format = format;
  std::vector<double> unused;
  if (Status s =
          readCloud(format, options, {path, chunk_points, &sink, unused}, description);
      !s.ok())
    return s;
  return describeCrs(path, description);
}

} // namespace pcl_vts
