// The crop and the PMF ground filter on inputs larger than memory: the pre-pass of a
// tiled run.
//
// pcl::ProgressiveMorphologicalFilter is point-based: each round opens (min z, then
// max z, over the points still ground in an XY box of half the round's window around
// each point) and keeps the points less than the round's threshold above the opened
// surface. A point's class therefore depends only on the points within pmfReach()
// of it (preprocess_cloud.h). The pre-pass cuts the cloud into square pre-tiles,
// loads each pre-tile's points with a halo of that reach, runs the in-memory filter
// (preprocessCloud) on them with the whole cloud's shift (so PCL sees the very floats
// of the in-memory run), and keeps the ground points of the pre-tile's core. The
// union over the pre-tiles is the in-memory run's set of ground points; each file
// holds its points in input order, and points with equal XY share a file, so every
// duplicate rule gives the in-memory z.
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/export.h>
#include <pcl_vts/preprocess_cloud.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pcl_vts {

/// xyz triples in chunks; a feed calls the sink with every input point, in input
/// order, and gives the same points each time it is called (it is called twice).
using GroundSink = std::function<Status(const double* xyz, std::size_t n)>;
using GroundFeed = std::function<Status(const GroundSink& sink)>;

/// How several processes (MPI ranks) share the pre-pass: every rank calls groundTiles
/// with the same arguments; rank 0 reads the inputs and writes the pre-tile files
/// (into a folder every rank sees), then every rank filters the pre-tiles it takes
/// from the shared counter. Default: one process.
struct GroundShare {
  int rank = 0, ranks = 1;
  std::function<void(std::string& bytes, int root)> broadcast;
  std::function<void(std::vector<std::uint64_t>& values)> sum; ///< element-wise
  std::function<void()> start_tasks;        ///< collective: the counter to 0
  std::function<std::uint64_t()> next_task; ///< thread-safe: 0, 1, 2, ...
};

struct GroundTilesOptions {
  /// crop and ground_pmf only: voxel, grid-min and outliers are not tiled
  /// (INVALID_PARAMETER); fixed_shift is set by the pre-pass.
  PreprocessOptions preprocess;
  /// Memory the pre-pass may use: one pre-tile and its halo at a time.
  std::uint64_t memory_limit = std::uint64_t{1} << 30;
  /// Pre-tiles filtered at once (0 = all hardware threads); the memory limit is
  /// shared between them. The points kept are the same for every value.
  unsigned threads = 1;
  /// Testing knob: pre-tiles per side (0 = from memory_limit).
  int tiles_per_side = 0;
  /// Several processes (default: one).
  GroundShare share;
  /// Called with "ground scan", "ground bucket" (points done so far) and "ground
  /// filter" (pre-tiles done of total); from the calling thread only.
  std::function<void(const char* phase, std::uint64_t done, std::uint64_t total)>
      progress;
};

struct GroundTilesReport {
  std::uint64_t points = 0;     ///< fed
  std::uint64_t non_finite = 0; ///< dropped
  std::uint64_t cropped = 0;    ///< left after the crop (all finite points without)
  std::uint64_t kept = 0;       ///< ground points written
  int tiles_per_side = 0;
  std::uint64_t tiles = 0;            ///< pre-tiles with core points
  double tile_side = 0.0, halo = 0.0; ///< XY units
  std::uint64_t points_loaded = 0;    ///< over the pre-tiles, halos included
  std::uint64_t max_tile_points = 0;  ///< the largest pre-tile with its halo
  double seconds_scan = 0.0, seconds_bucket = 0.0, seconds_filter = 0.0;
};

/// Runs the crop and the ground filter of options.preprocess over the points of
/// feed, writing the points kept into files in folder (which must exist); `files`
/// gets their paths (the caller's to remove; each pre-tile's own file is removed
/// once filtered). Their union is what preprocessCloud keeps of all the points
/// together. EMPTY_INPUT (the in-memory message) when no point is left.
PCL_VTS_EXPORT Status groundTiles(const GroundFeed& feed,
                                  const GroundTilesOptions& options,
                                  const std::string& folder,
                                  std::vector<std::string>& files,
                                  GroundTilesReport& report);

/// Streams a file written by groundTiles to sink, chunk_points at a time.
PCL_VTS_EXPORT Status readGroundFile(const std::string& path, std::size_t chunk_points,
                                     const GroundSink& sink);

} // namespace pcl_vts
