// An RGB picture, the colours renderMesh marks things with, and the PNG writer: the
// bottom of the picture module (with view.h), which the rasteriser, the font and the
// PNG encoder build on without including mesh_picture.h.
#pragma once

#include <pcl_vts/core/status.h>
#include <pcl_vts/picture/export.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl_vts {

/// 3 bytes/pixel, row-major, top row first.
struct Picture {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
};

/// Colours the picture uses, for tests and legends.
struct PictureColour {
  std::uint8_t r, g, b;
};
constexpr PictureColour PICTURE_BACKGROUND{255, 255, 255};
constexpr PictureColour PICTURE_BOUNDARY{230, 0, 0};
constexpr PictureColour PICTURE_NON_MANIFOLD{230, 0, 230};
constexpr PictureColour PICTURE_MARK{20, 20, 20};
/// Back faces (seen from below: flipped triangles) are shaded from this orange.
constexpr PictureColour PICTURE_BACK_FACE{255, 140, 0};

/// Writes a truecolour 8-bit RGB PNG. Atomic: ".<name>.tmp.<pid>" in the target
/// folder, then rename; on failure the temp file is removed.
/// \return INVALID_PARAMETER for an inconsistent picture (size or rgb length),
///         IO_ERROR naming the path and the system's reason when writing fails.
PCL_VTS_PICTURE_EXPORT Status writePng(const std::string& path, const Picture& picture);

} // namespace pcl_vts
