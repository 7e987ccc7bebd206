/// \file fuzz_png.cpp
/// libFuzzer harness for the PNG writer (renderer/output/png_write.h) and its error
/// path: libpng reports errors with longjmp back into the encoder, which must free
/// its state and return a message, whatever point of the file it had reached. The
/// input bytes choose (FuzzedDataProvider):
///   - a shape: 0–5 channels (0 and 5 are invalid) and either a small image (sides
///     −1..40, so 0 and −1 are invalid) or one side over libpng's limit of 10⁶ pixels
///     (up to INT_MAX; libpng must reject it in png_set_IHDR before reading a row);
///   - a bound on the encoded size: none, or 0..8192 bytes (the encoder stops with an
///     error inside libpng's write callback, in any chunk, mid-row or in the last one);
///   - the pixels: the remaining bytes, repeated to fill the image.
///
/// Oracle (anything else, or a sanitizer report, e.g. a leak of libpng's state or a
/// read past the pixels, is a finding): an invalid shape or an oversized side gives
/// false with a one-line message starting "PNG: "; a valid image encodes without a
/// bound, and libpng's own reader gives back exactly the pixels; with a bound, the
/// encoding succeeds exactly when the file fits, with the same bytes, and otherwise
/// fails with the bound's message, having kept no more than the bound.

#include "fuzz_common.h"

#include "renderer/output/png_write.h"

#include <fuzzer/FuzzedDataProvider.h>
#include <png.h>

#include <climits>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

using namespace rosy;

namespace {

constexpr int kLibpngMaxSide = 1'000'000; // PNG_USER_WIDTH_MAX / PNG_USER_HEIGHT_MAX

void checkMessage(const std::string &error) {
    ROSY_FUZZ_ASSERT(error.rfind("PNG: ", 0) == 0 && error.size() > 5, "message: " + error);
    ROSY_FUZZ_ASSERT(error.find('\n') == std::string::npos, "one line: " + error);
}

/// The pixels libpng's simplified reader decodes from `file`, as 8-bit values of
/// the same channels; false when it cannot read the file.
bool decode(const std::vector<unsigned char> &file, int nChannels, int &width, int &height,
            std::vector<uint8_t> &pixels) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&image, file.data(), file.size())) return false;
    const png_uint_32 formats[] = {PNG_FORMAT_GRAY, PNG_FORMAT_GA, PNG_FORMAT_RGB, PNG_FORMAT_RGBA};
    image.format = formats[nChannels - 1];
    width = int(image.width);
    height = int(image.height);
    pixels.assign(PNG_IMAGE_SIZE(image), 0);
    const bool ok = png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr) != 0;
    png_image_free(&image);
    return ok;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fuzz::initOnce();
    FuzzedDataProvider in(data, size);
    const int nChannels = in.ConsumeIntegralInRange<int>(0, 5);
    const bool oversized = in.ConsumeIntegralInRange<int>(0, 7) == 0;
    int width, height;
    if (oversized) {
        const int big = in.ConsumeIntegralInRange<int>(kLibpngMaxSide + 1, INT_MAX);
        const int other = in.ConsumeIntegralInRange<int>(-1, INT_MAX);
        const bool wide = in.ConsumeBool();
        width = wide ? big : other;
        height = wide ? other : big;
    } else {
        width = in.ConsumeIntegralInRange<int>(-1, 40);
        height = in.ConsumeIntegralInRange<int>(-1, 40);
    }
    const bool bounded = in.ConsumeBool();
    const size_t maxBytes = bounded ? in.ConsumeIntegralInRange<size_t>(0, 8192) : std::numeric_limits<size_t>::max();
    const std::vector<uint8_t> tail = in.ConsumeRemainingBytes<uint8_t>();
    const bool valid = nChannels >= 1 && nChannels <= 4 && width >= 1 && height >= 1 && !oversized;
    // An oversized image gets one row's worth of a small side at most: the encoder
    // must not read it (ASan reports a read past the buffer).
    const size_t nBytes = valid ? size_t(width) * size_t(height) * size_t(nChannels) : 64;
    std::vector<uint8_t> pixels(nBytes);
    for (size_t i = 0; i < nBytes; ++i) pixels[i] = tail.empty() ? uint8_t(i * 37) : tail[i % tail.size()];

    std::vector<unsigned char> file;
    std::string error;
    const bool ok = renderer::encodePng8(width, height, nChannels, pixels.data(), file, error, maxBytes);
    if (!valid) {
        ROSY_FUZZ_ASSERT(!ok, "an invalid shape was encoded: " + std::to_string(width) + "x" +
                                  std::to_string(height) + "x" + std::to_string(nChannels));
        checkMessage(error);
        return 0;
    }
    std::vector<unsigned char> full;
    std::string fullError;
    ROSY_FUZZ_ASSERT(renderer::encodePng8(width, height, nChannels, pixels.data(), full, fullError),
                     "a valid image failed: " + fullError);
    ROSY_FUZZ_ASSERT(ok == (full.size() <= maxBytes), "bound " + std::to_string(maxBytes) + ", file " +
                                                         std::to_string(full.size()) + ": " + error);
    if (ok) {
        ROSY_FUZZ_ASSERT(file == full, "a bounded encoding that fits differs from the unbounded one");
    } else {
        checkMessage(error);
        ROSY_FUZZ_ASSERT(error == "PNG: the encoded image is larger than its bound", "bound message: " + error);
        ROSY_FUZZ_ASSERT(file.size() <= maxBytes, "kept past the bound");
    }
    int w = 0, h = 0;
    std::vector<uint8_t> back;
    ROSY_FUZZ_ASSERT(decode(full, nChannels, w, h, back), "libpng cannot read the file back");
    ROSY_FUZZ_ASSERT(w == width && h == height && back == pixels, "the pixels read back differ");
    return 0;
}
