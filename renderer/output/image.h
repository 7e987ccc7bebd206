#pragma once
/// \file image.h
/// Our image type and the one way images leave the program: writeImage(). The
/// files are written by OpenImageIO inside the run-time module of image_io.h
/// (oiio_module.cpp), so nothing outside that module sees OpenImageIO; 8-bit PNG
/// with straight alpha and no extra attributes by libpng directly, the same bytes
/// without loading the module (png_write.h).

#include "renderer/output/image_io.h"

#include <string>
#include <utility>
#include <vector>

namespace rosy::renderer {

/// A float image in linear light, channels interleaved, rows top to bottom:
/// data[(y * width + x) * nChannels + c].
struct Image {
    int width = 0;
    int height = 0;
    int nChannels = 0;
    /// One name per channel, e.g. {"R","G","B"} or {"R","G","B","A","depth"}. A channel
    /// named "A" is straight (not premultiplied) alpha, stored linearly, never sRGB-encoded,
    /// unless `premultipliedAlpha` says otherwise.
    std::vector<std::string> channelNames;
    std::vector<float> data;
    /// R, G, B are already multiplied by A (OpenEXR's convention, the EXR of an
    /// illustration: ink × coverage); writeImage() then does not mark the alpha as
    /// unassociated.
    bool premultipliedAlpha = false;
    /// Header attributes written after writeImage()'s own (e.g. the camera matrices
    /// of the EXR); EXR keeps them all, other formats may drop them.
    std::vector<ImageAttribute> attributes;

    Image() = default;
    /// width x height image with the given channels, all zero.
    Image(int width, int height, std::vector<std::string> channelNames);

    float &at(int x, int y, int c) { return data[offset(x, y, c)]; }
    float at(int x, int y, int c) const { return data[offset(x, y, c)]; }

private:
    size_t offset(int x, int y, int c) const {
        return (size_t(y) * size_t(width) + size_t(x)) * size_t(nChannels) + size_t(c);
    }
};

struct ImageWriteOptions {
    /// EXR only: store half floats instead of 32-bit floats.
    bool exrHalf = false;
    /// PNG and TIFF: 8 or 16 bits per channel (sRGB-encoded either way). JPEG
    /// accepts only 8; EXR ignores it.
    int bitsPerChannel = 8;
    /// Extra float attributes for the file header (name, value), e.g.
    /// "rosy:hatch_spacing_px". OpenEXR keeps them; other formats may drop them.
    std::vector<std::pair<std::string, float>> floatAttributes;
};

/// The file extensions writeImage() accepts, for messages: ".png .exr .tif .tiff .jpg .jpeg".
const char *supportedImageExtensions();

/// True if writeImage() can write a file with this path's extension.
bool isSupportedImagePath(const std::string &path);

/// True if writeImage() of a picture to `path` (8 bits, no extra header
/// attributes, straight alpha) loads the OpenImageIO module (image_io.h): every
/// format but PNG, which libpng writes directly (png_write.h). Callers preload
/// the module only then.
bool writeNeedsImageIoModule(const std::string &path);

/// Writes `image` to `path`, format chosen by the (case-insensitive) extension:
///  - .png, .tif/.tiff, .jpg/.jpeg: 8 bits per channel (PNG and TIFF: 16 on request,
///    see ImageWriteOptions::bitsPerChannel), colour channels converted
///    from linear light with the sRGB transfer curve (values clamped to [0, 1], NaN -> 0),
///    alpha kept linear; PNG/TIFF take 1-4 channels, JPEG 1 or 3 and at most 65500
///    pixels per side;
///  - .exr: every channel with its name, 32-bit float (or half, see options);
///    NaN and infinities become 0, except +infinity in a channel named "Z"
///    (OpenEXR's depth: nothing there), which is kept.
/// The file appears atomically (temporary file + rename, see core/atomic_file.h): on
/// failure no temporary file is left and an existing file at `path` is untouched.
/// No time stamps or host names are written, so equal images give equal files.
/// \throws InputError naming `path` for an unsupported extension, a channel count
///   or size the format cannot hold, or a bit depth other than 8 and 16 (16 for JPEG).
/// \throws IoError with OpenImageIO's message if the file cannot be written.
void writeImage(const Image &image, const std::string &path, const ImageWriteOptions &options = {});

/// sRGB transfer curve (IEC 61966-2-1) of a linear value in [0, 1].
double linearToSrgb(double linear);

/// The 8-bit sRGB code writeImage() stores for a linear value: exactly
/// uint8_t(std::lround(linearToSrgb(v) * 255)) for every float v (NaN and v <= 0
/// give 0, v >= 1 gives 255), looked up in a table of the 255 least floats at
/// which the code steps up (binary searches, once, on linearToSrgb itself) instead
/// of a pow() per value.
uint8_t linearToSrgb8(float linear);

} // namespace rosy::renderer
