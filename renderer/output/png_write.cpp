/// \file png_write.cpp
/// writePng8() (png_write.h): libpng with the settings of OpenImageIO 2.4's writer.

#include "renderer/output/png_write.h"

#include <png.h>
#include <zlib.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cstring>
#include <new>
#include <vector>

namespace rosy::renderer {
namespace {

/// The encoded file in memory, its bound and libpng's last error message.
struct PngSink {
    std::vector<unsigned char> *bytes = nullptr;
    size_t maxBytes = 0;
    char message[256] = {};
};

void appendBytes(png_structp png, png_bytep data, size_t n) {
    auto *sink = static_cast<PngSink *>(png_get_io_ptr(png));
    // No C++ exception may cross libpng's C frames: failures go through png_error().
    // (png_error() longjmps: never from inside the catch handler.)
    const bool fits = n <= sink->maxBytes - sink->bytes->size();
    bool stored = false;
    if (fits) {
        try {
            sink->bytes->insert(sink->bytes->end(), data, data + n);
            stored = true;
        } catch (const std::bad_alloc &) {
        }
    }
    if (!stored) png_error(png, fits ? "out of memory for the encoded image" : "the encoded image is larger than its bound");
}

void flushNothing(png_structp) {}

[[noreturn]] void onError(png_structp png, png_const_charp message) {
    auto *sink = static_cast<PngSink *>(png_get_error_ptr(png));
    std::snprintf(sink->message, sizeof sink->message, "%s", message ? message : "libpng error");
    png_longjmp(png, 1);
}

void onWarning(png_structp, png_const_charp) {}

/// Encodes into sink->bytes; false (sink->message set) on a libpng error. Plain C
/// objects only in this frame: libpng leaves it with longjmp on errors.
bool encode(PngSink *sink, int width, int height, int nChannels, const uint8_t *pixels) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, sink, onError, onWarning);
    if (!png) {
        std::snprintf(sink->message, sizeof sink->message, "libpng: out of memory");
        return false;
    }
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        if (!info) std::snprintf(sink->message, sizeof sink->message, "libpng: out of memory");
        png_destroy_write_struct(&png, info ? &info : nullptr);
        return false;
    }
    png_set_write_fn(png, sink, appendBytes, flushNothing);
    // What OpenImageIO 2.4 sets: zlib level 6, default strategy; libpng's own
    // default filter choice (adaptive, all five filters).
    png_set_compression_level(png, 6);
    png_set_compression_strategy(png, Z_DEFAULT_STRATEGY);
    const int colorType = nChannels == 1   ? PNG_COLOR_TYPE_GRAY
                          : nChannels == 2 ? PNG_COLOR_TYPE_GRAY_ALPHA
                          : nChannels == 3 ? PNG_COLOR_TYPE_RGB
                                           : PNG_COLOR_TYPE_RGB_ALPHA;
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, colorType, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_ABSOLUTE);
    png_set_oFFs(png, info, 0, 0, PNG_OFFSET_PIXEL);
    png_text text{};
    char key[] = "oiio:ColorSpace";
    char value[] = "sRGB";
    text.compression = PNG_TEXT_COMPRESSION_NONE;
    text.key = key;
    text.text = value;
    text.text_length = std::strlen(value);
    png_set_text(png, info, &text, 1);
    png_write_info(png, info);
    const size_t rowBytes = size_t(width) * size_t(nChannels);
    for (int y = 0; y < height; ++y) png_write_row(png, pixels + size_t(y) * rowBytes);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

} // namespace

bool encodePng8(int width, int height, int nChannels, const uint8_t *pixels, std::vector<unsigned char> &bytes,
                std::string &error, size_t maxBytes) {
    bytes.clear();
    if (nChannels < 1 || nChannels > 4 || width < 1 || height < 1) {
        error = "PNG: unsupported image shape";
        return false;
    }
    PngSink sink;
    sink.bytes = &bytes;
    sink.maxBytes = maxBytes;
    // A first guess at the size (a quarter of the pixels' bytes; capped, so that a
    // shape libpng will reject allocates nothing large).
    const double guess = double(width) * double(height) * double(nChannels) / 4 + 4096;
    bytes.reserve(size_t(std::min({guess, double(maxBytes), double(size_t(1) << 28)})));
    if (!encode(&sink, width, height, nChannels, pixels)) {
        error = std::string("PNG: ") + sink.message;
        return false;
    }
    return true;
}

bool writePng8(const std::string &path, int width, int height, int nChannels, const uint8_t *pixels,
               std::string &error) {
    std::vector<unsigned char> bytes;
    if (!encodePng8(width, height, nChannels, pixels, bytes, error)) return false;
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) {
        error = std::string("cannot open for writing: ") + std::strerror(errno);
        return false;
    }
    const unsigned char *p = bytes.data();
    size_t left = bytes.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            error = std::string("write failed: ") + std::strerror(n < 0 ? errno : ENOSPC);
            ::close(fd);
            return false;
        }
        p += n;
        left -= size_t(n);
    }
    if (::close(fd) != 0) {
        error = std::string("write failed: ") + std::strerror(errno);
        return false;
    }
    return true;
}

} // namespace rosy::renderer
