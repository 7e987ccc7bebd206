#pragma once
/// \file bitmap_font.h
/// A small built-in bitmap font for labels drawn into images (the panels of
/// `rosyhatch compare`), so a picture with text needs no font installed. Glyphs
/// are 5x7 pixels above the baseline plus two rows of descenders, advancing 6
/// pixels; printable ASCII letters, digits and `-+=().,:/%'` and space. A
/// character without a glyph is drawn as a hollow box, so it shows rather than
/// vanishing.

#include "renderer/output/image.h"

#include <array>
#include <string>

namespace rosy::renderer {

/// Rows of one glyph cell at scale 1: 7 above the baseline, 2 below.
constexpr int kFontGlyphRows = 9;

/// Width in pixels of `text` drawn at integer `scale` >= 1 (every font pixel a
/// scale x scale block), without the gap after the last glyph; 0 for "".
int textWidthPx(const std::string &text, int scale);

/// Draws `text` with the top-left corner of its first glyph cell at pixel (x, y)
/// (y down), every font pixel a `scale` x `scale` block in linear RGB `colour` on
/// channels 0-2 of `image`. Only columns in [clipX0, clipX1) and inside the image
/// are touched; alpha and other channels are left as they are.
void drawText(Image &image, const std::string &text, int x, int y, int scale, const std::array<float, 3> &colour,
              int clipX0, int clipX1);

} // namespace rosy::renderer
