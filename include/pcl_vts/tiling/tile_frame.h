// The fixed quadtree every tiled job hangs on: a square frame over the exact bounding
// box of the kept points, cut into 2^16 x 2^16 code cells numbered in Morton order.
// Blocks (the unit of loading) and tiles (the unit of work) are quadtree nodes at
// coarser levels, so each is a contiguous range of codes, and the canonical vertex
// order (code, then x, then y) is the same for every tiling and for the in-memory run.
#pragma once
#include <pcl_vts/core/point2.h>
#include <pcl_vts/tiling/export.h>

#include <cstdint>

namespace pcl_vts {

/// An axis-aligned rectangle in input units.
struct Rect {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct PCL_VTS_TILING_EXPORT TileFrame {
  static constexpr int CODE_LEVEL = 16;
  static constexpr std::uint32_t CODE_CELLS = 1u << CODE_LEVEL;

  double min_x = 0, min_y = 0;
  double side = 0;  ///< edge of the square frame (the larger extent of the box)
  double scale = 0; ///< CODE_CELLS / side

  /// The frame of a box; a box of zero extent gets side 1 (one code cell holds all).
  static TileFrame fromBounds(double min_x, double min_y, double max_x, double max_y);

  /// Code-cell column of x: floor((x - min_x) * scale) clamped to the frame. Monotone
  /// in x, so a point's cell never depends on which run computes it.
  std::uint32_t column(double x) const { return clampCell((x - min_x) * scale); }
  std::uint32_t row(double y) const { return clampCell((y - min_y) * scale); }
  /// Morton code (x bits even, y bits odd) of the code cell holding (x, y).
  std::uint32_t code(double x, double y) const; // inline below
  std::uint32_t code(const Point2& p) const { return code(p.x, p.y); }

  /// Node of `level` (0 = the whole frame) holding code cell `code`, Morton-numbered.
  static std::uint32_t nodeOf(std::uint32_t code, int level)
  {
    return level == 0 ? 0u : code >> (2 * (CODE_LEVEL - level));
  }
  /// The rectangle of node `node` at `level`, widened by more than the rounding of
  /// column()/row(): every point whose code falls in the node lies inside it.
  Rect nodeRect(int level, std::uint32_t node) const;

 private:
  static std::uint32_t clampCell(double t)
  {
    if (!(t > 0))
      return 0;
    return t >= CODE_CELLS - 1 ? CODE_CELLS - 1 : static_cast<std::uint32_t>(t);
  }
};

/// Canonical vertex order: Morton code, then x, then y.
inline bool canonicalLess(std::uint32_t code_a, const Point2& a, std::uint32_t code_b,
                          const Point2& b)
{
  if (code_a != code_b)
    return code_a < code_b;
  return a.x < b.x || (a.x == b.x && a.y < b.y);
}

/// Spreads the 16 low bits of v to the even bit positions (inline: a Morton code a
/// vertex in canonicalMesh's loop).
inline std::uint32_t spreadBits(std::uint32_t v)
{
  v &= 0xFFFFu;
  v = (v | (v << 8)) & 0x00FF00FFu;
  v = (v | (v << 4)) & 0x0F0F0F0Fu;
  v = (v | (v << 2)) & 0x33333333u;
  v = (v | (v << 1)) & 0x55555555u;
  return v;
}
/// The inverse of spreadBits: gathers the even bits.
PCL_VTS_TILING_EXPORT std::uint32_t gatherBits(std::uint32_t v);

inline std::uint32_t TileFrame::code(double x, double y) const
{
  return spreadBits(column(x)) | (spreadBits(row(y)) << 1);
}

} // namespace pcl_vts
