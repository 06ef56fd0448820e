// docs_pictures OUT_DIR SHARED_DATA_DIR: the before/after pictures of the post-passes
// in docs/reconstruction.md (`make docs-pictures` writes them into docs/img). Top
// view, one camera per pair: the raw Delaunay mesh with the triangles trimming
// removes in grey; the trimmed + filled mesh with hole patches tinted blue, inserted
// points as dark dots and boundary edges red. A docs tool, not a test: it checks
// nothing but that each step succeeds; a shared file that is missing is skipped.
#include "support/synthetic_terrain.h"

#include <pcl_vts/core/reconstruct_surface.h>
#include <pcl_vts/core/vts_pipeline.h>
#include <pcl_vts/io/point_cloud_loader.h>
#include <pcl_vts/picture/mesh_picture.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace {

using namespace pcl_vts;

std::array<VertexId, 3> sortedCorners(const TriangleMesh& mesh, std::size_t t)
{
  std::array<VertexId, 3> key = {mesh.triangles[3 * t], mesh.triangles[3 * t + 1],
                                 mesh.triangles[3 * t + 2]};
  std::sort(key.begin(), key.end());
  return key;
}

/// Meshes xyz, trims and fills it, and writes <dir>/<name>_{before,after}.png.
Status writeBeforeAfter(const std::string& dir, const std::string& name,
                        const std::vector<double>& xyz,
                        const ReconstructionOptions& options)
{
  VtsResult raw;
  Status s = runVtsPipeline(xyz.data(), xyz.size() / 3, VtsOptions{}, raw);
  if (!s.ok())
    return s;
  TriangleMesh trimmed = raw.mesh;
  ReconstructionOptions trim_only = options;
  trim_only.fill = false;
  ReconstructionDiagnostics diagnostics;
  if (s = reconstructSurface(trimmed, trim_only, diagnostics); !s.ok())
    return s;
  TriangleMesh filled = raw.mesh;
  if (s = reconstructSurface(filled, options, diagnostics); !s.ok())
    return s;

  // Trimming keeps a subset of the raw triangles; filling appends its patches.
  std::set<std::array<VertexId, 3>> kept;
  for (std::size_t t = 0; t < trimmed.triangleCount(); ++t)
    kept.insert(sortedCorners(trimmed, t));
  const auto cls = [](PictureTriangleClass c) { return static_cast<std::uint8_t>(c); };
  PictureMesh before = pictureMeshOf(raw.mesh);
  before.triangle_class.assign(raw.mesh.triangleCount(),
                               cls(PictureTriangleClass::SURFACE));
  for (std::size_t t = 0; t < raw.mesh.triangleCount(); ++t)
    if (!kept.count(sortedCorners(raw.mesh, t)))
      before.triangle_class[t] = cls(PictureTriangleClass::REMOVED);
  PictureMesh after = pictureMeshOf(filled);
  after.triangle_class.assign(filled.triangleCount(),
                              cls(PictureTriangleClass::SURFACE));
  for (std::size_t t = trimmed.triangleCount(); t < filled.triangleCount(); ++t)
    after.triangle_class[t] = cls(PictureTriangleClass::FILLED);
  after.vertex_marks = diagnostics.fill.inserted;

  const PictureFrame frame = unionOf(pictureFrameOf(before), pictureFrameOf(after));
  PictureOptions view;
  view.width = 480;
  for (const auto& [suffix, mesh] :
       {std::pair{"_before.png", &before}, std::pair{"_after.png", &after}})
    if (s = writePng(dir + "/" + name + suffix, renderMesh(*mesh, frame, view));
        !s.ok())
      return s;
  std::printf("%s/%s_{before,after}.png: %zu triangles, %zu after trim and fill\n",
              dir.c_str(), name.c_str(), raw.mesh.triangleCount(),
              filled.triangleCount());
  return Status::success();
}

} // namespace

int main(int argc, char** argv)
{
  if (argc != 3) {
    std::fprintf(stderr, "usage: docs_pictures OUT_DIR SHARED_DATA_DIR\n");
    return 1;
  }
  const std::string out = argv[1], shared = argv[2];
  struct Input {
    std::string name, path; ///< path empty: the synthetic terrain
    double max_hole_area;   ///< 0: the default
  };
  const Input inputs[] = {
      {"synthetic", "", 600.0},
      {"west_bijou_gully", shared + "/dem/landlab/west_bijou_gully.asc", 0.0},
      {"zSW3", shared + "/dem/landlab/zSW3.asc", 0.0},
      {"samp11", shared + "/pcd/isprs_filtertest/samp11-utm-ground.pcd", 0.0},
  };
  int failures = 0;
  for (const Input& input : inputs) {
    std::vector<double> xyz;
    if (input.path.empty()) {
      xyz = test::makeSyntheticTerrain(7).xyz;
    } else if (!std::ifstream(input.path).good()) {
      std::printf("%s: not found, skipped\n", input.path.c_str());
      continue;
    } else {
      CloudDescription description;
      const Status s = loadPointCloud(input.path, CloudLoadOptions{}, xyz, description);
      if (!s.ok()) {
        std::fprintf(stderr, "docs_pictures: %s: %s\n", input.path.c_str(),
                     s.toString().c_str());
        ++failures;
        continue;
      }
    }
    ReconstructionOptions options;
    options.fill_options.max_hole_area = input.max_hole_area;
    const Status s = writeBeforeAfter(out, input.name, xyz, options);
    if (!s.ok()) {
      std::fprintf(stderr, "docs_pictures: %s: %s\n", input.name.c_str(),
                   s.toString().c_str());
      ++failures;
    }
  }
  return failures == 0 ? 0 : 1;
}
