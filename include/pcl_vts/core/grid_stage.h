// Stage 1 of the pipeline in one piece: input conditioning (non-finite points
// dropped, the coordinate range checked), bucketing into the cell grid, the duplicate
// merge, the crowded cells' quadtrees and the occupancy pyramid. The grid is the one
// that buildCellGrid, mergeDuplicates (any rule), subdivideCrowdedCells and
// buildCellPyramid give on the finite points, the reference composition the tests
// compare it with, for any number of threads; but its memory traffic is sequential:
// the points are first distributed into bands of rows (a stable counting sort by
// band), then each band, small enough to stay in cache, is sorted by cell, merged and
// subdivided on its own, one band per thread at a time.
#pragma once

#include <pcl_vts/core/cell_grid.h>
#include <pcl_vts/core/cell_pyramid.h>
#include <pcl_vts/core/cell_subdivision.h>
#include <pcl_vts/core/export.h>
#include <pcl_vts/core/merge_duplicates.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {

/// What the grid stage hands to the triangulation.
struct GridStage {
  CellGrid grid;
  CellSubdivision subdivision;
  CellPyramid pyramid;
  std::vector<std::uint32_t> source; ///< input index of each vertex (grid point)
};

/// Builds the grid stage of xyz (3n doubles, n < INVALID_ID).
/// \param[in] cell_size 0 for automatic (buildCellGrid)
/// \param[in] rule which point represents equal XY (mergeDuplicates)
/// \param[in] threads threads (at least 1); the result is the same for any number
/// \param[out] input_to_vertex per input point: its vertex, INVALID_ID if dropped;
///             left empty when no point was merged (it is then the inverse of
///             stage.source: INVALID_ID but at source[v], v)
/// \param[out] diag non_finite_dropped, duplicates_merged, distinct_points, cells and
///             cell_size
/// \return COORDINATE_RANGE (|x| or |y| beyond 1e60, or an XY extent below 1e-80),
///         EMPTY_INPUT (no finite point) or INVALID_PARAMETER (absurd cell count)
PCL_VTS_CORE_EXPORT Status buildGridStage(const double* xyz, std::size_t n,
                                          double cell_size, DuplicateRule rule,
                                          unsigned threads, GridStage& stage,
                                          std::vector<VertexId>& input_to_vertex,
                                          Diagnostics& diag);

/// buildGridStage without the per-input map when input_to_vertex is nullptr (the
/// same grid stage, less the merged points' bookkeeping): for a caller that needs
/// neither the map nor the merged points' mean height.
PCL_VTS_CORE_EXPORT Status buildGridStage(const double* xyz, std::size_t n,
                                          double cell_size, DuplicateRule rule,
                                          unsigned threads, GridStage& stage,
                                          std::vector<VertexId>* input_to_vertex,
                                          Diagnostics& diag);

} // namespace pcl_vts
