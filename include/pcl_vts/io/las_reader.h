// Reads the x, y, z of a LAS 1.0-1.4 file (point formats 0-10), plain or LASzip-
// compressed (LAZ: point formats 0-3 and 6-10, decoded chunk by chunk on threads), into
// doubles: int32 * scale + offset, records stepped by the header's record length
// (extra bytes), optional classification and return filters. Every size the header
// claims is checked against the file before anything is allocated. PCL-free (std +
// POSIX); no LAS or LAZ library needed.
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

/// Which returns of each pulse are kept.
enum class LasReturnFilter {
  ALL,   ///< every point (default)
  FIRST, ///< return number 1
  LAST   ///< return number == number of returns
};

/// "all", "first" or "last".
PCL_VTS_IO_EXPORT const char* lasReturnFilterName(LasReturnFilter filter);

struct LasReadOptions {
  /// Classification codes to keep, e.g. {2} for ground; empty = every class.
  /// Formats 0-5 store the class in the low 5 bits, formats 6-10 in a full byte.
  std::vector<std::uint8_t> classes;
  LasReturnFilter returns = LasReturnFilter::ALL;
  /// LAZ: chunks decoded at once, one per thread (1 = on the calling thread).
  unsigned threads = 1;
};

/// What the reader found, for the caller's summary.
struct PCL_VTS_IO_EXPORT LasInfo {
  int version_major = 0;
  int version_minor = 0;
  int point_format = 0;             ///< 0-10
  std::size_t record_length = 0;    ///< bytes per point record (>= format minimum)
  std::size_t header_size = 0;      ///< bytes of the public header block
  std::size_t offset_to_points = 0; ///< byte offset of the first point record
  std::uint64_t points_in_header = 0;
  std::uint64_t points_read = 0; ///< records read (== points_in_header on success)
  std::uint64_t points_kept = 0; ///< records that passed the filters
  std::array<double, 3> scale{};
  std::array<double, 3> offset{};
  std::array<double, 3> header_min{}; ///< bounds as the header states them
  std::array<double, 3> header_max{};
  std::array<double, 3> min{}; ///< bounds of the kept points (computed)
  std::array<double, 3> max{};
  /// Records read per classification code (formats 0-5: 0-31 only).
  std::array<std::uint64_t, 256> class_counts{};
  std::string system_identifier;
  std::string generating_software;
  /// LAZ: how the points are compressed ("layered-chunked (3), LASzip 3.4.3, 50000
  /// points per chunk"); empty for LAS.
  std::string laz;

  /// "LAS 1.2, point format 3, 34-byte records" ("LAZ 1.4, ..." for LAZ).
  std::string description() const;
};

/// Reads every point record of a LAS file and keeps those passing the filters.
/// \param[in] path the .las file
/// \param[in] options classification / return filters
/// \param[out] xyz 3 doubles per kept point, in file order; cleared on error
/// \param[out] info header fields and counts; meaningful on success
/// \return IO_ERROR (one line naming the file) when it is missing, unreadable, not
///         LAS, LAZ-compressed (the message says how to convert), of an unsupported
///         version or point format, has an inconsistent header or is truncated;
///         EMPTY_INPUT when it holds 0 points or no point passes the filters (the
///         message lists the classes present).
PCL_VTS_IO_EXPORT Status readLasCloud(const std::string& path,
                                      const LasReadOptions& options,
                                      std::vector<double>& xyz, LasInfo& info);

/// Receives kept points, xyz triples in file order, a chunk at a time.
using LasChunkSink = std::function<Status(const double* xyz, std::size_t n)>;

/// Same as readLasCloud, but the kept points go to `sink` in chunks of at most
/// chunk_points instead of one array, and the file's pages are released behind the
/// reader: memory stays bounded by the chunk whatever the file's size. A sink error
/// stops the read and is returned. EMPTY_INPUT (with nothing sent) as readLasCloud.
PCL_VTS_IO_EXPORT Status readLasCloudChunks(const std::string& path,
                                            const LasReadOptions& options,
                                            std::size_t chunk_points,
                                            const LasChunkSink& sink, LasInfo& info);

/// Same, on bytes in memory; name is used in messages only.
PCL_VTS_IO_EXPORT Status parseLasCloud(const std::uint8_t* data, std::size_t size,
                                       const std::string& name,
                                       const LasReadOptions& options,
                                       std::vector<double>& xyz, LasInfo& info);

} // namespace pcl_vts
