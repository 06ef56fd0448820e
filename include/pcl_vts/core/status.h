// Status and diagnostics returned by every core entry point: a code a caller can
// test, a message that names the values involved, and counts of the recoverable
// oddities (dropped, merged) that are not errors. No exception crosses the core API.
#pragma once

#include <pcl_vts/core/export.h>

#include <cstddef>
#include <string>

namespace pcl_vts {

enum class StatusCode {
  OK = 0,
  EMPTY_INPUT,       ///< no point at all (or none left after dropping non-finite ones)
  CAPACITY_EXCEEDED, ///< more points or triangles than the 32-bit ids can number
  TOO_FEW_POINTS,    ///< fewer than 3 distinct XY positions
  ALL_COLLINEAR,     ///< every distinct XY position lies on one line
  COORDINATE_RANGE,  ///< coordinates too large or extent too small to grid safely
  INVALID_PARAMETER, ///< an option out of its documented range
  IO_ERROR,          ///< reading or writing a file failed
  INTERNAL_ERROR     ///< a post-condition check failed: a bug, please report
};

/// Short upper-case name of a code, e.g. "ALL_COLLINEAR".
PCL_VTS_CORE_EXPORT const char* statusCodeName(StatusCode code);

struct [[nodiscard]] Status {
  StatusCode code = StatusCode::OK;
  std::string message;

  bool ok() const { return code == StatusCode::OK; }
  static Status success() { return {}; }
  static Status error(StatusCode c, std::string msg) { return {c, std::move(msg)}; }
  /// "ALL_COLLINEAR: all 12 distinct points lie on one line"
  PCL_VTS_CORE_EXPORT std::string toString() const;
};

/// A number for a message: shortest form that reads back to the same double.
PCL_VTS_CORE_EXPORT std::string formatValue(double value);

/// The one check of a length-like parameter: OK when value is finite and >= 0, else
/// INVALID_PARAMETER "<name> = <value> must be finite and >= 0<note>" (NaN and
/// infinities are out of the documented range like negatives; note says what 0
/// means, e.g. " (0 = automatic)").
PCL_VTS_CORE_EXPORT Status checkFiniteNonNegative(const char* name, double value,
                                                  const char* note = "");

/// What happened to the input on its way to the mesh.
struct Diagnostics {
  std::size_t points_in = 0;          ///< points handed to the pipeline
  std::size_t non_finite_dropped = 0; ///< NaN/Inf in x, y or z: skipped
  std::size_t duplicates_merged = 0;  ///< points folded into another with equal XY
  std::size_t distinct_points = 0;    ///< vertices of the triangulation
  std::size_t hull_vertices = 0;      ///< vertices on the convex hull (collinear kept)
  std::size_t triangles = 0;          ///< triangles output
  std::size_t cells = 0;              ///< grid cells (nx * ny)
  double cell_size = 0.0;             ///< grid cell edge length actually used
  std::size_t local_searches =
      0; ///< third-point searches settled in the edge rectangle
  std::size_t widened_searches = 0; ///< searches that needed the widening stage
  std::size_t cells_visited = 0;    ///< grid cells whose points were tested
  std::size_t points_tested = 0;    ///< candidate points looked at by the searches
  double seconds_grid = 0.0;        ///< input conditioning + grid build
  double seconds_hull = 0.0;        ///< convex hull
  double seconds_triangulate = 0.0; ///< region growing
  /// Lattice fast path (VtsOptions::lattice): distinct x and y values of the lattice,
  /// 0 when the ordinary path ran; the fringe (docs/algorithm.md, section 7): its
  /// pieces, the points they gave the ordinary path in their last rounds, and the
  /// most rounds a piece took.
  std::size_t lattice_columns = 0;
  std::size_t lattice_rows = 0;
  std::size_t lattice_fringe_pieces = 0;
  std::size_t lattice_fringe_points = 0;
  std::size_t lattice_fringe_rounds = 0;
  /// Fringe triangles proven in one window (VtsOptions::lattice_one_window; 0 when
  /// the pieces went one by one).
  std::size_t lattice_fringe_window = 0;
};

} // namespace pcl_vts
