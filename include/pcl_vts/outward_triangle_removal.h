// pcl::OutwardTriangleRemoval: the PCL face of pcl_vts::trimOutwardTriangles
// (trim_outward_triangles.h) on a pcl::PolygonMesh. Thin adapter: convert, call the
// core, write the kept triangles back. Thesis section 4.2; docs/reconstruction.md.
#pragma once

#include <pcl_vts/core/trim_outward_triangles.h>
#include <pcl_vts/export.h>
#include <pcl_vts/vts_mesh_processing.h>

#include <string>

namespace pcl {

/** \brief Removes the outward triangles of a 2.5D triangle mesh (z = f(x, y)): the
 * long triangles a Delaunay triangulation of the convex hull lays over concave parts
 * of the outline and over data voids.
 *
 * A triangle is oversized when its longest XY edge exceeds setTrimFactor() times the
 * local point spacing (median nearest-neighbour distance around its vertices), or
 * setMaxEdgeLength() when that is set. Oversized triangles are peeled from the
 * boundary inwards until nothing changes, and voids are opened from inside
 * (setOpenVoids()); a removal that would pinch a vertex is undone. The output cloud
 * is the input cloud (points left without triangles stay, counted in getResult());
 * polygons are the kept triangles, counter-clockwise seen from +z.
 *
 * Works on any triangle mesh whose XY projection is a planar triangulation, e.g.
 * pcl::VTSGridTriangulation's output.
 * \ingroup surface
 */
class PCL_VTS_EXPORT OutwardTriangleRemoval : public VTSMeshProcessing {
 public:
  /** \brief Set the oversize factor against the local point spacing (default 4,
   * must be finite and > 1; checked when process() runs). */
  inline void setTrimFactor(double factor) { options_.trim_factor = factor; }
  inline double getTrimFactor() const { return options_.trim_factor; }

  /** \brief Set an absolute longest-edge limit in XY units; 0 (default) = none. */
  inline void setMaxEdgeLength(double length) { options_.max_edge = length; }
  inline double getMaxEdgeLength() const { return options_.max_edge; }

  /** \brief Also open interior data voids into holes (default true). */
  inline void setOpenVoids(bool open) { options_.open_voids = open; }
  inline bool getOpenVoids() const { return options_.open_voids; }

  /** \brief Counts of the last process(): triangles removed, points left without a
   * triangle, removals undone to stay manifold, spacing measured. */
  inline const pcl_vts::TrimResult& getResult() const { return result_; }

  std::string getClassName() const override { return "OutwardTriangleRemoval"; }

 protected:
  pcl_vts::Status performProcessing(pcl_vts::TriangleMesh& mesh,
                                    pcl::PolygonMesh& output) override;

 private:
  pcl_vts::TrimOptions options_;
  pcl_vts::TrimResult result_;
};

} // namespace pcl
