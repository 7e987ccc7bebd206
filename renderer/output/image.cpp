#include "renderer/output/image.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "renderer/output/image_io.h"
#include "renderer/output/large_buffer.h"
#include "renderer/output/png_write.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <limits>

namespace rosy::renderer {

Image::Image(int w, int h, std::vector<std::string> names)
    : width(w), height(h), nChannels(int(names.size())), channelNames(std::move(names)) {
    ROSY_CHECK_GE(width, 0);
    ROSY_CHECK_GE(height, 0);
    assignLarge(data, size_t(width) * size_t(height) * size_t(nChannels), 0.0f);
}

const char *supportedImageExtensions() { return ".png .exr .tif .tiff .jpg .jpeg"; }

double linearToSrgb(double linear) {
    if (!(linear > 0.0)) return 0.0; // also maps NaN to 0
    if (linear >= 1.0) return 1.0;
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

namespace {

uint8_t srgb8ByPow(float linear) { return uint8_t(std::lround(linearToSrgb(linear) * 255.0)); }

uint32_t bitsOf(float v) {
    uint32_t u;
    std::memcpy(&u, &v, sizeof u);
    return u;
}

/// The steps of the 8-bit code: firstAtLeast[k - 1] is the least positive float
/// whose srgb8ByPow() is >= k, k = 1..255, and atBucket[b] the code of the float
/// with bit pattern b << 16 (b below that of 1.0f), from which a lookup walks up
/// the few steps (at most one, for this curve) to its value. The code never
/// decreases as the float grows (linearToSrgb is monotone; the test
/// LinearToSrgb.EightBitCodesAreTheRoundedCurveForEveryFloat checks the codes around
/// every step), and the bit patterns of positive floats are in the same order as
/// their values, so a binary search over the patterns finds each step.
struct Srgb8Steps {
    static constexpr uint32_t kOne = 0x3f800000u; // 1.0f; srgb8ByPow(1.0f) = 255
    float firstAtLeast[256];
    uint8_t atBucket[kOne >> 16];
    Srgb8Steps() {
        for (int k = 1; k <= 255; ++k) {
            uint32_t lo = 1, hi = kOne;
            while (lo < hi) {
                const uint32_t mid = lo + (hi - lo) / 2;
                float v;
                std::memcpy(&v, &mid, sizeof v);
                if (srgb8ByPow(v) >= k)
                    hi = mid;
                else
                    lo = mid + 1;
            }
            std::memcpy(&firstAtLeast[k - 1], &lo, sizeof lo);
        }
        firstAtLeast[255] = std::numeric_limits<float>::infinity(); // no code above 255
        for (uint32_t b = 0; b < (kOne >> 16); ++b) {
            float v;
            const uint32_t bits = b << 16;
            std::memcpy(&v, &bits, sizeof v);
            atBucket[b] = srgb8ByPow(v);
        }
    }
    uint8_t operator()(float linear) const {
        if (!(linear > 0.0f)) return 0; // also NaN
        const uint32_t bits = bitsOf(linear);
        if (bits >= kOne) return 255; // 1, above, +infinity
        int code = atBucket[bits >> 16];
        while (linear >= firstAtLeast[code]) ++code;
        return uint8_t(code);
    }
};

const Srgb8Steps &srgb8Steps() {
    static const Srgb8Steps steps;
    return steps;
}

} // namespace

uint8_t linearToSrgb8(float linear) { return srgb8Steps()(linear); }

namespace {

enum class Format { Png, Exr, Tiff, Jpeg };

std::string lowerExtension(const std::string &path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

Format formatOf(const std::string &path) {
    std::string ext = lowerExtension(path);
    if (ext == ".png") return Format::Png;
    if (ext == ".exr") return Format::Exr;
    if (ext == ".tif" || ext == ".tiff") return Format::Tiff;
    if (ext == ".jpg" || ext == ".jpeg") return Format::Jpeg;
    throw InputError(FileLoc{path},
                     "cannot write images with extension '" + ext + "'",
                     std::string("use one of ") + supportedImageExtensions());
}

const char *oiioFormatName(Format f) {
    switch (f) {
    case Format::Png: return "png";
    case Format::Exr: return "openexr";
    case Format::Tiff: return "tiff";
    case Format::Jpeg: return "jpeg";
    }
    return "";
}

int alphaIndex(const Image &image) {
    for (int c = 0; c < image.nChannels; ++c)
        if (image.channelNames[size_t(c)] == "A") return c;
    return -1;
}

} // namespace

bool isSupportedImagePath(const std::string &path) {
    std::string ext = lowerExtension(path);
    for (const char *e : {".png", ".exr", ".tif", ".tiff", ".jpg", ".jpeg"})
        if (ext == e) return true;
    return false;
}

bool writeNeedsImageIoModule(const std::string &path) { return lowerExtension(path) != ".png"; }

void writeImage(const Image &image, const std::string &path, const ImageWriteOptions &options) {
    ROSY_CHECK_EQ(int(image.channelNames.size()), image.nChannels);
    ROSY_CHECK_EQ(image.data.size(),
                  size_t(image.width) * size_t(image.height) * size_t(image.nChannels));
    Format format = formatOf(path);
    bool eightBit = format != Format::Exr; // integer-coded, sRGB (8 or 16 bits)
    if (options.bitsPerChannel != 8 && options.bitsPerChannel != 16)
        throw InputError(FileLoc{path},
                         "cannot write " + std::to_string(options.bitsPerChannel) + " bits per channel",
                         "use 8 or 16");
    if (format == Format::Jpeg && options.bitsPerChannel != 8)
        throw InputError(FileLoc{path}, "JPEG holds only 8 bits per channel",
                         "write .png or .tif for 16 bits");
    bool sixteenBit = eightBit && options.bitsPerChannel == 16;
    if (image.width < 1 || image.height < 1)
        throw InputError(FileLoc{path}, "cannot write an empty image (" +
                                            std::to_string(image.width) + "x" +
                                            std::to_string(image.height) + ")");
    // JPEG has no alpha: an RGBA picture (our composite is opaque paper) loses its A.
    if (format == Format::Jpeg && image.nChannels == 4 && alphaIndex(image) == 3) {
        Image rgb(image.width, image.height, {image.channelNames[0], image.channelNames[1], image.channelNames[2]});
        for (size_t p = 0, n = size_t(image.width) * size_t(image.height); p < n; ++p)
            for (size_t c = 0; c < 3; ++c) rgb.data[3 * p + c] = image.data[4 * p + c];
        writeImage(rgb, path, options);
        return;
    }
    if (format == Format::Jpeg && image.nChannels != 1 && image.nChannels != 3)
        throw InputError(FileLoc{path},
                         "JPEG holds 1 or 3 channels, the image has " + std::to_string(image.nChannels),
                         "write .png, .tif or .exr instead");
    // libjpeg ends the whole process (exit()) on larger images instead of reporting an
    // error through OpenImageIO, so refuse them here.
    if (format == Format::Jpeg && (image.width > 65500 || image.height > 65500))
        throw InputError(FileLoc{path},
                         "JPEG images are limited to 65500 pixels per side, this one is " +
                             std::to_string(image.width) + "x" + std::to_string(image.height),
                         "write .png, .tif or .exr instead");
    if (eightBit && (image.nChannels < 1 || image.nChannels > 4))
        throw InputError(FileLoc{path},
                         "8-bit formats hold 1 to 4 channels, the image has " +
                             std::to_string(image.nChannels),
                         "write .exr to keep every channel");
    if (image.nChannels < 1) throw InputError(FileLoc{path}, "cannot write an image without channels");

    int alpha = alphaIndex(image);
    ImageFileSpec spec;
    spec.format = oiioFormatName(format);
    spec.width = image.width;
    spec.height = image.height;
    spec.nChannels = image.nChannels;
    spec.fileType = sixteenBit ? PixelType::UInt16
                    : eightBit ? PixelType::UInt8
                               : (options.exrHalf ? PixelType::Half : PixelType::Float);
    spec.channelNames = image.channelNames;
    spec.alphaChannel = alpha;
    using A = ImageAttribute;
    // Our alpha is straight (not premultiplied): tell the writers not to divide by it.
    if (alpha >= 0 && !image.premultipliedAlpha) spec.attributes.push_back(A::integer("oiio:UnassociatedAlpha", 1));
    // An empty DateTime stops the EXR and TIFF writers stamping the current time:
    // the same render must give the same bytes on every run.
    spec.attributes.push_back(A::text("DateTime", ""));
    if (eightBit) {
        spec.attributes.push_back(A::text("oiio:ColorSpace", "sRGB"));
        if (format == Format::Jpeg) spec.attributes.push_back(A::integer("CompressionQuality", 95));
    } else {
        spec.attributes.push_back(A::text("oiio:ColorSpace", "Linear"));
        spec.attributes.push_back(A::text("compression", "zip"));
    }
    for (const auto &[name, value] : options.floatAttributes) spec.attributes.push_back(A::real(name, value));
    for (const ImageAttribute &a : image.attributes) spec.attributes.push_back(a);

    // Encode once, outside the writer: exact rounding of our own sRGB curve rather
    // than whatever conversion the format plugin would apply.
    std::vector<uint8_t> bytes;
    std::vector<uint16_t> words;
    if (eightBit) {
        if (sixteenBit)
            words.resize(image.data.size());
        else
            bytes.resize(image.data.size());
        // Rows in parallel: each value depends only on itself.
        const size_t rowValues = size_t(image.width) * size_t(image.nChannels);
        const Srgb8Steps &srgb8 = srgb8Steps();
        parallelFor(0, image.height, [&](int64_t y) {
            for (size_t i = size_t(y) * rowValues, end = i + rowValues; i < end; ++i) {
                int c = int(i % size_t(image.nChannels));
                double v = image.data[i];
                if (!sixteenBit && c != alpha) {
                    bytes[i] = srgb8(image.data[i]); // linearToSrgb8(): the formula below, without pow()
                    continue;
                }
                double e = c == alpha ? (v == v ? std::clamp(v, 0.0, 1.0) : 0.0) : linearToSrgb(v);
                if (sixteenBit)
                    words[i] = uint16_t(std::lround(e * 65535.0));
                else
                    bytes[i] = uint8_t(std::lround(e * 255.0));
            }
        }, 16);
    }
    // NaN and infinities cannot be displayed; EXR would store them verbatim, which
    // breaks "never NaN in output". Replace them before writing, but keep +inf in
    // a Z channel: OpenEXR's depth of a pixel that sees nothing.
    std::vector<float> floats;
    if (!eightBit) {
        floats = image.data;
        const size_t nc = size_t(image.nChannels);
        std::vector<char> keepInf(nc, 0);
        for (size_t c = 0; c < nc; ++c) keepInf[c] = image.channelNames[c] == "Z";
        for (size_t i = 0; i < floats.size(); ++i)
            if (!std::isfinite(floats[i]) && !(keepInf[i % nc] && floats[i] > 0)) floats[i] = 0.0f;
    }

    // The common case, an 8-bit PNG with straight or no alpha and no extra header
    // attributes, goes to libpng directly: the same bytes without loading the
    // OpenImageIO module (png_write.h).
    const bool plainPng = format == Format::Png && !sixteenBit && options.floatAttributes.empty() &&
                          image.attributes.empty() &&
                          (alpha < 0 || (alpha == image.nChannels - 1 && image.nChannels % 2 == 0 &&
                                         !image.premultipliedAlpha));
    if (plainPng) {
        writeAtomically(path, [&](const std::string &tmpPath) {
            std::string error;
            if (!writePng8(tmpPath, image.width, image.height, image.nChannels, bytes.data(), error))
                throw IoError(path, error);
        });
        return;
    }

    const ImageIo &io = imageIo(); // before the temporary exists: a missing module leaves nothing behind
    // A large EXR takes seconds to compress: say what is being written (terminal only, after a second).
    Progress progress("writing", {{std::filesystem::path(path).filename().string(), 1.0}});
    writeAtomically(path, [&](const std::string &tmpPath) {
        std::string error;
        const bool ok = sixteenBit ? io.write(tmpPath, spec, PixelType::UInt16, words.data(), error)
                        : eightBit ? io.write(tmpPath, spec, PixelType::UInt8, bytes.data(), error)
                                   : io.write(tmpPath, spec, PixelType::Float, floats.data(), error);
        if (!ok) throw IoError(path, error);
    });
}

} // namespace rosy::renderer
