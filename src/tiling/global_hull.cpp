// Global convex hull and box clipping for the known-space tests (global_hull.h).
#include "global_hull.h"

#include <pcl_vts/core/predicates.h>

#include <algorithm>
#include <cmath>

namespace pcl_vts {
namespace {

bool lexLessXy(const Point2& a, const Point2& b)
{
  return a.x < b.x || (a.x == b.x && a.y < b.y);
}

/// Sutherland-Hodgman step: keeps the part of `polygon` left of the directed line
/// a -> b shifted outward (to its right) by `margin`.
std::vector<Point2> clipLeftOf(const std::vector<Point2>& polygon, const Point2& a,
                               const Point2& b, double margin)
{
  const double ex = b.x - a.x, ey = b.y - a.y;
  const double length = std::sqrt(ex * ex + ey * ey);
  const auto side = [&](const Point2& p) { // > 0 left, signed distance plus margin
    return (ex * (p.y - a.y) - ey * (p.x - a.x)) / length + margin;
  };
  std::vector<Point2> out;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Point2& p = polygon[i];
    const Point2& q = polygon[(i + 1) % polygon.size()];
    const double sp = side(p), sq = side(q);
    if (sp >= 0)
      out.push_back(p);
    if ((sp >= 0) != (sq >= 0)) {
      const double t = sp / (sp - sq);
      out.push_back({p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)});
    }
  }
  return out;
}

} // namespace

std::vector<Point2> hullOfSorted(const std::vector<Point2>& p)
{
  std::vector<Point2> unique;
  for (const Point2& q : p)
    if (unique.empty() || !(unique.back() == q))
      unique.push_back(q);
  const std::size_t n = unique.size();
  if (n < 3)
    return unique;
  std::vector<Point2> hull(2 * n);
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) { // lower chain
    while (k >= 2 && orient2d(hull[k - 2], hull[k - 1], unique[i]) != Sign::POSITIVE)
      --k;
    hull[k++] = unique[i];
  }
  for (std::size_t i = n - 1, lower = k + 1; i-- > 0;) { // upper chain
    while (k >= lower &&
           orient2d(hull[k - 2], hull[k - 1], unique[i]) != Sign::POSITIVE)
      --k;
    hull[k++] = unique[i];
  }
  hull.resize(k - 1);
  if (hull.size() < 3) // all collinear: the two extremes
    return {unique.front(), unique.back()};
  return hull;
}

std::vector<Point2> hullOf(std::vector<Point2> points)
{
  std::sort(points.begin(), points.end(), lexLessXy);
  return hullOfSorted(points);
}

bool insideOrOnHull(const std::vector<Point2>& hull, const Point2& p)
{
  if (hull.size() < 3)
    return false;
  for (std::size_t i = 0; i < hull.size(); ++i)
    if (orient2d(hull[i], hull[(i + 1) % hull.size()], p) == Sign::NEGATIVE)
      return false;
  return true;
}

ClippedBox clipBox(const std::vector<Point2>& hull, const Rect& box, double margin)
{
  ClippedBox clipped;
  const Point2 corners[4] = {
      {box.x0, box.y0}, {box.x1, box.y0}, {box.x1, box.y1}, {box.x0, box.y1}};
  bool all_inside = hull.size() >= 3;
  for (const Point2& c : corners)
    all_inside = all_inside && insideOrOnHull(hull, c);
  if (all_inside)
    return clipped;
  clipped.inside = false;
  if (hull.size() < 3) { // a degenerate hull: keep the box (nothing is known outside)
    clipped.polygon.assign(corners, corners + 4);
    clipped.spanning.assign(corners, corners + 4);
    return clipped;
  }
  clipped.polygon.assign(corners, corners + 4);
  for (std::size_t i = 0; i < hull.size() && !clipped.polygon.empty(); ++i)
    clipped.polygon =
        clipLeftOf(clipped.polygon, hull[i], hull[(i + 1) % hull.size()], margin);
  for (const Point2& c : corners)
    if (insideOrOnHull(hull, c))
      clipped.spanning.push_back(c);
  const auto inBox = [&](const Point2& p) {
    return p.x >= box.x0 && p.x <= box.x1 && p.y >= box.y0 && p.y <= box.y1;
  };
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Point2& a = hull[i];
    const Point2& b = hull[(i + 1) % hull.size()];
    // An edge whose bounding box meets the box may cross it: keep both ends.
    if (std::max(a.x, b.x) >= box.x0 && std::min(a.x, b.x) <= box.x1 &&
        std::max(a.y, b.y) >= box.y0 && std::min(a.y, b.y) <= box.y1) {
      clipped.spanning.push_back(a);
      clipped.spanning.push_back(b);
    } else if (inBox(a)) {
      clipped.spanning.push_back(a);
    }
  }
  return clipped;
}

} // namespace pcl_vts
