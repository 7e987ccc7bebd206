#pragma once
/// \file png_write.h
/// 8-bit PNG written with libpng directly, the common output of `rosyhatch render`,
/// without loading the OpenImageIO module (image_io.h): mapping and relocating its
/// ~270 shared libraries costs more CPU time than the whole hatching stage of the
/// default scene (docs/benchmarks.md, "Whole process").
///
/// Up to 256 KiB of filtered rows the file is the same bytes OpenImageIO 2.4's PNG
/// writer produces for the spec writeImage() builds (tests/renderer/image_test.cpp
/// checks that on several images): libpng's default adaptive filters, zlib level 6
/// with the default strategy, 8 KiB IDAT chunks, then gAMA/sRGB/cHRM (sRGB, absolute
/// intent), a zero oFFs and the tEXt `oiio:ColorSpace` = `sRGB`. Larger images (a
/// 1024² render) have the same chunks, pixels and filtered rows (libpng's filter
/// choice, row by row), but their rows are filtered and deflated in segments of
/// 256 KiB in parallel, each primed with the 32 KiB before it: a valid zlib stream
/// of other bytes (a 1024² render's file about 0.2 % smaller), the same at every
/// thread count; the encoder's wall time about halves on two cores.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace rosy::renderer {

/// The PNG writePng8() writes, encoded in memory into `bytes` (replaced). False with
/// a message when the shape is not 1–4 channels of at least 1×1, when libpng rejects
/// the image (e.g. a side over its limit of 10⁶ pixels) or runs out of memory, or when
/// the file would pass `maxBytes` (then `bytes` holds what was encoded up to there).
/// libpng reports its errors by longjmp back into the encoder, which then frees
/// its state (tests/fuzz/fuzz_png.cpp drives every one of these exits).
bool encodePng8(int width, int height, int nChannels, const uint8_t *pixels, std::vector<unsigned char> &bytes,
                std::string &error, size_t maxBytes = std::numeric_limits<size_t>::max());

/// Writes `pixels` (height rows of width * nChannels bytes, 1 = grey, 2 = grey +
/// alpha, 3 = RGB, 4 = RGBA, alpha last and straight) as a PNG at `path` (created
/// or truncated). False with a message when the file cannot be written.
bool writePng8(const std::string &path, int width, int height, int nChannels, const uint8_t *pixels,
               std::string &error);

} // namespace rosy::renderer
