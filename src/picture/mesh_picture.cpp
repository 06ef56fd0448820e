// renderMesh and the picture helpers. The camera is picture_camera.h, the z-buffer
// picture_raster.h, the caption font bitmap_font.h, the PNG file png_writer.cpp.
#include "bitmap_font.h"
#include "picture_camera.h"
#include "picture_colours.h"
#include "picture_raster.h"

#include <pcl_vts/picture/mesh_picture.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace pcl_vts {

using picture_detail::PictureCamera;
using picture_detail::Raster;
using picture_detail::ScreenPoint;
using namespace picture_detail::colours;

namespace {

constexpr PictureColour TEXT_COLOUR{30, 30, 30};
constexpr int SUPERSAMPLE_BELOW = 4096; // wider pictures are drawn without 2x2

bool finiteVertex(const PictureMesh& mesh, std::uint32_t v)
{
  return 3 * static_cast<std::size_t>(v) + 2 < mesh.xyz.size() &&
         std::isfinite(mesh.xyz[3 * v]) && std::isfinite(mesh.xyz[3 * v + 1]) &&
         std::isfinite(mesh.xyz[3 * v + 2]);
}

/// Colour of triangle t: class colour, hypsometric by mean z, hill-shaded by its normal
/// with z exaggerated like the camera's; facing down (flipped) = orange.
PictureColour triangleColour(const PictureMesh& mesh, std::size_t t,
                             const PictureCamera& camera)
{
  const double* p[3];
  for (int k = 0; k < 3; ++k)
    p[k] = &mesh.xyz[3 * static_cast<std::size_t>(mesh.triangles[3 * t + k])];
  const double zs = camera.zScale();
  // Differences in double before anything else: UTM-sized coordinates stay exact.
  const double ux = p[1][0] - p[0][0], uy = p[1][1] - p[0][1],
               uz = (p[1][2] - p[0][2]) * zs;
  const double vx = p[2][0] - p[0][0], vy = p[2][1] - p[0][1],
               vz = (p[2][2] - p[0][2]) * zs;
  double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
  const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
  if (len > 0 && std::isfinite(len)) {
    nx /= len;
    ny /= len;
    nz /= len;
  } else { // no area in 3D: shade as flat ground
    nx = 0;
    ny = 0;
    nz = 1;
  }
  if (nz < 0) // facing down: a flipped triangle
    return shaded(PICTURE_BACK_FACE, 0.45 + 0.55 * hillshade(-nx, -ny, -nz));
  const double factor = 0.30 + 0.85 * hillshade(nx, ny, nz);
  const std::uint8_t cls = mesh.triangle_class.size() == mesh.triangles.size() / 3
                               ? mesh.triangle_class[t]
                               : 0;
  if (cls == static_cast<std::uint8_t>(PictureTriangleClass::REMOVED))
    return shaded(REMOVED_GREY, factor);
  const double z_range = camera.zMax() - camera.zMin();
  const double z_mean = (p[0][2] + p[1][2] + p[2][2]) / 3.0;
  const double t01 = z_range > 0 ? (z_mean - camera.zMin()) / z_range : 0.5;
  PictureColour base = rampColour(t01);
  if (cls == static_cast<std::uint8_t>(PictureTriangleClass::FILLED))
    base = blend(base, FILLED_BLUE, 0.7);
  return shaded(base, factor);
}

/// A white picture saying why nothing was drawn (under the caption, if any).
Picture messagePicture(const PictureOptions& options, const std::string& why)
{
  const int width = std::clamp(options.width, picture_detail::MIN_PICTURE_WIDTH,
                               picture_detail::MAX_PICTURE_WIDTH);
  const std::string text =
      (options.caption.empty() ? std::string() : options.caption + "\n") +
      "nothing to draw: " + why;
  const int scale = picture_detail::textScaleFor(width);
  Picture picture;
  picture.width = width;
  picture.height = std::max(width / 4, picture_detail::textHeight(text, scale) + 16);
  picture.rgb.assign(3 * static_cast<std::size_t>(width) * picture.height, 255);
  picture_detail::drawText(picture, 8, 8, text, scale, TEXT_COLOUR);
  return picture;
}

void drawEdges(Raster& raster, const PictureMesh& mesh,
               const std::vector<std::uint32_t>& pairs, const PictureCamera& camera,
               int factor, double bias, PictureColour colour)
{
  const int brush = factor == 1 ? 2 : 3; // >= 1.5 output pixels: a solid core survives
  for (std::size_t i = 0; i + 1 < pairs.size(); i += 2) {
    if (!finiteVertex(mesh, pairs[i]) || !finiteVertex(mesh, pairs[i + 1]))
      continue;
    ScreenPoint a = camera.project(mesh.xyz[3 * std::size_t{pairs[i]}],
                                   mesh.xyz[3 * std::size_t{pairs[i]} + 1],
                                   mesh.xyz[3 * std::size_t{pairs[i]} + 2]);
    ScreenPoint b = camera.project(mesh.xyz[3 * std::size_t{pairs[i + 1]}],
                                   mesh.xyz[3 * std::size_t{pairs[i + 1]} + 1],
                                   mesh.xyz[3 * std::size_t{pairs[i + 1]} + 2]);
    for (ScreenPoint* s : {&a, &b})
      *s = {s->column * factor, s->row * factor, s->depth * factor};
    raster.drawLine(a, b, brush, bias, colour);
  }
}

} // namespace

