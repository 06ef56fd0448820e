// Status codes at their edges: the 32-bit capacity limits are CAPACITY_EXCEEDED (not a
// rejected option) with the limit in the message, and the one check of length-like
// parameters rejects negatives, NaN and infinities alike.
#include <pcl_vts/core/fill_holes.h>
#include <pcl_vts/core/grid_triangulator.h>
#include <pcl_vts/core/status.h>
#include <pcl_vts/core/trim_outward_triangles.h>
#include <pcl_vts/core/vts_pipeline.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace pcl_vts {
namespace {

TEST(StatusCodes, CapacityCodeHasItsName)
{
  EXPECT_STREQ(statusCodeName(StatusCode::CAPACITY_EXCEEDED), "CAPACITY_EXCEEDED");
  const Status s = Status::error(StatusCode::CAPACITY_EXCEEDED, "too many");
  EXPECT_EQ(s.toString(), "CAPACITY_EXCEEDED: too many");
}

TEST(StatusCodes, TriangleCapacityIsExactAtTheLimit)
{
  EXPECT_EQ(MAX_MESH_TRIANGLES, 715827882u);
  // 2n - h - 2 triangles: n = 357913944 with 4 hull vertices fills the limit exactly.
  EXPECT_TRUE(checkTriangleCapacity(357913944, 4).ok());
  const Status over = checkTriangleCapacity(357913945, 4);
  EXPECT_EQ(over.code, StatusCode::CAPACITY_EXCEEDED);
  EXPECT_EQ(over.message, "357913945 points need 715827884 triangles, beyond the limit "
                          "of 715827882 (32-bit halfedge ids, about 357.9 million "
                          "points); split the input into tiles");
  // More hull vertices, fewer triangles: the same count fits again.
  EXPECT_TRUE(checkTriangleCapacity(357913945, 6).ok());
  // Small and degenerate counts never underflow into a huge need.
  EXPECT_TRUE(checkTriangleCapacity(3, 3).ok());
  EXPECT_TRUE(checkTriangleCapacity(0, 0).ok());
  EXPECT_TRUE(checkTriangleCapacity(1, 5).ok());
}

TEST(StatusCodes, MorePointsThanVertexIdsIsCapacityNotAnOption)
{
  // The count is rejected before a single point is read: three doubles are enough.
  const double xyz[3] = {0.0, 0.0, 0.0};
  VtsResult result;
  const Status s = runVtsPipeline(xyz, std::size_t{0xffffffffu}, VtsOptions{}, result);
  EXPECT_EQ(s.code, StatusCode::CAPACITY_EXCEEDED) << s.toString();
  EXPECT_EQ(s.message, "4294967295 points exceed the 32-bit vertex ids (at most "
                       "4294967294 points)");
}

TEST(StatusCodes, FiniteNonNegativeCheck)
{
  for (const double ok : {0.0, -0.0, 1e-310, 1.0, 1e300})
    EXPECT_TRUE(checkFiniteNonNegative("v", ok).ok()) << ok;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const struct {
    double value;
    const char* text;
  } bad[] = {
      {-1.0, "-1"}, {-1e-310, "-1e-310"}, {nan, "nan"}, {inf, "inf"}, {-inf, "-inf"}};
  for (const auto& b : bad) {
    const Status s = checkFiniteNonNegative("cell_size", b.value, " (0 = automatic)");
    EXPECT_EQ(s.code, StatusCode::INVALID_PARAMETER) << b.text;
    EXPECT_EQ(s.message, std::string("cell_size = ") + b.text +
                             " must be finite and >= 0 (0 = automatic)");
  }
  EXPECT_EQ(checkFiniteNonNegative("voxel", -2.5).message,
            "voxel = -2.5 must be finite and >= 0");
}

TEST(StatusCodes, EveryLengthOptionUsesTheCheck)
{
  // Each option that is a length or an area goes through the one check: same words.
  VtsOptions vts;
  vts.cell_size = -3.0;
  EXPECT_EQ(validateOptions(vts).message,
            "cell_size = -3 must be finite and >= 0 (0 = automatic)");
  TrimOptions trim;
  trim.max_edge = std::numeric_limits<double>::infinity();
  EXPECT_EQ(validateTrimOptions(trim).message,
            "max_edge = inf must be finite and >= 0 (0 = no limit)");
  FillOptions fill;
  fill.point_spacing = -1.0;
  EXPECT_EQ(validateFillOptions(fill).message,
            "point_spacing = -1 must be finite and >= 0 (0 = automatic)");
  fill = FillOptions{};
  fill.max_hole_area = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(validateFillOptions(fill).message,
            "max_hole_area = nan must be finite and >= 0 (0 = automatic)");
}

} // namespace
} // namespace pcl_vts
