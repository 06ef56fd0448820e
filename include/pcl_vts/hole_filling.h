// pcl::HoleFilling: the PCL face of pcl_vts::fillHoles (fill_holes.h) on a
// pcl::PolygonMesh. Thin adapter: convert, call the core, append the inserted points
// to the cloud, write the triangles back. Thesis section 4.3; docs/reconstruction.md.
#pragma once

#include <pcl_vts/core/fill_holes.h>
#include <pcl_vts/export.h>
#include <pcl_vts/vts_mesh_processing.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl {

/** \brief Fills the holes (inner boundary loops) of a 2.5D triangle mesh up to an
 * area limit: new points on a hexagonal lattice at the local spacing, z from a
 * thin-plate spline through the rim and two rings of vertices around it, and a
 * constrained Delaunay patch that meets the rim edges exactly.
 *
 * The output cloud is the input cloud followed by the inserted points (x, y, z set,
 * every other field zero; the cloud becomes unorganized, height 1);
 * getInsertedFlags() marks them. When the cloud stores x or y as float, inserted
 * points are rounded to float before they are triangulated, so the stored mesh is
 * the one that was checked. Holes larger than setMaxHoleArea(), holes through a pinch
 * vertex and holes around another piece of the mesh stay open (counted).
 * \ingroup surface
 */
class PCL_VTS_EXPORT HoleFilling : public VTSMeshProcessing {
 public:
  /** \brief Largest hole area filled, XY units squared; 0 (default) = 1000 times
   * the squared median point spacing. Finite, >= 0. */
  inline void setMaxHoleArea(double area) { options_.max_hole_area = area; }
  inline double getMaxHoleArea() const { return options_.max_hole_area; }

  /** \brief Distance between inserted points; 0 (default) = the rim's spacing. */
  inline void setPointSpacing(double spacing) { options_.point_spacing = spacing; }
  inline double getPointSpacing() const { return options_.point_spacing; }

  /** \brief How inserted points get z (default: thin-plate spline). */
  inline void setZMethod(pcl_vts::HoleZMethod method) { options_.z_method = method; }
  inline pcl_vts::HoleZMethod getZMethod() const { return options_.z_method; }

  /** \brief Counts of the last process(): holes found, filled, left open, skipped,
   * points inserted, triangles added, area limit used. */
  inline const pcl_vts::FillResult& getResult() const { return result_; }

  /** \brief Per output point: 1 for an inserted point, 0 for an input point. */
  inline const std::vector<std::uint8_t>& getInsertedFlags() const
  {
    return result_.inserted;
  }

  std::string getClassName() const override { return "HoleFilling"; }

 protected:
  pcl_vts::Status performProcessing(pcl_vts::TriangleMesh& mesh,
                                    pcl::PolygonMesh& output) override;

 private:
  pcl_vts::FillOptions options_;
  pcl_vts::FillResult result_;
};

} // namespace pcl
