// The trim's compaction (internal to the core; trim_outward_triangles.cpp): drops
// the removed triangles from the mesh's arrays in place, the survivors in their
// order, the twins remapped. Exported for the tests, which compare its loops.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/mesh_arrays.h>

#include <vector>

namespace pcl_vts::detail {

/// Which loop moves the survivors: the best this CPU runs (AVX2 when it has it), or
/// the portable one (SSE2, else scalar). The same arrays either way.
enum class CompactionLoop { BEST, PORTABLE };

/// Whether CompactionLoop::BEST runs the AVX2 loop on this CPU.
PCL_VTS_CORE_EXPORT bool compactionHasAvx2();

/// Drops the triangles of `dropped` (distinct ids, any order, at least one) from
/// mesh: the others keep their relative order, a twin into a dropped triangle
/// becomes INVALID_ID; with boundary, every halfedge without twin afterwards, in
/// increasing order (the mesh's twins must be consistent). On `threads` contiguous
/// ranges (the same arrays for any value).
PCL_VTS_CORE_EXPORT void compactTriangles(TriangleMesh& mesh,
                                          const std::vector<TriangleId>& dropped,
                                          unsigned threads,
                                          std::vector<HalfedgeId>* boundary,
                                          CompactionLoop loop = CompactionLoop::BEST);

} // namespace pcl_vts::detail