PictureMesh pictureMeshOf(const TriangleMesh& mesh)
{
  PictureMesh out;
  out.xyz.reserve(3 * mesh.vertexCount());
  for (std::size_t v = 0; v < mesh.vertexCount() && v < mesh.xy.size(); ++v)
    out.xyz.insert(out.xyz.end(), {mesh.xy[v].x, mesh.xy[v].y, mesh.z[v]});
  out.triangles = mesh.triangles;
  if (mesh.halfedges.size() == mesh.triangles.size())
    for (HalfedgeId e = 0; e < mesh.halfedges.size(); ++e)
      if (mesh.halfedges[e] == INVALID_ID)
        out.boundary_edges.insert(out.boundary_edges.end(),
                                  {mesh.triangles[e], mesh.triangles[nextHalfedge(e)]});
  return out;
}

PictureFrame pictureFrameOf(const PictureMesh& mesh)
{
  constexpr double INF = std::numeric_limits<double>::infinity();
  PictureFrame frame{{INF, INF, INF}, {-INF, -INF, -INF}};
  for (std::size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
    if (!finiteVertex(mesh, mesh.triangles[t]) ||
        !finiteVertex(mesh, mesh.triangles[t + 1]) ||
        !finiteVertex(mesh, mesh.triangles[t + 2]))
      continue; // renderMesh skips it too
    for (int k = 0; k < 3; ++k) {
      const double* p = &mesh.xyz[3 * static_cast<std::size_t>(mesh.triangles[t + k])];
      for (int d = 0; d < 3; ++d) {
        frame.min[d] = std::min(frame.min[d], p[d]);
        frame.max[d] = std::max(frame.max[d], p[d]);
      }
    }
  }
  return frame;
}

bool picturePixelOf(const PictureFrame& frame, const PictureOptions& options, double x,
                    double y, double z, double& column, double& row)
{
  const PictureCamera camera(frame, options);
  if (!camera.valid())
    return false;
  const ScreenPoint s = camera.project(x, y, z);
  column = s.column;
  row = s.row;
  return true;
}

double pictureZScaleOf(const PictureFrame& frame, const PictureOptions& options)
{
  const PictureCamera camera(frame, options);
  return camera.valid() ? camera.zScale() : 1.0;
}

