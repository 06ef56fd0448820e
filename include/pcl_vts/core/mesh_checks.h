// Checkers over mesh arrays: library functions, not test helpers, so the pipeline
// can verify its own post-conditions and tests can prove each checker fails on a
// broken mesh. All geometric decisions use the exact predicates.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/mesh_arrays.h>

#include <cstddef>
#include <string>
#include <vector>

namespace pcl_vts {

/// Every triangle has positive exact orientation (CCW seen from +z).
/// On failure, *why names the first bad triangle. `threads` (0 = all hardware
/// threads) split the scan; the verdict and the message are the same for any value
/// (here and in halfedgesConsistent and isValidSurfaceMesh).
PCL_VTS_CORE_EXPORT bool allTrianglesCcw(const TriangleMesh& mesh,
                                         std::string* why = nullptr,
                                         unsigned threads = 1);

/// halfedges is twin-symmetric: h[h[e]] == e, twins join the same two vertices in
/// opposite directions, ids are in range.
PCL_VTS_CORE_EXPORT bool halfedgesConsistent(const TriangleMesh& mesh,
                                             std::string* why = nullptr,
                                             unsigned threads = 1);

/// No undirected edge is used by more than two triangles, and no directed edge twice.
PCL_VTS_CORE_EXPORT bool isEdgeManifold(const TriangleMesh& mesh,
                                        std::string* why = nullptr);

/// isEdgeManifold, halfedgesConsistent and allTrianglesCcw, in this order (the first
/// failure's message), in one pass over the triangles and a byte a vertex: with
/// consistent twins and CCW triangles, a vertex whose fan turns once (its corners'
/// quadrant crossings, docs/reconstruction.md) uses no directed edge twice; only the
/// other vertices' halfedges are sorted.
PCL_VTS_CORE_EXPORT bool isValidSurfaceMesh(const TriangleMesh& mesh,
                                            std::string* why = nullptr,
                                            unsigned threads = 1);

/// Every interior edge is locally Delaunay: the vertex opposite across the edge is
/// not strictly inside the circumcircle (exact incircle). Together with a valid
/// triangulation of the hull this means the whole triangulation is Delaunay.
PCL_VTS_CORE_EXPORT bool isDelaunay(const TriangleMesh& mesh,
                                    std::string* why = nullptr);

/// Every vertex is used by at least one triangle.
PCL_VTS_CORE_EXPORT bool allVerticesUsed(const TriangleMesh& mesh,
                                         std::string* why = nullptr);

/// V - E + F over the triangles (isolated vertices not counted).
PCL_VTS_CORE_EXPORT long long eulerCharacteristic(const TriangleMesh& mesh);

/// Number of boundary halfedges (halfedges without twin).
PCL_VTS_CORE_EXPORT std::size_t boundaryEdgeCount(const TriangleMesh& mesh);

/// Twice the signed area of all triangles, summed (exact inputs, double sum).
PCL_VTS_CORE_EXPORT double twiceArea(const TriangleMesh& mesh);

} // namespace pcl_vts
