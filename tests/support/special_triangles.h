// Random triangles for the trim's clearance tests: ordinary ones far from the
// origin, at scales from 1e-40 to 1e40, and the cases where the clearance's figures
// need care (obtuse, degenerate, non-finite, tiny, huge).
#pragma once
#include <pcl_vts/core/mesh_arrays.h>

#include <random>

namespace pcl_vts {
namespace test {

/// The kinds specialTriangle draws: 0 ordinary, 1 obtuse (c near the middle of ab),
/// 2 degenerate (a repeated corner or three collinear ones), 3 a special coordinate
/// (0, -0, 1e-31 ... 1e160, NaN, +-inf), 4 tiny and 5 huge without an origin.
constexpr int SPECIAL_TRIANGLE_KINDS = 6;

/// A triangle of `kind` into p, drawn from random.
void specialTriangle(std::mt19937_64& random, int kind, Point2 (&p)[3]);

} // namespace test
} // namespace pcl_vts
