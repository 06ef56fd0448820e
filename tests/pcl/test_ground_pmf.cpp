// --ground pmf (pcl::ProgressiveMorphologicalFilter through preprocessCloud): on a
// sloped ground with a building and a tree, the defaults keep the ground and drop
// the objects; the kept points are the original doubles.
#include <pcl_vts/preprocess_cloud.h>

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>
#include <vector>

namespace pcl_vts {
namespace {

TEST(GroundPmf, KeepsTheGroundDropsABuildingAndATree)
{
  std::vector<double> xyz;
  std::set<std::tuple<double, double, double>> ground;
  std::size_t objects = 0;
  for (int j = 0; j < 80; ++j)
    for (int i = 0; i < 80; ++i) {
      const double x = 600000.25 + i, y = 5100000.5 + j;
      const double g = 200.0 + 0.05 * i + 0.3 * std::sin(0.2 * j);
      const bool building = i >= 30 && i < 45 && j >= 30 && j < 48; // 15 x 18 m
      const bool tree = std::hypot(i - 15.0, j - 60.0) < 3.0;
      const double z = building ? g + 9.0 : tree ? g + 6.0 + 0.1 * i : g;
      xyz.insert(xyz.end(), {x, y, z});
      if (building || tree)
        ++objects;
      else
        ground.insert({x, y, z});
    }
  PreprocessOptions options;
  options.ground_pmf = true;
  std::vector<PreprocessStep> steps;
  ASSERT_TRUE(preprocessCloud(xyz, options, steps).ok());
  ASSERT_FALSE(steps.empty());
  ASSERT_EQ(steps.back().name, "ground");
  std::size_t kept_ground = 0, kept_objects = 0;
  for (std::size_t k = 0; k < xyz.size(); k += 3)
    (ground.count({xyz[k], xyz[k + 1], xyz[k + 2]}) ? kept_ground : kept_objects) += 1;
  EXPECT_EQ(kept_objects, 0u) << "of " << objects << " object points";
  EXPECT_GE(kept_ground, ground.size() * 98 / 100) << "of " << ground.size();

  PreprocessOptions bad = options;
  bad.pmf_base = 1.0;
  EXPECT_EQ(validatePreprocessOptions(bad).code, StatusCode::INVALID_PARAMETER);
}

} // namespace
} // namespace pcl_vts
