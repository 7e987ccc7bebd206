/// \file png_write.cpp
/// writePng8() (png_write.h): libpng with the settings of OpenImageIO 2.4's writer;
/// above one segment of filtered rows, the image data compressed in parallel.

#include "renderer/output/png_write.h"

#include "core/parallel.h"

#include <png.h>
#include <zlib.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
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

/// The filtered rows of a large image are compressed in segments of this many bytes
/// (the last one shorter), each primed with the 32 KiB before it; the split depends
/// only on the image, never on the thread count. Smaller images go through libpng.
constexpr size_t kSegmentBytes = size_t(256) << 10;
constexpr size_t kWindowBytes = size_t(32) << 10;
constexpr size_t kIdatBytes = 8192; // libpng's IDAT size (its zlib output buffer)

/// libpng's weight of a filtered byte for its adaptive choice: |v| as a signed byte.
inline size_t filterWeight(unsigned v) { return v < 128 ? v : 256 - v; }

inline uint8_t paeth(int a, int b, int c) {
    const int pa = std::abs(b - c), pb = std::abs(a - c), pc = std::abs(a + b - 2 * c);
    return uint8_t(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

/// One row filtered as libpng 1.6 does with all five filters: each candidate's
/// residuals summed with filterWeight(), the smallest sum kept, ties to the lower
/// filter type. Writes the filter byte then the `n` residuals to `out`; `prev` is
/// the row above (zeros for the first); `scratch` holds 4 n bytes.
void filterRow(const uint8_t *row, const uint8_t *prev, size_t n, int bpp, uint8_t *out, uint8_t *scratch) {
    const size_t k = size_t(bpp);
    uint8_t *sub = scratch, *up = scratch + n, *avg = scratch + 2 * n, *pae = scratch + 3 * n;
    for (size_t i = 0; i < k; ++i) {
        sub[i] = row[i];
        up[i] = uint8_t(row[i] - prev[i]);
        avg[i] = uint8_t(row[i] - (prev[i] >> 1));
        pae[i] = uint8_t(row[i] - prev[i]); // a = c = 0: the predictor is b
    }
    for (size_t i = k; i < n; ++i) {
        sub[i] = uint8_t(row[i] - row[i - k]);
        up[i] = uint8_t(row[i] - prev[i]);
        avg[i] = uint8_t(row[i] - ((int(row[i - k]) + int(prev[i])) >> 1));
        pae[i] = uint8_t(row[i] - paeth(row[i - k], prev[i], prev[i - k]));
    }
    const uint8_t *candidates[5] = {row, sub, up, avg, pae};
    int best = 0;
    size_t bestSum = 0;
    for (int type = 0; type < 5; ++type) {
        size_t sum = 0;
        const uint8_t *r = candidates[type];
        for (size_t i = 0; i < n; ++i) sum += filterWeight(r[i]);
        if (type == 0 || sum < bestSum) {
            bestSum = sum;
            best = type;
        }
    }
    out[0] = uint8_t(best);
    std::memcpy(out + 1, candidates[best], n);
}

/// Deflates `in` into `out` (appended) with `z`, growing `out` as needed; true when
/// zlib returned `want` with all input taken.
bool deflateAll(z_stream &z, const uint8_t *in, size_t n, int flush, int want, std::vector<uint8_t> &out) {
    z.next_in = const_cast<Bytef *>(in);
    z.avail_in = uInt(n);
    int rc = Z_OK;
    do {
        const size_t used = out.size();
        out.resize(used + std::max<size_t>(n / 4, 4096));
        z.next_out = out.data() + used;
        z.avail_out = uInt(out.size() - used);
        rc = deflate(&z, flush);
        out.resize(out.size() - z.avail_out);
    } while (rc == Z_OK && (z.avail_in != 0 || z.avail_out == 0));
    return rc == want && z.avail_in == 0;
}

/// The image data of a large image, or empty when the image is small (libpng's own
/// rows then) or zlib cannot allocate. Rows are grouped into segments of about
/// kSegmentBytes of filtered data; each segment, in parallel, filters its rows
/// (libpng's choice per row, filterRow()) and deflates them (zlib level 6, default
/// strategy, 32 KiB window, as libpng) primed with the 32 KiB of filtered rows before
/// it, ending on a byte boundary (a sync flush; the last one finishes the stream).
/// The parts follow one zlib header and end with the Adler-32 of all filtered rows.
/// The grouping depends on the image only, never on the thread count.
std::vector<uint8_t> compressedImageData(int width, int height, int nChannels, const uint8_t *pixels) {
    const size_t rowBytes = size_t(width) * size_t(nChannels), lineBytes = rowBytes + 1;
    if (lineBytes * size_t(height) <= kSegmentBytes) return {};
    const int64_t rowsPerSegment = int64_t(std::max<size_t>(1, kSegmentBytes / lineBytes));
    const int64_t rowsBack = int64_t((kWindowBytes + lineBytes - 1) / lineBytes);
    const int64_t nSegments = (height + rowsPerSegment - 1) / rowsPerSegment;
    std::vector<std::vector<uint8_t>> parts(static_cast<size_t>(nSegments));
    std::vector<uLong> adlers(static_cast<size_t>(nSegments));
    std::vector<uint8_t> failed(static_cast<size_t>(nSegments), 0);
    const std::vector<uint8_t> zeros(rowBytes, 0);
    parallelFor(0, nSegments, [&](int64_t s) {
        const int64_t y0 = s * rowsPerSegment, y1 = std::min<int64_t>(height, y0 + rowsPerSegment);
        const int64_t from = std::max<int64_t>(0, y0 - rowsBack); // rows of the window
        std::vector<uint8_t> filtered(size_t(y1 - from) * lineBytes), scratch(4 * rowBytes);
        for (int64_t y = from; y < y1; ++y)
            filterRow(pixels + size_t(y) * rowBytes, y > 0 ? pixels + size_t(y - 1) * rowBytes : zeros.data(),
                      rowBytes, nChannels, filtered.data() + size_t(y - from) * lineBytes, scratch.data());
        const uint8_t *own = filtered.data() + size_t(y0 - from) * lineBytes;
        const size_t ownBytes = size_t(y1 - y0) * lineBytes;
        adlers[size_t(s)] = adler32(1, own, uInt(ownBytes));
        z_stream z{};
        if (deflateInit2(&z, 6, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
            failed[size_t(s)] = 1;
            return;
        }
        const size_t window = std::min(kWindowBytes, size_t(own - filtered.data()));
        if (window > 0 && deflateSetDictionary(&z, own - window, uInt(window)) != Z_OK) failed[size_t(s)] = 1;
        const bool last = s + 1 == nSegments;
        if (!failed[size_t(s)] &&
            !deflateAll(z, own, ownBytes, last ? Z_FINISH : Z_SYNC_FLUSH, last ? Z_STREAM_END : Z_OK,
                        parts[size_t(s)]))
            failed[size_t(s)] = 1;
        deflateEnd(&z);
    }, 1);
    if (std::find(failed.begin(), failed.end(), 1) != failed.end()) return {};
    // CMF/FLG of a 32 KiB window at level 6 (FLEVEL 2), no preset dictionary.
    std::vector<uint8_t> stream = {0x78, 0x9c};
    size_t size = 6;
    for (const auto &part : parts) size += part.size();
    stream.reserve(size);
    uLong adler = 1;
    for (int64_t s = 0; s < nSegments; ++s) {
        const std::vector<uint8_t> &part = parts[size_t(s)];
        stream.insert(stream.end(), part.begin(), part.end());
        const int64_t rows = std::min<int64_t>(height, (s + 1) * rowsPerSegment) - s * rowsPerSegment;
        adler = adler32_combine(adler, adlers[size_t(s)], z_off_t(size_t(rows) * lineBytes));
    }
    for (int shift = 24; shift >= 0; shift -= 8) stream.push_back(uint8_t(adler >> shift));
    return stream;
}

/// `idat`, when not empty, is the image's compressed data (compressedImageData()),
/// written as 8 KiB IDAT chunks instead of libpng's rows.
bool encode(PngSink *sink, int width, int height, int nChannels, const uint8_t *pixels,
            const std::vector<uint8_t> &idat) {
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
    if (idat.empty()) {
        const size_t rowBytes = size_t(width) * size_t(nChannels);
        for (int y = 0; y < height; ++y) png_write_row(png, pixels + size_t(y) * rowBytes);
        png_write_end(png, info);
    } else {
        static const png_byte kIdat[5] = "IDAT", kIend[5] = "IEND";
        for (size_t at = 0; at < idat.size(); at += kIdatBytes)
            png_write_chunk(png, kIdat, idat.data() + at, std::min(kIdatBytes, idat.size() - at));
        png_write_chunk(png, kIend, nullptr, 0); // what png_write_end() adds here
    }
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
    // libpng checks the shape (its limit of 10^6 pixels a side) before any row is
    // read: the large path compresses only shapes it accepts.
    std::vector<uint8_t> idat;
    if (width <= 1'000'000 && height <= 1'000'000) idat = compressedImageData(width, height, nChannels, pixels);
    if (!encode(&sink, width, height, nChannels, pixels, idat)) {
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
