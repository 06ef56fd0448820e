// Picture strips of a comparison (compare_pictures.h).
#include "compare_pictures.h"

#include <algorithm>
#include <limits>

namespace pcl_vts {
namespace compare {

constexpr std::size_t MAX_DOTS = 1500;

PictureFrame frameOfPoints(const PointSet& points)
{
  PictureFrame frame;
  for (int k = 0; k < 3; ++k) {
    frame.min[k] = std::numeric_limits<double>::infinity();
    frame.max[k] = -std::numeric_limits<double>::infinity();
  }
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      frame.min[k] = std::min(frame.min[k], points.xyz[3 * i + k]);
      frame.max[k] = std::max(frame.max[k], points.xyz[3 * i + k]);
    }
  return frame;
}

MethodPictures renderMethod(const CompareMesh* mesh, const TopologyCounts* topology,
                            const PictureFrame& frame, int width,
                            const std::string& caption)
{
  PictureMesh picture;
  if (mesh) {
    picture.xyz = mesh->xyz;
    picture.triangles = mesh->triangles;
    const std::size_t nv = mesh->vertexCount();
    std::vector<std::uint8_t> used(nv, 0);
    for (std::uint32_t v : mesh->triangles)
      used[v] = 1;
    // Points of the input that the method left out (vertex-based methods only).
    if (mesh->source.size() == nv) {
      picture.vertex_marks.assign(nv, 0);
      std::size_t marked = 0;
      for (std::size_t v = 0; v < nv; ++v) {
        picture.vertex_marks[v] = mesh->source[v] >= 0 && !used[v] ? 1 : 0;
        marked += picture.vertex_marks[v];
      }
      if (marked > MAX_DOTS) // a blanket of dots would hide the surface
        picture.vertex_marks.clear();
      // Triangles with a vertex of their own (hole filling) are "filled".
      const bool vertex_based = std::any_of(mesh->source.begin(), mesh->source.end(),
                                            [](std::int32_t s) { return s >= 0; });
      if (vertex_based) {
        picture.triangle_class.assign(mesh->triangleCount(), 0);
        for (std::size_t t = 0; t < mesh->triangleCount(); ++t)
          for (int k = 0; k < 3; ++k)
            if (mesh->source[mesh->triangles[3 * t + k]] < 0)
              picture.triangle_class[t] =
                  static_cast<std::uint8_t>(PictureTriangleClass::FILLED);
      }
    }
    if (topology) {
      picture.boundary_edges = topology->boundary_edge_list;
      picture.non_manifold_edges = topology->non_manifold_edge_list;
    }
  }
  MethodPictures out;
  PictureOptions options;
  options.width = width;
  options.caption = caption;
  options.view = PictureView::TOP;
  const double dx = frame.max[0] - frame.min[0], dy = frame.max[1] - frame.min[1];
  if (dx > 0.0 && dy > dx)
    options.width = std::max(64, static_cast<int>(width * dx / dy));
  out.top = renderMesh(picture, frame, options);
  options.width = width;
  options.view = PictureView::OBLIQUE;
  out.oblique = renderMesh(picture, frame, options);
  return out;
}

Status writePictureStrips(const std::string& dir, const std::string& name,
                          const std::vector<MethodPictures>& pictures)
{
  std::vector<Picture> top, oblique;
  for (const MethodPictures& p : pictures) {
    top.push_back(p.top);
    oblique.push_back(p.oblique);
  }
  constexpr int GAP = 6;
  if (Status s = writePng(dir + "/" + name + "_top.png", besideEachOther(top, GAP));
      !s.ok())
    return s;
  return writePng(dir + "/" + name + "_oblique.png", besideEachOther(oblique, GAP));
}

} // namespace compare
} // namespace pcl_vts
