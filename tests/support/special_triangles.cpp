#include "support/special_triangles.h"

#include <cmath>
#include <iterator>
#include <limits>

namespace pcl_vts {
namespace test {

void specialTriangle(std::mt19937_64& random, int kind, Point2 (&p)[3])
{
  constexpr double INF = std::numeric_limits<double>::infinity();
  const double specials[] = {0.0,   -0.0,  1e-31,
                             1e-29, 1e30,  1e31,
                             1e155, 1e160, std::numeric_limits<double>::quiet_NaN(),
                             INF,   -INF};
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double scale =
      std::pow(10.0, std::uniform_int_distribution<int>(-40, 40)(random));
  const Point2 origin{1e6 * unit(random), 1e6 * unit(random)};
  for (Point2& q : p)
    q = {origin.x + scale * unit(random), origin.y + scale * unit(random)};
  switch (kind) {
  case 1: // obtuse: c near the middle of ab
    p[2] = {0.5 * (p[0].x + p[1].x) + 1e-3 * scale * unit(random),
            0.5 * (p[0].y + p[1].y) + 1e-3 * scale * unit(random)};
    break;
  case 2: // degenerate: a repeated corner or three collinear ones
    p[2] = random() % 2 ? p[0] : Point2{2 * p[1].x - p[0].x, 2 * p[1].y - p[0].y};
    break;
  case 3: // a special coordinate
    (random() % 2 ? p[random() % 3].x : p[random() % 3].y) =
        specials[random() % std::size(specials)];
    break;
  case 4: // tiny, without an origin
    for (Point2& q : p)
      q = {scale * 1e-25 * unit(random), scale * 1e-25 * unit(random)};
    break;
  case 5: // huge, without an origin
    for (Point2& q : p)
      q = {scale * 1e118 * unit(random), scale * 1e118 * unit(random)};
    break;
  default:
    break;
  }
}

} // namespace test
} // namespace pcl_vts
