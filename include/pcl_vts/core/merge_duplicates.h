// Input conditioning after gridding: points with identical XY cannot both be vertices
// of a 2D triangulation, so each run of equal XY (adjacent once grid-sorted) folds
// into one vertex by a stated rule. Counted, never an error.
#pragma once

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/export.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {

/// Which z survives when several input points share the same XY exactly.
enum class DuplicateRule {
  LOWEST_Z,  ///< keep the lowest point (default: ground under vegetation returns)
  HIGHEST_Z, ///< keep the highest point
  MEAN_Z,    ///< one vertex at the mean z; its source is the first such point
  FIRST      ///< keep the point that comes first in the input
};

/// "lowest", "highest", "mean" or "first".
PCL_VTS_CORE_EXPORT const char* duplicateRuleName(DuplicateRule rule);

/// Folds each run of equal XY in grid.points into one point.
/// \param[in,out] grid points and cell_start are compacted in place
/// \param[in] rule which z (and which source point) represents a run
/// \param[in,out] z per grid slot on entry, per distinct point on exit
/// \param[in,out] source input index per grid slot on entry, per distinct point on
///                exit (the representative's index)
/// \param[out] slot_to_vertex per grid slot on entry: its distinct point
/// \return the number of points folded into another
PCL_VTS_CORE_EXPORT std::size_t mergeDuplicates(CellGrid& grid, DuplicateRule rule,
                                                std::vector<double>& z,
                                                std::vector<std::uint32_t>& source,
                                                std::vector<VertexId>& slot_to_vertex);

} // namespace pcl_vts
