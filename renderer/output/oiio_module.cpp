/// \file oiio_module.cpp
/// The image I/O module (librosy_image_io.so): the ImageIo interface of
/// image_io.h over OpenImageIO. The only file of the programs that includes
/// OpenImageIO; see image_io.h for why it is loaded at run time.

#include "renderer/output/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>

namespace rosy::renderer {
namespace {

/// The writers' output: a file descriptor behind OpenImageIO's IOProxy interface.
/// A failed write (disk full, EFBIG past `ulimit -f`) is recorded and every later
/// write skipped, but the writer is told it succeeded: libjpeg's default error
/// handler calls exit() when its output fails, which would end the whole program
/// with a temporary file left behind. The failure is reported after close().
class FdOutput final : public OIIO::Filesystem::IOProxy {
public:
    FdOutput(int fd, const std::string &name) : IOProxy(name, Write), m_fd(fd) {}
    const char *proxytype() const override { return "rosyhatch-fd"; }
    bool seek(int64_t offset) override {
        m_pos = offset;
        return true;
    }
    size_t write(const void *buf, size_t size) override {
        pwrite(buf, size, m_pos);
        m_pos += int64_t(size);
        return size;
    }
    size_t pwrite(const void *buf, size_t size, int64_t offset) override {
        const char *p = static_cast<const char *>(buf);
        size_t left = size;
        int64_t at = offset;
        while (m_errno == 0 && left > 0) {
            const ssize_t n = ::pwrite(m_fd, p, left, off_t(at));
            if (n < 0) {
                if (errno != EINTR) m_errno = errno;
                continue;
            }
            p += n;
            left -= size_t(n);
            at += n;
        }
        m_size = std::max(m_size, offset + int64_t(size));
        return size;
    }
    size_t read(void *buf, size_t size) override {
        const size_t n = pread(buf, size, m_pos);
        m_pos += int64_t(n);
        return n;
    }
    size_t pread(void *buf, size_t size, int64_t offset) override {
        const ssize_t n = ::pread(m_fd, buf, size, off_t(offset));
        return n < 0 ? 0 : size_t(n);
    }
    size_t size() const override { return size_t(m_size); }
    /// errno of the first failed write, 0 if none.
    int failure() const { return m_errno; }

private:
    int m_fd;
    int m_errno = 0;
    int64_t m_size = 0;
};

/// Closes the descriptor on every path out.
struct FdCloser {
    int fd;
    ~FdCloser() {
        if (fd >= 0) ::close(fd);
    }
};

OIIO::TypeDesc oiioType(PixelType t) {
    switch (t) {
    case PixelType::UInt8: return OIIO::TypeDesc::UINT8;
    case PixelType::UInt16: return OIIO::TypeDesc::UINT16;
    case PixelType::Half: return OIIO::TypeDesc::HALF;
    case PixelType::Float: return OIIO::TypeDesc::FLOAT;
    }
    return OIIO::TypeDesc::UNKNOWN;
}

class OiioReader final : public ImageFileReader {
public:
    explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in) : m_in(std::move(in)) {
        const OIIO::ImageSpec &spec = m_in->spec();
        m_header.width = spec.width;
        m_header.height = spec.height;
        m_header.depth = spec.depth;
        m_header.nChannels = spec.nchannels;
        m_header.channelNames = spec.channelnames;
        m_header.alphaChannel = spec.alpha_channel;
        m_header.floating = spec.format.basetype == OIIO::TypeDesc::FLOAT ||
                            spec.format.basetype == OIIO::TypeDesc::HALF ||
                            spec.format.basetype == OIIO::TypeDesc::DOUBLE;
        m_header.colorSpace = spec.get_string_attribute("oiio:ColorSpace");
    }
    ~OiioReader() override { m_in->close(); }

    const ImageFileHeader &header() const override { return m_header; }
    float floatAttribute(const std::string &name, float fallback) const override {
        return m_in->spec().get_float_attribute(name, fallback);
    }
    bool readFloat(float *out, std::string &error) override {
        if (m_in->read_image(0, 0, 0, m_header.nChannels, OIIO::TypeDesc::FLOAT, out)) return true;
        error = m_in->geterror();
        return false;
    }

private:
    std::unique_ptr<OIIO::ImageInput> m_in;
    ImageFileHeader m_header;
};

class OiioImageIo final : public ImageIo {
public:
    bool write(const std::string &path, const ImageFileSpec &s, PixelType dataType, const void *pixels,
               std::string &error) const override {
        OIIO::ImageSpec spec(s.width, s.height, s.nChannels, oiioType(s.fileType));
        spec.channelnames = s.channelNames;
        spec.alpha_channel = s.alphaChannel;
        for (const ImageAttribute &a : s.attributes) {
            switch (a.kind) {
            case ImageAttribute::Kind::Int: spec.attribute(a.name, a.intValue); break;
            case ImageAttribute::Kind::Float: spec.attribute(a.name, a.floatValue); break;
            case ImageAttribute::Kind::String: spec.attribute(a.name, a.stringValue); break;
            case ImageAttribute::Kind::Matrix44: spec.attribute(a.name, OIIO::TypeMatrix44, a.matrixValue.data()); break;
            }
        }
        auto out = OIIO::ImageOutput::create(s.format);
        if (!out) {
            error = "OpenImageIO has no writer: " + OIIO::geterror();
            return false;
        }
        // Pixels, then close (which flushes); the first failure's message wins.
        auto writeAndClose = [&] {
            bool ok = out->write_image(oiioType(dataType), pixels);
            if (!ok) error = out->geterror();
            if (!out->close() && ok) {
                ok = false;
                error = out->geterror();
            }
            return ok;
        };
        // TIFF goes to the path itself: OpenImageIO 2.4.7's TIFF writer produces a file
        // without a valid directory through any IOProxy (its own IOFile included), and
        // libtiff reports write failures as errors rather than ending the process.
        if (s.format == "tiff" || !out->supports("ioproxy")) {
            if (!out->open(path, spec)) {
                error = out->geterror();
                return false;
            }
            return writeAndClose();
        }
        // Read-write: libtiff reads back what it wrote when it finishes a directory.
        FdCloser file{::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0666)};
        if (file.fd < 0) {
            error = std::string("cannot open for writing: ") + std::strerror(errno);
            return false;
        }
        FdOutput proxy(file.fd, path);
        if (!out->set_ioproxy(&proxy) || !out->open(path, spec)) {
            error = out->geterror();
            return false;
        }
        bool ok = writeAndClose();
        if (proxy.failure() != 0) {
            error = std::string("write failed: ") + std::strerror(proxy.failure());
            return false;
        }
        if (::close(file.fd) != 0 && ok) {
            ok = false;
            error = std::string("write failed: ") + std::strerror(errno);
        }
        file.fd = -1;
        return ok;
    }

    std::unique_ptr<ImageFileReader> open(const std::string &path, std::string &error) const override {
        auto in = OIIO::ImageInput::open(path);
        if (!in) {
            error = OIIO::geterror();
            return nullptr;
        }
        return std::make_unique<OiioReader>(std::move(in));
    }
};

} // namespace
} // namespace rosy::renderer

extern "C" __attribute__((visibility("default"))) const rosy::renderer::ImageIo *rosy_image_io_v1(int version) {
    static const rosy::renderer::OiioImageIo instance;
    return version == rosy::renderer::kImageIoInterfaceVersion ? &instance : nullptr;
}
