// The one place the pipeline order is written: condition input -> grid ->
// triangulate (-> trim boundary -> fill holes, later stages). Adapters (PCL class,
// CLI) call runVtsPipeline and map vertex ids back to their own inputs.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/merge_duplicates.h>
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/reconstruct_surface.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {

/// Reconstruction options with both passes off.
inline ReconstructionOptions noPostPasses()
{
  ReconstructionOptions options;
  options.trim = false;
  options.fill = false;
  return options;
}

struct VtsOptions {
  /// Grid cell edge length in input XY units; 0 = derived from the point density
  /// (docs/decisions.md). Must be finite and >= 0.
  double cell_size = 0.0;
  DuplicateRule duplicate_rule = DuplicateRule::LOWEST_Z;
  /// Threads for the grid, the triangulation and the post-passes (it replaces
  /// reconstruction.threads); 0 = all hardware threads. The output is identical for
  /// every value.
  unsigned threads = 1;
  /// Width of the strips of grid columns grown independently (docs/algorithm.md,
  /// section 4); 0 = automatic (about 32 strips, at least 32 columns wide), else a
  /// power of two. A tuning and testing knob: the triangulation is the same for every
  /// value, only the triangle order changes.
  std::uint32_t strip_columns = 0;
  /// Cache blocks (docs/scaling.md): each block of 32 x 32 cells is triangulated with
  /// a ring of cells by Bowyer-Watson, the triangles proven final are kept and the
  /// search only grows the rest. The same triangulation, another triangle order
  /// (14-28 % faster than the search alone at 1e6 points).
  bool cache_blocks = true;
  /// Post-passes after the triangulation (docs/reconstruction.md). Off by default
  /// here, so the core returns the exact Delaunay triangulation of the hull;
  /// pcd_to_mesh turns both on unless --no-trim / --no-fill.
  ReconstructionOptions reconstruction = noPostPasses();
  /// Validate the output against its post-conditions (triangle count, twins, CCW)
  /// before returning; a failure is INTERNAL_ERROR. Cheap (linear).
  bool check_output = true;
  /// Fill VtsResult::input_to_vertex (4 bytes a point). Off: it is left empty, the
  /// rest of the result is the same; pcd_to_mesh, which does not use it, turns it off.
  bool input_map = true;
  /// Lattice fast path: when the distinct points lie on a rectilinear lattice (DEM
  /// rasters), complete lattice cells are split without any search and only the
  /// cells near missing points go through the region growing (docs/algorithm.md,
  /// section 7). The same triangles, hull and vertex positions; vertex ids follow
  /// the lattice rows instead of the grid cells. Off: always the ordinary path.
  bool lattice = true;
  /// Lattice fast path: width in lattice steps of the ring of points added around
  /// the points near missing cells before they are triangulated (section 7). A
  /// tuning and testing knob: the triangulation is the same for every value, only
  /// the number of rounds changes.
  std::uint32_t lattice_ring = 1;
  /// Lattice fast path: the pieces of a fringe of up to 2^16 points triangulated
  /// together, in one window of the cache blocks' kernel with no rounds (section 7);
  /// off, or when that window loses a triangle, piece by piece with the ring and the
  /// rounds above. A testing knob: the triangulation is the same either way.
  bool lattice_one_window = true;
};

/// Checks every option; the message names the offending value.
PCL_VTS_CORE_EXPORT Status validateOptions(const VtsOptions& options);

struct VtsResult {
  /// Vertices are the distinct XY positions (merged z applied); triangles are CCW,
  /// tiling exactly the convex hull (unless post-passes ran); halfedges give twins.
  TriangleMesh mesh;
  /// Per mesh vertex: index of the input point it came from; INVALID_ID for points
  /// inserted by hole filling (appended after the input's vertices).
  std::vector<std::uint32_t> source_index;
  /// Per input point: the mesh vertex that represents it (merged duplicates point to
  /// the same vertex), or INVALID_ID for dropped (non-finite) points. Empty when
  /// VtsOptions::input_map is off.
  std::vector<VertexId> input_to_vertex;
  /// Convex hull, CCW, as mesh vertex ids (collinear boundary points included).
  std::vector<VertexId> hull;
  Diagnostics diagnostics;
  /// What trimming and filling did (zeros when they are off); fill.inserted flags
  /// inserted vertices.
  ReconstructionDiagnostics reconstruction;
};

/// Triangulates n points given as xyz triples (3n doubles). Never throws.
/// On error, result.mesh is empty and the status says why.
PCL_VTS_CORE_EXPORT Status runVtsPipeline(const double* xyz, std::size_t n,
                                          const VtsOptions& options, VtsResult& result);

/// runVtsPipeline on the points of xyz (3 doubles a point), taking the array over:
/// once the triangulation has read it, its memory serves the post-passes' scratch
/// (resident pages instead of fresh ones: the trim's rows fit in it), and it is
/// freed before the call returns (xyz is left empty). The same result; a size
/// that is not a multiple of 3 is INVALID_PARAMETER.
PCL_VTS_CORE_EXPORT Status runVtsPipeline(std::vector<double>&& xyz,
                                          const VtsOptions& options, VtsResult& result);

} // namespace pcl_vts
