// Reads the x, y, z fields of a PCD file into doubles, never through a float PointXYZ:
// float64 (UTM-sized) coordinates keep every bit. The header is checked before PCL
// sees it (PCL allocates the claimed size up front and crashes on some bad files),
// the body is read by pcl::PCDReader into a PCLPointCloud2 (ASCII bodies strictly, by
// us: PCL turns a malformed line into a silent 0). PCL types stay out of this header.
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/io/export.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pcl_vts {

/// Storage type of a PCD field (PCD TYPE + SIZE).
enum class PcdValueType : std::uint8_t {
  INT8,
  UINT8,
  INT16,
  UINT16,
  INT32,
  UINT32,
  INT64,
  UINT64,
  FLOAT32,
  FLOAT64
};

/// "float32", "float64", "int8", ..., "uint64".
PCL_VTS_IO_EXPORT const char* pcdValueTypeName(PcdValueType type);

/// What the reader found in the file, for the caller's summary and output choices.
struct PCL_VTS_IO_EXPORT PcdCloudInfo {
  std::size_t points = 0;   ///< WIDTH * HEIGHT = POINTS
  std::uint32_t width = 0;  ///< PCD WIDTH
  std::uint32_t height = 0; ///< PCD HEIGHT
  std::string data_format;  ///< "ascii", "binary" or "binary_compressed"
  std::string fields;       ///< every field name, space separated, as in the file
  /// The fields used for x, y, z as spelled in the file ("x" or "X").
  std::array<std::string, 3> xyz_names;
  std::array<PcdValueType, 3> xyz_types{PcdValueType::FLOAT32, PcdValueType::FLOAT32,
                                        PcdValueType::FLOAT32};

  /// True when x, y and z are all stored as float32.
  bool xyzAllFloat32() const;
  /// True when any of x, y, z is stored as float64.
  bool xyzAnyFloat64() const;
  /// "x y z float32" or "X Y Z float64" or "x:float32 y:float32 z:float64".
  std::string xyzDescription() const;
};

/// Reads the x, y, z coordinates of every point of a PCD file (ascii, binary or
/// binary_compressed). Field names match "x"/"y"/"z" in either case (lower case
/// preferred); each must have COUNT 1 and a float or integer type. NaN and Inf are
/// passed through unchanged (the core drops and counts them).
/// \param[in] path the .pcd file
/// \param[out] xyz 3 doubles per point, in file order; cleared on error
/// \param[out] info what was found; meaningful on success
/// \return IO_ERROR (one-line message naming the file) when the file is missing,
///         unreadable, empty, not a PCD file, has no x/y/z, is truncated or its header
///         claims more data than the file holds; EMPTY_INPUT when it holds 0 points.
PCL_VTS_IO_EXPORT Status readPcdCloud(const std::string& path, std::vector<double>& xyz,
                                      PcdCloudInfo& info);

/// readPcdCloud in chunks of at most chunk_points handed to sink as the body is read:
/// ascii and binary bodies stream (the mapped pages behind the reader are dropped), so
/// memory stays at one chunk whatever the file's size; a binary_compressed body (LZF,
/// stored column by column) is unpacked whole first. The same errors; a sink's failure
/// stops the read and is returned.
PCL_VTS_IO_EXPORT Status
readPcdCloudChunks(const std::string& path, std::size_t chunk_points,
                   const std::function<Status(const double* xyz, std::size_t n)>& sink,
                   PcdCloudInfo& info);

} // namespace pcl_vts
