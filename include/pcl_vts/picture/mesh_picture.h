// Pictures of 2.5D triangle meshes for people: a z-buffered software rasteriser
// (hill shading from the north-west over a hypsometric colour ramp, top or oblique
// view) and a truecolour PNG writer (zlib's deflate, linked privately). PCL-free, so
// tools and test binaries link it cheaply (target pcl_vts::picture). The top of the
// module: picture types and writePng in image.h, view and frame in view.h.
#pragma once

#include <pcl_vts/core/mesh_arrays.h>
#include <pcl_vts/picture/export.h>
#include <pcl_vts/picture/image.h>
#include <pcl_vts/picture/view.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {

/// Values of PictureMesh::triangle_class.
enum class PictureTriangleClass : std::uint8_t { SURFACE = 0, REMOVED = 1, FILLED = 2 };

/// A mesh to draw: plain arrays, any triangle soup (need not be manifold).
struct PictureMesh {
  /// x, y, z per vertex (world units; may be UTM-sized).
  std::vector<double> xyz;
  /// 3 vertex ids per triangle.
  std::vector<std::uint32_t> triangles;
  /// Empty, or per triangle: 0 surface, 1 removed, 2 filled (PictureTriangleClass).
  std::vector<std::uint8_t> triangle_class;
  /// Empty, or per vertex: non-zero drawn as a dot.
  std::vector<std::uint8_t> vertex_marks;
  /// Vertex-id pairs, drawn red.
  std::vector<std::uint32_t> boundary_edges;
  /// Vertex-id pairs, drawn magenta.
  std::vector<std::uint32_t> non_manifold_edges;
};

/// The triangles of a core mesh (vertices xy + z), with boundary_edges taken from its
/// halfedges (the edges without a twin); no classes, no marks.
PCL_VTS_PICTURE_EXPORT PictureMesh pictureMeshOf(const TriangleMesh& mesh);

/// Box of the finite vertices used by triangles (all +inf/-inf when there is none:
/// isEmpty() then holds).
PCL_VTS_PICTURE_EXPORT PictureFrame pictureFrameOf(const PictureMesh& mesh);

/// Draws mesh as seen through frame. Never fails: degenerate input (no triangle, an
/// empty frame or one without horizontal extent) gives a white picture whose text
/// says why; triangles, edges and marks with a non-finite or out-of-range vertex are
/// skipped. options.width is clamped to 16..8192 and the height to 2 x width (long
/// strips are scaled to fit). Linear in the number of triangles plus pixels.
PCL_VTS_PICTURE_EXPORT Picture renderMesh(const PictureMesh& mesh,
                                          const PictureFrame& frame,
                                          const PictureOptions& options);

/// Where renderMesh(mesh, frame, options) draws the world point (x, y, z): column and
/// row in pixels, fractional (0, 0 is the top-left corner of the top-left pixel, so
/// pixel (i, j) covers [i, i+1) x [j, j+1)). False when the frame is empty or flat
/// (renderMesh then draws only a message).
PCL_VTS_PICTURE_EXPORT bool picturePixelOf(const PictureFrame& frame,
                                           const PictureOptions& options, double x,
                                           double y, double z, double& column,
                                           double& row);

/// The vertical exaggeration renderMesh applies for this frame and options (OBLIQUE
/// geometry, and hill shading in both views): options.z_scale when > 0, else relief
/// about 1/4 of the horizontal extent, between 1 and 20. 1 for an empty frame.
PCL_VTS_PICTURE_EXPORT double pictureZScaleOf(const PictureFrame& frame,
                                              const PictureOptions& options);

/// Tiles pictures left to right with white gaps; the result is as tall as the
/// tallest (shorter ones are padded white at the bottom).
PCL_VTS_PICTURE_EXPORT Picture besideEachOther(const std::vector<Picture>& pictures,
                                               int gap_pixels);

} // namespace pcl_vts
