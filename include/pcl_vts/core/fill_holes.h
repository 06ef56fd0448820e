// Hole filling (thesis section 4.3): every inner boundary loop (boundary_loops.h)
// enclosing at most max_hole_area is filled with new points on a hexagonal lattice
// at the local spacing, kept away from the rim; their z comes from a thin-plate spline
// through the rim and the rings of vertices around it; the hole is triangulated as a
// constrained Delaunay patch meeting the rim edges exactly. docs/reconstruction.md.
#pragma once

#include <pcl_vts/core/export.h>
#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace pcl_vts {

/// How inserted points get their z.
enum class HoleZMethod {
  THIN_PLATE_SPLINE, ///< smooth surface through the rim rings (default)
  FLAT_RIM_MEAN      ///< mean z of the rim vertices: for comparison only
};

struct FillOptions {
  /// Holes whose area (XY, input units squared) exceeds this stay open (a lake, a
  /// quarry); 0 = automatic: AUTO_HOLE_AREA_FACTOR * spacing^2 with the mesh's
  /// median spacing. Finite, >= 0.
  double max_hole_area = 0.0;
  /// Distance between inserted points; 0 = the median local spacing of the rim
  /// vertices. Finite, >= 0.
  double point_spacing = 0.0;
  /// Inserted points keep at least rim_clearance * point spacing from every rim
  /// edge. Finite, in [0.1, 1].
  double rim_clearance = 0.5;
  /// Rings of vertices around the rim that feed the z fit (the rim itself is ring
  /// 0); in [0, 4].
  std::size_t rim_rings = 2;
  HoleZMethod z_method = HoleZMethod::THIN_PLATE_SPLINE;
  /// Round inserted x, y (and z) to float before any geometric test, so that a
  /// caller storing float coordinates (PCL clouds) gets exactly the mesh that was
  /// checked. Points that collapse onto another after rounding are dropped.
  bool snap_to_float = false;

  /// 500 spacing^2: a disc of about 25 point spacings across.
  static constexpr double AUTO_HOLE_AREA_FACTOR = 500.0;
  /// At most this many samples feed one spline (evenly subsampled above).
  static constexpr std::size_t MAX_SPLINE_SAMPLES = 600;
};

/// Checks every option; the message names the offending value.
PCL_VTS_CORE_EXPORT Status validateFillOptions(const FillOptions& options);

struct FillResult {
  std::size_t holes_found = 0;     ///< inner boundary loops
  std::size_t holes_filled = 0;    ///< patched
  std::size_t holes_left_open = 0; ///< larger than max_hole_area
  /// Not fillable as a simple polygon: the loop passes a vertex twice, or another
  /// piece of the mesh lies inside it.
  std::size_t holes_skipped = 0;
  std::size_t points_inserted = 0;
  std::size_t triangles_added = 0;
  double max_hole_area = 0.0; ///< the limit actually used (0 when no hole)
  /// Per vertex of the output mesh: 1 for an inserted point, 0 for an input vertex.
  std::vector<std::uint8_t> inserted;
};

/// Fills the holes of mesh in place.
/// \param[in,out] mesh CCW triangles, consistent halfedges, edge-manifold. Input
///   vertices keep their ids; inserted vertices are appended; triangles are appended
///   after the input ones; halfedges rebuilt.
/// Post-conditions: every filled loop is gone; edge-manifold, CCW, consistent twins.
/// Deterministic.
PCL_VTS_CORE_EXPORT Status fillHoles(TriangleMesh& mesh, const FillOptions& options,
                                     FillResult& result);

/// What a part of a mesh does not show about the whole (the tiled path fills holes
/// on the triangles around them only).
struct MeshPart {
  /// The whole mesh's median spacing (PointSpacing::global_median).
  double global_spacing = 0.0;
  /// False for a twin-less halfedge that the part cut, not a boundary of the whole;
  /// a loop counts when all its halfedges are real. (May also say false for real
  /// boundaries that touch no hole, such as the outline far from any.)
  std::function<bool(HalfedgeId)> real_boundary;
};

/// fillHoles on a part of a mesh holding every triangle around each vertex within
/// rim_rings + 1 rings of every real boundary loop: the holes are found, measured,
/// filled and given z exactly as in the whole mesh, because fillHoles depends on
/// positions only (where a loop starts, the order of the spline samples); loops
/// through cut edges are ignored. part == nullptr: the whole mesh (fillHoles).
PCL_VTS_CORE_EXPORT Status fillHolesOfPart(TriangleMesh& mesh,
                                           const FillOptions& options,
                                           const MeshPart* part, FillResult& result);

} // namespace pcl_vts
