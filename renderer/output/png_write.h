#pragma once
/// \file png_write.h
/// 8-bit PNG written with libpng directly, the common output of `rosyhatch render`,
/// without loading the OpenImageIO module (image_io.h): mapping and relocating its
/// ~270 shared libraries costs more CPU time than the whole hatching stage of the
/// default scene (docs/benchmarks.md, "Whole process").
///
/// The file is the same bytes OpenImageIO 2.4's PNG writer produces for the spec
/// writeImage() builds (tests/renderer/png_write_test.cpp checks that on several
/// images): libpng's default adaptive filters, zlib level 6 with the default
/// strategy, 8 KiB IDAT chunks, then gAMA/sRGB/cHRM (sRGB, absolute intent), a
/// zero oFFs and the tEXt `oiio:ColorSpace` = `sRGB`.

#include <cstdint>
#include <string>

namespace rosy::renderer {

/// Writes `pixels` (height rows of width * nChannels bytes, 1 = grey, 2 = grey +
/// alpha, 3 = RGB, 4 = RGBA, alpha last and straight) as a PNG at `path` (created
/// or truncated). False with a message when the file cannot be written.
bool writePng8(const std::string &path, int width, int height, int nChannels, const uint8_t *pixels,
               std::string &error);

} // namespace rosy::renderer
