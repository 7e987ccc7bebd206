/// \file oiio_module.cpp
/// The image I/O module (librosy_image_io.so): the ImageIo interface of
/// image_io.h over OpenImageIO. The only file of the programs that includes
/// OpenImageIO; see image_io.h for why it is loaded at run time.

#include "renderer/image_io.h"

#include <OpenImageIO/imageio.h>

namespace rosy::renderer {
namespace {

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
            }
        }
        auto out = OIIO::ImageOutput::create(s.format);
        if (!out) {
            error = "OpenImageIO has no writer: " + OIIO::geterror();
            return false;
        }
        if (!out->open(path, spec)) {
            error = out->geterror();
            return false;
        }
        if (!out->write_image(oiioType(dataType), pixels)) {
            error = out->geterror();
            out->close();
            return false;
        }
        if (!out->close()) {
            error = out->geterror();
            return false;
        }
        return true;
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
