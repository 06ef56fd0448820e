// Before/after pictures of the post-passes for docs/reconstruction.md, written only
// when PCL_VTS_PICTURE_DIR is set (skipped otherwise): the raw Delaunay mesh with the
// triangles trimming removes in red, and the trimmed + filled mesh with the hole
// patches in blue and inserted points as dark dots.
#include "support/asc_reader.h"
#include "support/mesh_picture.h"
#include "support/pipeline_checks.h"
#include "support/surface_checks.h"

#include <pcl_vts/core/reconstruct_surface.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace pcl_vts {
namespace {

std::set<std::array<VertexId, 3>> triangleSet(const TriangleMesh& mesh)
{
  std::set<std::array<VertexId, 3>> set;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    std::array<VertexId, 3> key = {mesh.triangles[3 * t], mesh.triangles[3 * t + 1],
                                   mesh.triangles[3 * t + 2]};
    std::sort(key.begin(), key.end());
    set.insert(key);
  }
  return set;
}

void writeBeforeAfter(const std::string& dir, const std::string& name,
                      const std::vector<double>& xyz,
                      const ReconstructionOptions& options)
{
  const test::PipelineRun run = test::runPipeline(xyz);
  ASSERT_TRUE(run.status.ok()) << run.status.toString();
  const TriangleMesh& raw = run.result.mesh;
  TriangleMesh trimmed = raw;
  ReconstructionOptions trim_only = options;
  trim_only.fill = false;
  ReconstructionDiagnostics diagnostics;
  ASSERT_TRUE(reconstructSurface(trimmed, trim_only, diagnostics).ok());
  TriangleMesh filled = raw;
  ASSERT_TRUE(reconstructSurface(filled, options, diagnostics).ok());

  const auto kept = triangleSet(trimmed);
  std::vector<test::TriangleClass> before(raw.triangleCount(),
                                          test::TriangleClass::KEPT);
  for (std::size_t t = 0; t < raw.triangleCount(); ++t) {
    std::array<VertexId, 3> key = {raw.triangles[3 * t], raw.triangles[3 * t + 1],
                                   raw.triangles[3 * t + 2]};
    std::sort(key.begin(), key.end());
    if (!kept.count(key))
      before[t] = test::TriangleClass::REMOVED;
  }
  std::vector<test::TriangleClass> after(filled.triangleCount(),
                                         test::TriangleClass::KEPT);
  for (std::size_t t = trimmed.triangleCount(); t < filled.triangleCount(); ++t)
    after[t] = test::TriangleClass::FILLED;
  EXPECT_TRUE(
      test::writeMeshPicture(dir + "/" + name + "_before.png", raw, before, {}, 480));
  EXPECT_TRUE(test::writeMeshPicture(dir + "/" + name + "_after.png", filled, after,
                                     diagnostics.fill.inserted, 480));
}

const char* pictureDir()
{
  return std::getenv("PCL_VTS_PICTURE_DIR");
}

TEST(ReconstructionPictures, SyntheticTerrain)
{
  if (!pictureDir())
    GTEST_SKIP() << "set PCL_VTS_PICTURE_DIR to write the pictures";
  ReconstructionOptions options;
  options.fill_options.max_hole_area = 600.0;
  writeBeforeAfter(pictureDir(), "synthetic", test::makeSyntheticTerrain(7).xyz,
                   options);
}

TEST(ReconstructionPictures, SharedDems)
{
  if (!pictureDir())
    GTEST_SKIP() << "set PCL_VTS_PICTURE_DIR to write the pictures";
  for (const std::string name : {"west_bijou_gully", "zSW3"}) {
    const std::string path =
        std::string(PCL_VTS_SHARED_DATA_DIR) + "/dem/landlab/" + name + ".asc";
    if (!std::ifstream(path).good())
      continue;
    test::AsciiGrid grid;
    ASSERT_TRUE(test::readAsciiGrid(path, grid));
    writeBeforeAfter(pictureDir(), name, grid.xyz, ReconstructionOptions{});
  }
}

} // namespace
} // namespace pcl_vts
