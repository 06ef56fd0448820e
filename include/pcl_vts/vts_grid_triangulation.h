// pcl::VTSGridTriangulation: the PCL face of the VTS pipeline (vts_pipeline.h). It
// copies the selected points to doubles, calls pcl_vts::runVtsPipeline and maps the
// mesh vertices back to input_ ids; all geometry lives in the PCL-free core.
// Source: Nhan Ba Cong, 2015 thesis; Nguyen, Tran, Nhan, REV Journal 2015.
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <pcl/PolygonMesh.h>
#include <pcl/Vertices.h>
#include <pcl/point_cloud.h>
#include <pcl/surface/reconstruction.h>

#include <string>
#include <vector>

namespace pcl {

/** \brief Exact 2.5D Delaunay triangulation of an elevation surface (z = f(x, y):
 * terrain LiDAR, a DEM, a seismic horizon) by Voxel Traversal Search (VTS).
 *
 * The XY projection of the points is bucketed on a 2D grid and triangulated by
 * region growing from a seed Delaunay edge: for each open edge the third point is
 * found by visiting grid cells along the edge's discrete mediatrix and its
 * dilations, nearest circumcentre first. Predicates are exact, so the output is
 * exactly Delaunay (cocircular ties broken by symbolic perturbation) and tiles the
 * convex hull of the distinct XY positions: 2n - h - 2 triangles for n distinct
 * points, h of them on the hull (collinear hull points included).
 *
 * Output conventions:
 * - polygons are triangles whose vertex ids index the whole input cloud (as in
 *   every PCL reconstruction), also when setIndices() selected a subset;
 * - triangles are counter-clockwise seen from +z;
 * - non-finite points are skipped; points with identical XY are merged into one
 *   vertex chosen by setDuplicateRule(); both are counted in getDiagnostics().
 *
 * On bad parameters or degenerate input (fewer than 3 distinct XY positions, all
 * collinear) the polygons are empty, a PCL_ERROR names the cause, and
 * getLastStatus() returns a code a caller can test.
 *
 * \note Coordinates: float inputs are converted to double exactly, and the core is
 * translation-exact (exact predicates; any origin shift it makes is done in double),
 * so georeferenced (e.g. UTM) float clouds need no offset from the caller. Points
 * at such magnitudes are only as precise as their float storage.
 *
 * \note If you use this code in any academic work, please cite the method:
 *   Nhan Ba Cong, thesis, 2015 (VTS); and Nguyen, Tran, Nhan, "A Complete Method
 *   for Reconstructing an Elevation Surface of 3D Point Clouds", REV Journal, 2015.
 *
 * \ingroup surface
 */
template <typename PointInT>
class VTSGridTriangulation : public SurfaceReconstruction<PointInT> {
 public:
  using Ptr = shared_ptr<VTSGridTriangulation<PointInT>>;
  using ConstPtr = shared_ptr<const VTSGridTriangulation<PointInT>>;
  using PointCloudIn = pcl::PointCloud<PointInT>;

  /** \brief Constructor: no search tree is needed (the grid replaces it). */
  VTSGridTriangulation() { this->check_tree_ = false; }

  /** \brief Set the edge length of the square XY grid cells.
   * \param[in] cell_size cell edge length in input XY units (e.g. metres); 0 (the
   * default) derives it from the point density. Must be finite and >= 0; checked
   * when reconstruct() starts (INVALID_PARAMETER otherwise).
   * \note Affects speed only, never the triangulation.
   */
  inline void setCellSize(double cell_size) { cell_size_ = cell_size; }

  /** \brief Get the grid cell edge length set by the user (0 = automatic); the
   * size actually used is getDiagnostics().cell_size. */
  inline double getCellSize() const { return cell_size_; }

