// Before/after pictures of the post-passes for docs/reconstruction.md, written only
// when PCL_VTS_PICTURE_DIR is set (skipped otherwise) by the library's renderer
// (mesh_picture.h), top view, one camera for both: the raw Delaunay mesh with the
// triangles trimming removes in grey, and the trimmed + filled mesh with the hole
// patches tinted blue, inserted points as dark dots and boundary edges in red.
#include "support/asc_reader.h"
#include "support/pipeline_checks.h"
#include "support/surface_checks.h"

#include <pcl_vts/core/reconstruct_surface.h>
#include <pcl_vts/picture/mesh_picture.h>

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
  PictureMesh before = pictureMeshOf(raw);
  before.triangle_class.assign(
      raw.triangleCount(), static_cast<std::uint8_t>(PictureTriangleClass::SURFACE));
  for (std::size_t t = 0; t < raw.triangleCount(); ++t) {
    std::array<VertexId, 3> key = {raw.triangles[3 * t], raw.triangles[3 * t + 1],
                                   raw.triangles[3 * t + 2]};
    std::sort(key.begin(), key.end());
    if (!kept.count(key))
      before.triangle_class[t] =
          static_cast<std::uint8_t>(PictureTriangleClass::REMOVED);
  }
  PictureMesh after = pictureMeshOf(filled);
  after.triangle_class.assign(filled.triangleCount(),
                              static_cast<std::uint8_t>(PictureTriangleClass::SURFACE));
  for (std::size_t t = trimmed.triangleCount(); t < filled.triangleCount(); ++t)
    after.triangle_class[t] = static_cast<std::uint8_t>(PictureTriangleClass::FILLED);
  after.vertex_marks = diagnostics.fill.inserted;
  const PictureFrame frame = unionOf(pictureFrameOf(before), pictureFrameOf(after));
  PictureOptions view;
  view.width = 480;
  EXPECT_TRUE(
      writePng(dir + "/" + name + "_before.png", renderMesh(before, frame, view)).ok());
  EXPECT_TRUE(
      writePng(dir + "/" + name + "_after.png", renderMesh(after, frame, view)).ok());
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
