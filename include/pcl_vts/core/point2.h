// The 2D point every core pass works on: XY of a vertex, in double precision.
#pragma once

namespace pcl_vts {

struct Point2 {
  double x;
  double y;
};

inline bool operator==(const Point2& a, const Point2& b)
{
  return a.x == b.x && a.y == b.y;
}

inline bool operator!=(const Point2& a, const Point2& b)
{
  return !(a == b);
}

/// Strict lexicographic order (x, then y): the priority order of the tie-break rule.
inline bool lexLess(const Point2& a, const Point2& b)
{
  return a.x < b.x || (a.x == b.x && a.y < b.y);
}

} // namespace pcl_vts