  /** \brief Set which point represents several points with identical XY.
   * \param[in] rule LOWEST_Z (default, terrain under vegetation), HIGHEST_Z, FIRST,
   * or MEAN_Z (the first such point is the vertex, its z is replaced by the mean
   * in the output cloud).
   */
  inline void setDuplicateRule(pcl_vts::DuplicateRule rule) { duplicate_rule_ = rule; }

  /** \brief Get the duplicate-XY rule. */
  inline pcl_vts::DuplicateRule getDuplicateRule() const { return duplicate_rule_; }

  /** \brief Set the number of threads running the third-point searches.
   * \param[in] threads 1 (default), or 0 for all hardware threads
   * \note The triangles are identical for every thread count. */
  inline void setNumberOfThreads(unsigned int threads) { threads_ = threads; }

  /** \brief Get the number of threads set (0 = all hardware threads). */
  inline unsigned int getNumberOfThreads() const { return threads_; }

  /** \brief Status of the last reconstruct() call: OK, or the code and message of
   * what stopped it (INVALID_PARAMETER, TOO_FEW_POINTS, ALL_COLLINEAR, ...). */
  inline const pcl_vts::Status& getLastStatus() const { return last_status_; }

  /** \brief Counts and timings of the last reconstruct() call: points in, non-finite
   * dropped, duplicates merged, distinct and hull vertices, triangles, cell size
   * used, seconds per stage. Counts refer to the points selected by the indices. */
  inline const pcl_vts::Diagnostics& getDiagnostics() const { return diagnostics_; }

  /** \brief Triangulate the selected points into a PolygonMesh.
   * \param[out] output the whole input cloud (z of merged MEAN_Z vertices replaced)
   * and the triangles, as ids into it.
   * \note PCL's base class dereferences input_ before checking it; this override
   * checks first, so a missing setInputCloud() gives EMPTY_INPUT, not a crash.
   */
  void reconstruct(pcl::PolygonMesh& output) override;

  /** \brief Triangulate the selected points.
   * \param[out] points a copy of the input cloud (z of merged MEAN_Z vertices
   * replaced)
   * \param[out] polygons the triangles, as ids into points
   */
  void reconstruct(PointCloudIn& points, std::vector<pcl::Vertices>& polygons) override;

  /** \brief Class name used in log lines. */
  std::string getClassName() const override { return "VTSGridTriangulation"; }

 protected:
  using SurfaceReconstruction<PointInT>::input_;
  using SurfaceReconstruction<PointInT>::indices_;

  void performReconstruction(pcl::PolygonMesh& output) override;

  void performReconstruction(PointCloudIn& points,
                             std::vector<pcl::Vertices>& polygons) override;

 private:
  /** \brief Runs the core on the points selected by indices_ and fills polygons
   * with input_ ids. On failure: status kept, PCL_ERROR logged, polygons empty.
   * \param[out] result the core's output; its source_index holds positions in
   * indices_ */
  bool triangulate(std::vector<pcl::Vertices>& polygons, pcl_vts::VtsResult& result);

  /** \brief Calls apply(input id as std::size_t, z) for every vertex whose z (as float)
   * differs from its source point's, i.e. vertices merged under MEAN_Z. */
  template <typename Apply>
  void forEachChangedZ(const pcl_vts::VtsResult& result, Apply apply) const;

  /** \brief False (status EMPTY_INPUT, logged) when no input cloud is set. */
  bool checkInput();

  /** \brief Records a failed status and logs it as [pcl::Class::method]. */
  void fail(pcl_vts::Status status, const char* method = "performReconstruction");

  double cell_size_{0.0};
  pcl_vts::DuplicateRule duplicate_rule_{pcl_vts::DuplicateRule::LOWEST_Z};
  unsigned int threads_{1};
  pcl_vts::Status last_status_;
  pcl_vts::Diagnostics diagnostics_;
};

} // namespace pcl

#ifdef PCL_NO_PRECOMPILE
#include <pcl_vts/impl/vts_grid_triangulation.hpp>
#endif
