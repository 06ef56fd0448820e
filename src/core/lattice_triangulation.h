// The lattice fast path of the pipeline (docs/algorithm.md, section 7): when the
// distinct input points lie on a rectilinear lattice (few distinct x values, few
// distinct y values: DEM rasters), every lattice cell whose four corners are present
// is an exact rectangle whose circumcircle holds no other lattice point, so its two
// triangles (diagonal chosen by the symbolic perturbation) are Delaunay in the whole
// set without any search. Only the triangles near missing cells (NODATA, concave
// outlines) are found by the ordinary triangulator, on a small subset that grows
// until every triangle it returns is proven by its empty closed circumdisk.
// Internal to the core: runVtsPipeline calls it when VtsOptions::lattice is on.
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <cstddef>

namespace pcl_vts {

/// Triangulates xyz (3n doubles) when its finite points lie on a rectilinear lattice
/// with at most LATTICE_FILL_FACTOR lattice positions per distinct point.
/// \param[out] handled false when the input is not such a lattice, or when the
///             ordinary path must decide (too few points, all collinear, coordinates
///             out of range): result is then left empty and the caller runs the
///             ordinary path
/// \param[out] result on success the same triangle set, vertices, hull and
///             diagnostics as the ordinary path (vertices in lattice row-major
///             order instead of cell order, so ids differ); the post-passes and the
///             output checks are the caller's
/// \return the status when handled (INTERNAL_ERROR if a proof check fails: a bug)
Status triangulateLattice(const double* xyz, std::size_t n, const VtsOptions& options,
                          VtsResult& result, bool& handled);

/// Lattice positions allowed per distinct point before the input counts as scattered.
constexpr std::size_t LATTICE_FILL_FACTOR = 8;

} // namespace pcl_vts
