// Reads an ESRI ASCII grid (.asc, AAIGrid) as one point per valid cell at the cell
// centre: (xll + (c + 0.5) cs, yll + (nrows - r - 0.5) cs) for column c, row r from
// the top, xll/yll being the lower-left corner (xllcenter/yllcenter are converted).
// NODATA cells are skipped and counted; numbers are parsed strictly. PCL-free.
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/io/export.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pcl_vts {

struct AscGridInfo {
  std::size_t ncols = 0;
  std::size_t nrows = 0;
  double xll = 0.0;               ///< x of the lower-left cell's lower-left corner
  double yll = 0.0;               ///< y of the lower-left cell's lower-left corner
  double cell_dx = 0.0;           ///< cellsize (or dx)
  double cell_dy = 0.0;           ///< cellsize (or dy)
  bool centre_registered = false; ///< the file gave xllcenter/yllcenter
  bool has_nodata = false;
  double nodata = 0.0;
  std::size_t nodata_cells = 0; ///< cells equal to NODATA, skipped
  std::size_t points = 0;       ///< valid cells returned
};

/// Reads every cell of the grid, NODATA skipped.
/// \param[out] xyz 3 doubles per valid cell, rows from the top; cleared on error
/// \return IO_ERROR (one line naming the file) when it is missing, empty, has a bad
///         or incomplete header (ncols, nrows, xll*, yll*, cellsize required), a
///         value that is not a number, fewer or more values than ncols x nrows;
///         EMPTY_INPUT when every cell is NODATA.
PCL_VTS_IO_EXPORT Status readAscGrid(const std::string& path, std::vector<double>& xyz,
                                     AscGridInfo& info);

/// Receives points, xyz triples in file order, a chunk at a time.
using AscChunkSink = std::function<Status(const double* xyz, std::size_t n)>;

/// Same as readAscGrid, but the valid cells go to `sink` in chunks of at most
/// chunk_points, and the file's pages are released behind the reader: memory stays
/// bounded by the chunk whatever the grid's size. Too many values are found after the
/// expected ones went out; a sink error stops the read and is returned.
PCL_VTS_IO_EXPORT Status readAscGridChunks(const std::string& path,
                                           std::size_t chunk_points,
                                           const AscChunkSink& sink, AscGridInfo& info);

/// Same, on bytes in memory; name is used in messages only.
PCL_VTS_IO_EXPORT Status parseAscGrid(const std::uint8_t* data, std::size_t size,
                                      const std::string& name, std::vector<double>& xyz,
                                      AscGridInfo& info);

} // namespace pcl_vts
