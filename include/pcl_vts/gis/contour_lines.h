// Contour lines of a TIN, as geometry only (no GDAL, no PCL): iso-lines of the
// piecewise-linear surface at every multiple of an interval, traced across
// triangles into polylines that close on themselves or end on the mesh boundary.
#pragma once

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/gis/export.h>
#include <pcl_vts/gis/mesh_stream.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace pcl_vts {

struct ContourLine {
  double level = 0.0;
  /// Vertices in order, higher ground on the left; a closed line repeats its first
  /// point at the end.
  std::vector<Point2> points;
  bool closed = false;
};

/// Receives each line as it is traced (levels ascending).
using ContourSink = std::function<Status(const ContourLine& line)>;

struct ContourStats {
  std::size_t levels = 0;   ///< levels that crossed the mesh
  std::size_t lines = 0;    ///< polylines handed to the sink
  std::size_t closed = 0;   ///< of which closed
  std::size_t segments = 0; ///< triangle crossings traced
};

/// Traces the contours at levels k*interval + base (k integer) strictly between
/// the lowest and the highest vertex z, or equal to the highest. A vertex whose z
/// equals a level counts as above it (symbolic rule): a triangle is crossed when
/// its lowest z < level <= its highest, exactly one segment per crossed triangle,
/// so no segment is ever duplicated and lines never branch. The crossing on an edge
/// is computed from its lower to its upper end, the same bits from both triangles
/// sharing it. Points that repeat the previous one (a line through a vertex at the
/// level) are dropped; lines left with fewer than 2 points are not emitted.
/// The mesh's halfedges must be valid (TriangleMesh::rebuildHalfedges).
PCL_VTS_GIS_EXPORT Status traceContours(const TriangleMesh& mesh, double interval,
                                        double base, const ContourSink& sink,
                                        ContourStats* stats = nullptr);

/// traceContours for a mesh that is not held (the tiled path's, read back from its
/// temporary files): the same lines with the same points, handed over in the same
/// order as traceContours gives them for the mesh with these vertices and triangles
/// in this order. The vertices go to a file in temp_folder (24 B each, mapped, pages
/// dropped as they are passed; removed at the end); the triangles are streamed twice
/// (count, then keep) and each crossing of a triangle by a level is kept as a 32 B
/// segment (level, triangle, its entry and exit edges as vertex pairs); a segment's
/// successor is the one entering by its exit edge, and the points are computed again
/// from the vertices as the lines are walked. Memory grows with the output (about 42 B
/// per crossing, each a point of a line), not with the mesh. Halfedges are not
/// needed; an edge entered twice or left twice at a level is INTERNAL_ERROR (not a
/// manifold), checked on the crossed edges only.
PCL_VTS_GIS_EXPORT Status traceContoursOutOfCore(const MeshStream& mesh,
                                                 double interval, double base,
                                                 const std::string& temp_folder,
                                                 const ContourSink& sink,
                                                 ContourStats* stats = nullptr);

} // namespace pcl_vts
