// A 5x7 pixel font (printable ASCII) for picture captions: no font files, no FreeType.
#pragma once

#include <pcl_vts/picture/image.h>

#include <string>

namespace pcl_vts {
namespace picture_detail {

/// Pixel size of one font dot for a picture this wide: 1, or 2 from 640 pixels on.
int textScaleFor(int picture_width);

/// Height in pixels of text ('\n' separates lines) drawn at this scale.
int textHeight(const std::string& text, int scale);

/// Draws text with its top-left corner at (column, row), clipped to the picture;
/// characters outside printable ASCII are drawn as '?'.
void drawText(Picture& picture, int column, int row, const std::string& text, int scale,
              PictureColour colour);

} // namespace picture_detail
} // namespace pcl_vts
