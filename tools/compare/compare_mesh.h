// The two arrays every part of compare_methods speaks: the input points and a method's
// mesh, both in one local frame (the input's offset removed in double, so that the
// float-based PCL methods see small coordinates). PCL-free.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_vts {
namespace compare {

/// Input points: xyz doubles (3 per point) in the local frame; offset is what was
/// subtracted (world = local + offset).
struct PointSet {
  std::vector<double> xyz;
  double offset[3] = {0.0, 0.0, 0.0};
  std::size_t size() const { return xyz.size() / 3; }
};

/// A method's output: any triangle soup (need not be manifold or oriented).
struct CompareMesh {
  std::vector<double> xyz;              ///< 3 per vertex, local frame
  std::vector<std::uint32_t> triangles; ///< 3 vertex ids per triangle
  /// Per vertex: the input point it is, or -1 for a vertex the method created
  /// (Poisson, hole filling). Empty when the method does not say.
  std::vector<std::int32_t> source;
  std::size_t vertexCount() const { return xyz.size() / 3; }
  std::size_t triangleCount() const { return triangles.size() / 3; }
};

} // namespace compare
} // namespace pcl_vts
