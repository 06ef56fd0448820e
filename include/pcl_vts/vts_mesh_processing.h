// pcl::VTSMeshProcessing: the three-method shape of pcl::MeshProcessing
// (setInputMesh / process / performProcessing) without deriving from it, because
// MeshProcessing's bodies live in libpcl_surface (VTK dependency) while pcl_vts links
// only pcl_common/search/kdtree/io (docs/reconstruction.md, "PCL wrappers"). Also the
// PolygonMesh <-> core array conversion every post-pass shares.
#pragma once

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/export.h>

#include <pcl/PolygonMesh.h>

#include <cstddef>
#include <string>
#include <vector>

namespace pcl {

/** \brief Base of the pcl_vts mesh post-passes, shaped like pcl::MeshProcessing.
 *
 * process() copies the input header and cloud into the output, clears its polygons
 * and calls performProcessing(). On bad input the output polygons stay empty, a
 * PCL_ERROR names the cause and getLastStatus() returns a code a caller can test.
 */
class PCL_VTS_EXPORT VTSMeshProcessing {
 public:
  using PolygonMeshConstPtr = pcl::PolygonMesh::ConstPtr;

  virtual ~VTSMeshProcessing() = default;

  /** \brief Set the mesh to process (triangles, x y z fields, float or double). */
  inline void setInputMesh(const PolygonMeshConstPtr& input) { input_mesh_ = input; }

  /** \brief Get the mesh to process. */
  inline PolygonMeshConstPtr getInputMesh() const { return input_mesh_; }

  /** \brief Process the input mesh into output (may be the same object's copy).
   * \param[out] output the processed mesh: header and cloud copied from the input
   * (plus any points a pass inserts), and the new polygons. */
  void process(pcl::PolygonMesh& output);

  /** \brief Status of the last process() call. */
  inline const pcl_vts::Status& getLastStatus() const { return last_status_; }

  /** \brief Class name used in log lines. */
  virtual std::string getClassName() const = 0;

 protected:
  /** \brief The pass itself: mesh holds the input triangles (CCW, twins built),
   * output holds the copied cloud and no polygon. */
  virtual pcl_vts::Status performProcessing(pcl_vts::TriangleMesh& mesh,
                                            pcl::PolygonMesh& output) = 0;

  PolygonMeshConstPtr input_mesh_;
  pcl_vts::Status last_status_;
};

namespace vts_detail {

/** \brief Copies x, y, z of every cloud point and the triangles of a PolygonMesh
 * into core arrays. Triangles clockwise in XY are reordered counter-clockwise (the
 * core's convention) and counted in *reoriented.
 * \return INVALID_PARAMETER for a polygon that is not a triangle, an id out of range,
 *   a triangle with zero XY area (not a 2.5D surface) or a non-manifold edge;
 *   EMPTY_INPUT for a cloud without x, y, z fields. */
PCL_VTS_EXPORT pcl_vts::Status polygonMeshToArrays(const pcl::PolygonMesh& input,
                                                   pcl_vts::TriangleMesh& mesh,
                                                   std::size_t* reoriented = nullptr);

/** \brief Writes the triangles of mesh as polygons. */
PCL_VTS_EXPORT void arraysToPolygons(const pcl_vts::TriangleMesh& mesh,
                                     std::vector<pcl::Vertices>& polygons);

/** \brief Appends mesh vertices first.. to cloud: each new point is a zeroed record
 * with x, y, z set (float or double as the fields are); width grows, height = 1. */
PCL_VTS_EXPORT void appendVertices(const pcl_vts::TriangleMesh& mesh, std::size_t first,
                                   pcl::PCLPointCloud2& cloud);

/** \brief True when the cloud stores x or y as float32 (inserted points must then
 * be rounded to float before they are triangulated). */
PCL_VTS_EXPORT bool xyIsFloat(const pcl::PCLPointCloud2& cloud);

} // namespace vts_detail
} // namespace pcl