Picture renderMesh(const PictureMesh& mesh, const PictureFrame& frame,
                   const PictureOptions& options)
{
  if (mesh.triangles.size() < 3)
    return messagePicture(options, "the mesh has no triangle");
  const PictureCamera camera(frame, options);
  if (!camera.valid())
    return messagePicture(options, isEmpty(frame)
                                       ? "the frame is empty (no finite vertex)"
                                       : "the frame has no horizontal extent");
  const int factor = camera.width() < SUPERSAMPLE_BELOW ? 2 : 1;
  Raster raster(camera.width() * factor, camera.height() * factor, PICTURE_BACKGROUND);
  auto screen = [&](std::uint32_t v) {
    const ScreenPoint s =
        camera.project(mesh.xyz[3 * std::size_t{v}], mesh.xyz[3 * std::size_t{v} + 1],
                       mesh.xyz[3 * std::size_t{v} + 2]);
    return ScreenPoint{s.column * factor, s.row * factor, s.depth * factor};
  };
  for (std::size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
    const std::uint32_t a = mesh.triangles[t], b = mesh.triangles[t + 1],
                        c = mesh.triangles[t + 2];
    if (!finiteVertex(mesh, a) || !finiteVertex(mesh, b) || !finiteVertex(mesh, c))
      continue;
    const ScreenPoint sa = screen(a), sb = screen(b), sc = screen(c);
    if (raster.mayCover(sa, sb, sc))
      raster.fillTriangle(sa, sb, sc, triangleColour(mesh, t / 3, camera));
  }
  // From above nothing of a 2.5D surface hides an edge, so lines go on top; from the
  // side, hills do: depth-test with a bias of a few samples against z-fighting.
  const double bias = options.view == PictureView::TOP
                          ? std::numeric_limits<double>::infinity()
                          : 3.0 * factor;
  drawEdges(raster, mesh, mesh.boundary_edges, camera, factor, bias, PICTURE_BOUNDARY);
  drawEdges(raster, mesh, mesh.non_manifold_edges, camera, factor, bias,
            PICTURE_NON_MANIFOLD);
  const std::size_t n_vertices = mesh.xyz.size() / 3;
  for (std::size_t v = 0; v < mesh.vertex_marks.size() && v < n_vertices; ++v)
    if (mesh.vertex_marks[v] && finiteVertex(mesh, static_cast<std::uint32_t>(v)))
      raster.drawDot(screen(static_cast<std::uint32_t>(v)), 1.2 * factor, bias,
                     PICTURE_MARK);
  Picture picture = raster.downsample(factor);
  if (!options.caption.empty()) {
    const int scale = picture_detail::textScaleFor(picture.width);
    const int margin =
        (camera.captionHeight() - picture_detail::textHeight(options.caption, scale)) /
        2;
    picture_detail::drawText(picture, margin, margin, options.caption, scale,
                             TEXT_COLOUR);
  }
  return picture;
}

Picture besideEachOther(const std::vector<Picture>& pictures, int gap_pixels)
{
  auto drawable = [](const Picture& p) {
    return p.width > 0 && p.height > 0 &&
           p.rgb.size() == 3 * static_cast<std::size_t>(p.width) * p.height;
  };
  Picture out;
  const int gap = std::max(0, gap_pixels);
  for (const Picture& p : pictures)
    if (drawable(p)) {
      out.width += p.width + (out.width > 0 ? gap : 0);
      out.height = std::max(out.height, p.height);
    }
  out.rgb.assign(3 * static_cast<std::size_t>(out.width) * out.height, 255);
  int left = 0;
  for (const Picture& p : pictures) {
    if (!drawable(p))
      continue;
    for (int r = 0; r < p.height; ++r)
      std::copy_n(
          p.rgb.begin() + 3 * static_cast<std::ptrdiff_t>(r) * p.width, 3 * p.width,
          out.rgb.begin() + 3 * (static_cast<std::ptrdiff_t>(r) * out.width + left));
    left += p.width + gap;
  }
  return out;
}

} // namespace pcl_vts
