// Triangles binned by their XY bounding box into a uniform grid: exact nearest
// triangle in 3D for a query point (rings of cells around the query until the ring's
// XY distance exceeds the best 3D distance found: a triangle outside the rings is at
// least that far in XY, hence in 3D), and the triangles whose box holds an XY point.
// PCL-free.
#pragma once

#include "compare_mesh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace compare {

/// Euclidean distance from p to the closed triangle abc (3 doubles each); exact up to
/// rounding, any triangle shape (degenerate ones included).
double pointTriangleDistance(const double* p, const double* a, const double* b,
                             const double* c);

class TriangleGrid {
 public:
  /// Bins mesh's triangles. The grid covers the mesh's box grown to hold
  /// [min_x, max_x] x [min_y, max_y] too (the queries' box), with about two triangles
  /// per cell. The mesh must outlive the grid.
  TriangleGrid(const CompareMesh& mesh, double min_x, double min_y, double max_x,
               double max_y);

  /// Distance from p (xyz) to the nearest triangle; +inf when the mesh has none.
  /// Also the triangle's id when triangle is not null.
  double nearestDistance(const double* p, std::uint32_t* triangle = nullptr) const;

  /// Calls fn(t) for every triangle whose XY box's cell range holds cell of (x, y)
  /// (a superset of the triangles containing (x, y)). Points outside the grid: none.
  template <class Fn>
  void forEachInCell(double x, double y, Fn fn) const
  {
    long cx, cy;
    if (!cellOf(x, y, cx, cy))
      return;
    const std::size_t cell = static_cast<std::size_t>(cy) * nx_ + cx;
    for (std::uint32_t k = start_[cell]; k < start_[cell + 1]; ++k)
      fn(items_[k]);
  }

  /// Cell ranges of a triangle's box, for pairwise tests.
  void cellRange(std::uint32_t triangle, long& x0, long& y0, long& x1, long& y1) const;
  template <class Fn>
  void forEachInCellIndex(long cx, long cy, Fn fn) const
  {
    const std::size_t cell = static_cast<std::size_t>(cy) * nx_ + cx;
    for (std::uint32_t k = start_[cell]; k < start_[cell + 1]; ++k)
      fn(items_[k]);
  }

 private:
  bool cellOf(double x, double y, long& cx, long& cy) const;
  const double* vertex(std::uint32_t v) const { return &mesh_.xyz[3 * v]; }

  const CompareMesh& mesh_;
  double x0_ = 0.0, y0_ = 0.0, cell_ = 1.0;
  long nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> start_; ///< nx*ny + 1 offsets into items_
  std::vector<std::uint32_t> items_; ///< triangle ids, grouped by cell
};

} // namespace compare
} // namespace pcl_vts
