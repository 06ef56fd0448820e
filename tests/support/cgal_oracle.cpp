// CGAL Delaunay_triangulation_2 with vertex info = input index, range insertion
// (spatially sorted by CGAL), finite faces read back as index triples.
#include "support/cgal_oracle.h"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Projection_traits_xy_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <utility>

namespace pcl_vts {
namespace test {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Traits = CGAL::Projection_traits_xy_3<Kernel>;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, Traits>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Traits, Tds>;

std::vector<IndexTriangle> triangulate(const std::vector<Point2>& points, double sign)
{
  std::vector<std::pair<Kernel::Point_3, std::uint32_t>> input;
  input.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    input.emplace_back(Kernel::Point_3(sign * points[i].x, sign * points[i].y, 0.0),
                       static_cast<std::uint32_t>(i));
  Delaunay dt;
  dt.insert(input.begin(), input.end());
  std::vector<IndexTriangle> out;
  if (dt.dimension() < 2)
    return out;
  out.reserve(dt.number_of_faces());
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f)
    out.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  return out;
}

} // namespace

std::vector<IndexTriangle> cgalDelaunay(const std::vector<Point2>& points)
{
  return triangulate(points, 1.0);
}

std::vector<IndexTriangle> cgalDelaunayMirrored(const std::vector<Point2>& points)
{
  return triangulate(points, -1.0);
}

std::vector<IndexTriangle> canonicalTriangles(std::vector<IndexTriangle> triangles)
{
  for (IndexTriangle& t : triangles) {
    const auto smallest = std::min_element(t.begin(), t.end());
    std::rotate(t.begin(), smallest, t.end());
  }
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

std::vector<IndexTriangle> canonicalTriangles(const std::vector<std::uint32_t>& flat,
                                              const std::vector<std::uint32_t>& map)
{
  std::vector<IndexTriangle> triangles;
  triangles.reserve(flat.size() / 3);
  for (std::size_t i = 0; i + 2 < flat.size(); i += 3)
    triangles.push_back({map[flat[i]], map[flat[i + 1]], map[flat[i + 2]]});
  return canonicalTriangles(std::move(triangles));
}

} // namespace test
} // namespace pcl_vts
