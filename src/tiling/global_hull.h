// The convex hull of every point of a tiled job, known before any tile is meshed:
// outside it there is no point, so the slivers of huge circumdisks that triangles
// along the hull have beyond it are known empty, and a loaded hull edge on it is
// final. Without it, tiles on the boundary of the data load most blocks along it.
#pragma once
#include <pcl_vts/core/point2.h>
#include <pcl_vts/tiling/tile_frame.h>

#include <vector>

namespace pcl_vts {

/// Strict convex hull (no collinear vertices), counter-clockwise, of points sorted
/// lexicographically (x, then y); exact orientation tests. Fewer than 3 distinct or
/// all collinear: the extreme points (one or two).
std::vector<Point2> hullOfSorted(const std::vector<Point2>& sorted);

/// The hull of any points (sorts a copy).
std::vector<Point2> hullOf(std::vector<Point2> points);

/// True when p lies inside or on the convex CCW polygon (exact).
bool insideOrOnHull(const std::vector<Point2>& hull, const Point2& p);

/// What a block's box keeps inside the hull.
struct ClippedBox {
  bool inside = true;          ///< the whole box lies inside the hull (no clipping)
  std::vector<Point2> polygon; ///< otherwise: box ∩ hull grown by a rounding margin
  /// Exact points spanning box ∩ hull for orientation tests: the box corners inside
  /// the hull, the hull vertices inside the box, and both ends of every hull edge
  /// that crosses the box.
  std::vector<Point2> spanning;
};

/// Clips a box by the hull. `margin` (input units) grows the hull before clipping the
/// polygon, so points on the hull stay strictly inside the float polygon.
ClippedBox clipBox(const std::vector<Point2>& hull, const Rect& box, double margin);

} // namespace pcl_vts
