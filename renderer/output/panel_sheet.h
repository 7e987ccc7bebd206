#pragma once
/// \file panel_sheet.h
/// Pictures side by side on a sheet of paper, each labeled underneath in ink with
/// the built-in bitmap font (bitmap_font.h), as the figures of Palacios & Zhang
/// 2007 (`rosyhatch compare`).

#include "renderer/output/image.h"

#include <array>
#include <string>
#include <vector>

namespace rosy::renderer {

/// One RGB sheet: the `pictures` (all the same width w and height h, at least RGB;
/// a 4th channel is straight alpha, composited over `paper`) in a row with gaps of
/// max(4, min(w, h) / 32) px, `labels[k]` centred under picture k. Labels are about
/// 2.5% of the panel height tall, shrunk to fit the panel width; a label still too
/// wide breaks after its last ": ", and a line still too wide is clipped at the
/// panel's edges. `paper` and `ink` are linear RGB.
/// Sizes must match (checked: a mismatch is a bug in the caller).
Image panelSheet(const std::vector<Image> &pictures, const std::vector<std::string> &labels,
                 const std::array<float, 3> &paper, const std::array<float, 3> &ink);

} // namespace rosy::renderer
