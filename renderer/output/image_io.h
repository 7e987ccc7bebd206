#pragma once
/// \file image_io.h
/// The narrow interface through which the renderer reads and writes image files.
///
/// Why a loadable module. Debian's OpenImageIO links about 260 shared libraries
/// (GDAL, OpenCV, GDCM, FFmpeg, ...). Linked into the executable, the dynamic
/// loader maps and relocates all of them before main() runs: about 0.4 s of every
/// rosyhatch call, `--help` included, on the 2-core development machine. So every
/// OpenImageIO call lives in one shared MODULE of ours, `rosy_image_io`
/// (renderer/output/oiio_module.cpp, the only file that includes OpenImageIO headers in
/// the programs), which the renderer opens with dlopen() when it first needs it.
/// `preloadImageIo()` starts that load on a background thread, so a render maps
/// OpenImageIO while it loads the mesh and solves the field; `imageIo()` waits for
/// it. The files written are the same bytes either way: the same OpenImageIO
/// writes them with the same settings.
///
/// Where the module is looked for, first match wins:
///   1. the path in the environment variable ROSY_IMAGE_IO_MODULE (for tests and
///      for relocated installs);
///   2. next to the running executable (`<dir of /proc/self/exe>/librosy_image_io.so`);
///   3. where `cmake --install` puts it: `<dir of the executable>/../lib/rosyhatch/`;
///   4. where the build put it (ROSY_IMAGE_IO_MODULE_PATH, a path compiled in).
/// Missing or unloadable, imageIo() throws IoError (exit code 3) naming the paths
/// tried and how to fix it.
///
/// 8-bit PNG without extra header attributes does not come here: writeImage()
/// writes it with libpng directly, the same bytes (png_write.h).
///
/// The interface passes only our own types (no OpenImageIO type crosses it) and
/// reports failures as strings, never as exceptions across the module boundary.

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rosy::renderer {

/// Storage type of pixel values, in memory or in the file.
enum class PixelType { UInt8, UInt16, Half, Float };

/// One header attribute, e.g. {"compression", "zip"}; kept in the order given,
/// which is the order OpenImageIO sees them.
struct ImageAttribute {
    /// Matrix44: a 4x4 float matrix, OpenEXR's M44f (e.g. the standard
    /// `worldToCamera`, `worldToNDC`), 16 values row by row as Imath stores them.
    enum class Kind { Int, Float, String, Matrix44 };
    std::string name;
    Kind kind = Kind::Int;
    int intValue = 0;
    float floatValue = 0.0f;
    std::string stringValue;
    std::array<float, 16> matrixValue{};

    static ImageAttribute integer(std::string name, int v) { return {std::move(name), Kind::Int, v, 0.0f, {}, {}}; }
    static ImageAttribute real(std::string name, float v) { return {std::move(name), Kind::Float, 0, v, {}, {}}; }
    static ImageAttribute text(std::string name, std::string v) {
        return {std::move(name), Kind::String, 0, 0.0f, std::move(v), {}};
    }
    static ImageAttribute matrix44(std::string name, const std::array<float, 16> &rowMajor) {
        return {std::move(name), Kind::Matrix44, 0, 0.0f, {}, rowMajor};
    }
};

/// Everything a writer needs to know besides the pixels.
struct ImageFileSpec {
    std::string format; ///< OpenImageIO format name: "png", "openexr", "tiff", "jpeg"
    int width = 0, height = 0, nChannels = 0;
    std::vector<std::string> channelNames;
    int alphaChannel = -1;               ///< -1: none
    PixelType fileType = PixelType::UInt8; ///< how values are stored in the file
    std::vector<ImageAttribute> attributes;
};

/// What an image file's header says.
struct ImageFileHeader {
    int width = 0, height = 0, depth = 1, nChannels = 0;
    std::vector<std::string> channelNames; ///< as stored; may be shorter than nChannels
    int alphaChannel = -1;
    bool floating = false;  ///< stored as half, float or double
    std::string colorSpace; ///< "oiio:ColorSpace", e.g. "sRGB" or "Linear"
};

/// An open image file. Not thread-safe; one reader per thread.
class ImageFileReader {
public:
    virtual ~ImageFileReader() = default;
    virtual const ImageFileHeader &header() const = 0;
    /// A float attribute of the header, or `fallback` when absent.
    virtual float floatAttribute(const std::string &name, float fallback) const = 0;
    /// Reads every channel of the (first subimage of the) file as float, interleaved,
    /// width * height * nChannels values. False with a message on failure.
    virtual bool readFloat(float *out, std::string &error) = 0;
};

/// The module's services. One instance, valid for the life of the process.
class ImageIo {
public:
    virtual ~ImageIo() = default;
    /// Writes `pixels` (interleaved, `dataType` values, spec.width * height *
    /// nChannels of them) to `path` in spec.format. `path` is opened (created or
    /// truncated) by the module and written through its descriptor, so a write that
    /// fails (disk full, `ulimit -f`) is reported here for every format, JPEG
    /// included, instead of libjpeg ending the process. False with a message on
    /// failure; a partial file may then remain at `path` (callers write to a
    /// temporary, core/atomic_file.h).
    virtual bool write(const std::string &path, const ImageFileSpec &spec, PixelType dataType, const void *pixels,
                       std::string &error) const = 0;
    /// Opens a file for reading; null with a message if it is no image the module can read.
    /// Through imageIo() the header is also checked against the read budget
    /// (checkReadBudget()) before it is returned, so no pixel buffer is allocated
    /// for a decompression bomb.
    virtual std::unique_ptr<ImageFileReader> open(const std::string &path, std::string &error) const = 0;
};

/// The read budget of `rosyhatch diff` and `inspect` (and every other reader going
/// through imageIo()): at most kMaxReadPixels pixels (4096 x 4096, the largest
/// render; scenes/README.md) and kMaxReadValues channel values, i.e. 1.5 GiB per
/// image as float: 24 channels at 4096², room for the 19 of a rosyhatch EXR.
/// A 168 KB PNG can claim 32000 x 32000 pixels and a 5 KB EXR a 50000² data window.
inline constexpr long long kMaxReadPixels = 4096LL * 4096LL;
inline constexpr long long kMaxReadValues = 24LL * 4096LL * 4096LL;

/// \throws InputError (exit 2) naming `path`, the image's size and the limit when
///   the header exceeds the read budget.
void checkReadBudget(const std::string &path, const ImageFileHeader &header);

/// The first of the module paths above that exists (what imageIo() would try
/// first), without loading it; empty if none does. For `rosyhatch --version`.
std::string imageIoModulePath();

/// Starts loading the module on a background thread (once; later calls do
/// nothing). Optional: imageIo() loads it anyway.
void preloadImageIo();

/// The loaded module, waiting for a preload in flight; its open() applies the read
/// budget (it may throw InputError, from this side of the module boundary).
/// \throws IoError if the module cannot be found or loaded (exit code 3).
const ImageIo &imageIo();

/// The entry point the module exports (extern "C", so dlsym finds it by this name):
/// returns the module's ImageIo if `interfaceVersion` matches its own, else null.
inline constexpr const char *kImageIoEntryPoint = "rosy_image_io_v1";
inline constexpr int kImageIoInterfaceVersion = 1;

} // namespace rosy::renderer
