#include "renderer/output/image.h"
#include "renderer/output/png_write.h"

#include "core/error.h"

#include <OpenImageIO/imageio.h>
#include "test_support.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include <sys/resource.h>

using namespace rosy::renderer;
namespace fs = std::filesystem;

namespace {


struct ReadBack {
    OIIO::ImageSpec spec;
    std::vector<float> floats;
    std::vector<unsigned char> bytes;
};

ReadBack readBack(const fs::path &path) {
    ReadBack r;
    // Read the stored values as they are, without premultiplying by alpha.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path.string(), &config);
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return r;
    r.spec = in->spec();
    size_t n = size_t(r.spec.width) * size_t(r.spec.height) * size_t(r.spec.nchannels);
    r.floats.resize(n);
    r.bytes.resize(n);
    EXPECT_TRUE(in->read_image(0, 0, 0, r.spec.nchannels, OIIO::TypeDesc::FLOAT, r.floats.data()));
    EXPECT_TRUE(in->read_image(0, 0, 0, r.spec.nchannels, OIIO::TypeDesc::UINT8, r.bytes.data()));
    in->close();
    return r;
}

using rosy::test::slurp;

} // namespace

TEST(LinearToSrgb, MatchesTheStandardCurve) {
    // IEC 61966-2-1: linear segment below 0.0031308, power 1/2.4 above.
    EXPECT_DOUBLE_EQ(linearToSrgb(0.0), 0.0);
    EXPECT_DOUBLE_EQ(linearToSrgb(1.0), 1.0);
    EXPECT_NEAR(linearToSrgb(0.001), 0.01292, 1e-12);
    EXPECT_NEAR(linearToSrgb(0.5), 0.735356983, 1e-8);
    EXPECT_NEAR(linearToSrgb(0.214041140), 0.5, 1e-6);
    EXPECT_EQ(linearToSrgb(std::numeric_limits<double>::quiet_NaN()), 0.0);
    EXPECT_EQ(linearToSrgb(-3.0), 0.0);
    EXPECT_EQ(linearToSrgb(7.0), 1.0);
}

TEST(LinearToSrgb, EightBitCodesAreTheRoundedCurveForEveryFloat) {
    // linearToSrgb8() looks the code up instead of calling pow(); it must be exactly
    // the rounded curve. Checked here around every step (the 9 floats on either side
    // of each value where the code changes), on 2^20 floats spread over [0, 1] by
    // their bit patterns, and on the special values. (All 1,074,266,242 floats in
    // [0, 1] plus infinities and NaNs were compared once, 2026-12-02: no difference.)
    auto byPow = [](float v) { return uint8_t(std::lround(linearToSrgb(v) * 255.0)); };
    auto bitsOf = [](float v) {
        uint32_t u;
        std::memcpy(&u, &v, sizeof u);
        return u;
    };
    auto floatOf = [](uint32_t u) {
        float v;
        std::memcpy(&v, &u, sizeof v);
        return v;
    };
    int steps = 0, differ = 0;
    for (uint32_t u = 1; u < bitsOf(1.0f); u += 1013) {
        const float v = floatOf(u), next = floatOf(u + 1013 < bitsOf(1.0f) ? u + 1013 : bitsOf(1.0f));
        differ += linearToSrgb8(v) != byPow(v);
        if (byPow(next) == byPow(v)) continue;
        // A step lies in (v, next]: find it and check its neighbourhood.
        uint32_t lo = u, hi = bitsOf(next);
        while (hi - lo > 1) {
            const uint32_t mid = lo + (hi - lo) / 2;
            (byPow(floatOf(mid)) == byPow(v) ? lo : hi) = mid;
        }
        ++steps;
        for (uint32_t w = hi - 9; w <= hi + 9; ++w) differ += linearToSrgb8(floatOf(w)) != byPow(floatOf(w));
    }
    EXPECT_EQ(steps, 255);
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    for (float v : {0.0f, -0.0f, -1.0f, -inf, nan, std::numeric_limits<float>::denorm_min(), 0.0031308f, 0.5f,
                    1.0f, 1.0000001f, 7.0f, inf})
        differ += linearToSrgb8(v) != byPow(v);
    EXPECT_EQ(differ, 0);
    EXPECT_EQ(linearToSrgb8(0.5f), 188);
    EXPECT_EQ(linearToSrgb8(1.0f), 255);
    EXPECT_EQ(linearToSrgb8(nan), 0);
}

TEST(WriteImage, PngRoundTripIsSrgbEncoded) {
    fs::path dir = rosy::test::freshDir("image", "png");
    Image img(4, 2, {"R", "G", "B"});
    // Hand-computed 8-bit sRGB codes: round(255 * srgb(v)).
    const float in[8] = {0.0f, 1.0f, 0.5f, 0.18f, 0.001f, 0.05f, 0.8f, 2.0f};
    const int code[8] = {0, 255, 188, 118, 3, 63, 231, 255};
    for (int i = 0; i < 8; ++i)
        for (int c = 0; c < 3; ++c) img.at(i % 4, i / 4, c) = c == 1 ? in[i] : 0.0f;
    img.at(0, 0, 0) = std::numeric_limits<float>::quiet_NaN();
    fs::path out = dir / "ramp.png";
    writeImage(img, out.string());
    ReadBack r = readBack(out);
    ASSERT_EQ(r.spec.width, 4);
    ASSERT_EQ(r.spec.height, 2);
    ASSERT_EQ(r.spec.nchannels, 3);
    EXPECT_EQ(r.spec.format, OIIO::TypeDesc::UINT8);
    for (int i = 0; i < 8; ++i) {
        EXPECT_EQ(int(r.bytes[size_t(i) * 3 + 1]), code[i]) << "value " << in[i];
        EXPECT_EQ(int(r.bytes[size_t(i) * 3 + 0]), 0);
    }
    // Only the final file remains.
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(WriteImage, PngAlphaStaysLinear) {
    fs::path dir = rosy::test::freshDir("image", "alpha");
    Image img(1, 1, {"R", "G", "B", "A"});
    img.at(0, 0, 0) = 0.5f;
    img.at(0, 0, 3) = 0.5f;
    writeImage(img, (dir / "a.png").string());
    ReadBack r = readBack(dir / "a.png");
    ASSERT_EQ(r.spec.nchannels, 4);
    EXPECT_EQ(r.spec.alpha_channel, 3);
    EXPECT_EQ(int(r.bytes[0]), 188);
    EXPECT_EQ(int(r.bytes[3]), 128); // round(0.5 * 255) = 127.5 -> 128
}

TEST(WriteImage, ExrKeepsFloatsAndChannelNames) {
    fs::path dir = rosy::test::freshDir("image", "exr");
    Image img(3, 2, {"R", "G", "B", "A", "depth"});
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i) * 1.25f - 7.0f;
    img.data[7] = 123456.5f;
    fs::path out = dir / "multi.EXR"; // extension is case-insensitive
    writeImage(img, out.string());
    ReadBack r = readBack(out);
    ASSERT_EQ(r.spec.nchannels, 5);
    EXPECT_EQ(r.spec.channelnames, img.channelNames);
    EXPECT_EQ(r.spec.format, OIIO::TypeDesc::FLOAT);
    ASSERT_EQ(r.floats.size(), img.data.size());
    for (size_t i = 0; i < img.data.size(); ++i) EXPECT_EQ(r.floats[i], img.data[i]);
}

TEST(WriteImage, ExrHalfStoresHalfFloats) {
    fs::path dir = rosy::test::freshDir("image", "half");
    Image img(2, 1, {"Y"});
    img.data = {0.5f, -2.25f}; // exactly representable in half
    ImageWriteOptions opt;
    opt.exrHalf = true;
    writeImage(img, (dir / "h.exr").string(), opt);
    ReadBack r = readBack(dir / "h.exr");
    EXPECT_EQ(r.spec.format, OIIO::TypeDesc::HALF);
    EXPECT_EQ(r.floats, img.data);
}

TEST(WriteImage, UnknownExtensionIsAnInputErrorListingFormats) {
    fs::path dir = rosy::test::freshDir("image", "ext");
    Image img(1, 1, {"R", "G", "B"});
    std::string path = (dir / "out.bmp").string();
    try {
        writeImage(img, path);
        FAIL() << "expected InputError";
    } catch (const rosy::InputError &e) {
        std::string what = e.what();
        EXPECT_EQ(what.rfind(path + ": error: ", 0), 0u) << what;
        EXPECT_NE(what.find(".png"), std::string::npos);
        EXPECT_NE(what.find(".exr"), std::string::npos);
    }
    EXPECT_FALSE(fs::exists(path));
}

TEST(WriteImage, MissingFolderIsAnIoError) {
    fs::path dir = rosy::test::freshDir("image", "missing");
    std::string path = (dir / "no-such-folder" / "x.png").string();
    Image img(2, 2, {"R", "G", "B"});
    EXPECT_THROW(writeImage(img, path), rosy::IoError);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
}

TEST(WriteImage, FailedWriteLeavesExistingFileAndNoTemporary) {
    fs::path dir = rosy::test::freshDir("image", "failed");
    const fs::path path = dir / "picture.png";
    {
        std::ofstream(path, std::ios::binary) << "precious";
    }
    ASSERT_EQ(slurp(path), "precious");
    Image img(64, 64, {"R", "G", "B"});
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float((i * 2654435761u) % 1000) / 1000.0f; // incompressible
    // A file size limit of 64 bytes (SIGXFSZ ignored, so write() fails with EFBIG
    // as on a full disk): the PNG cannot be written.
    struct rlimit old {};
    ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
    const auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit small = old;
    small.rlim_cur = 64;
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
    bool threwIo = false;
    try {
        writeImage(img, path.string());
    } catch (const rosy::IoError &) {
        threwIo = true;
    }
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, oldHandler);
    EXPECT_TRUE(threwIo);
    EXPECT_EQ(slurp(path), "precious");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1); // no temporary left
}

TEST(WriteImage, LongLegalNamesAreWritten) {
    // A 249-byte name is legal; the temporary beside it must not exceed NAME_MAX.
    fs::path dir = rosy::test::freshDir("image", "longname");
    const fs::path path = dir / (std::string(245, 'k') + ".png");
    writeImage(Image(2, 2, {"R", "G", "B"}), path.string());
    EXPECT_TRUE(fs::is_regular_file(path));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(WriteImage, OversizedJpegIsAnInputError) {
    fs::path dir = rosy::test::freshDir("image", "jpeg");
    Image img(70000, 1, {"R", "G", "B"});
    EXPECT_THROW(writeImage(img, (dir / "wide.jpg").string()), rosy::InputError);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
}

TEST(WriteImage, EqualImagesGiveEqualFiles) {
    fs::path dir = rosy::test::freshDir("image", "determinism");
    Image img(8, 8, {"R", "G", "B"});
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i % 17) / 16.0f;
    for (const char *ext : {".png", ".exr", ".tif", ".jpg"}) {
        fs::path a = dir / (std::string("a") + ext), b = dir / (std::string("b") + ext);
        writeImage(img, a.string());
        writeImage(img, b.string());
        EXPECT_EQ(slurp(a), slurp(b)) << ext;
    }
}

TEST(WriteImage, PngIsTheFileOpenImageIoWrites) {
    // writeImage() writes 8-bit PNG with libpng itself (renderer/output/png_write.h);
    // the file must be byte for byte what OpenImageIO writes for the same pixels and
    // the header writeImage() used to hand it (DateTime empty, sRGB colour space,
    // straight alpha), for every channel layout and for images on which libpng's
    // adaptive filter picks different filters row by row.
    fs::path dir = rosy::test::freshDir("image", "png-bytes");
    const std::vector<std::vector<std::string>> layouts = {{"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
    for (const auto &names : layouts) {
        for (const auto &[w, h] : std::vector<std::pair<int, int>>{{3, 5}, {301, 187}}) {
            Image img(w, h, names);
            const size_t nc = names.size();
            for (size_t i = 0; i < img.data.size(); ++i) {
                const size_t p = i / nc, x = p % size_t(w), y = p / size_t(w);
                // Smooth gradients in the top half, noise below, a flat band on the right.
                const float noise = float((i * 2654435761u) % 1000) / 1000.0f;
                const float smooth = float(x + 2 * y + 7 * (i % nc)) / float(w + 2 * h + 28);
                img.data[i] = x > size_t(w) * 3 / 4 ? 0.5f : (y < size_t(h) / 2 ? smooth : noise);
            }
            const std::string tag = std::to_string(nc) + "-" + std::to_string(w);
            const fs::path ours = dir / ("ours-" + tag + ".png"), theirs = dir / ("oiio-" + tag + ".png");
            writeImage(img, ours.string());
            const ReadBack stored = readBack(ours);
            ASSERT_EQ(stored.spec.nchannels, int(nc));
            OIIO::ImageSpec spec(w, h, int(nc), OIIO::TypeDesc::UINT8);
            spec.channelnames = names;
            spec.alpha_channel = names.back() == "A" ? int(nc) - 1 : -1;
            if (spec.alpha_channel >= 0) spec.attribute("oiio:UnassociatedAlpha", 1);
            spec.attribute("DateTime", "");
            spec.attribute("oiio:ColorSpace", "sRGB");
            auto out = OIIO::ImageOutput::create("png");
            ASSERT_TRUE(out && out->open(theirs.string(), spec));
            ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, stored.bytes.data()));
            ASSERT_TRUE(out->close());
            const std::string a = slurp(ours), b = slurp(theirs);
            EXPECT_TRUE(a == b) << tag << ": " << a.size() << " bytes against OpenImageIO's " << b.size();
        }
    }
}

namespace {

/// A PNG's chunks in file order: (type, data), each CRC checked.
std::vector<std::pair<std::string, std::string>> pngChunks(const std::string &file) {
    std::vector<std::pair<std::string, std::string>> out;
    EXPECT_EQ(file.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    for (size_t at = 8; at + 12 <= file.size();) {
        const auto *p = reinterpret_cast<const unsigned char *>(file.data() + at);
        const size_t n = size_t(p[0]) << 24 | size_t(p[1]) << 16 | size_t(p[2]) << 8 | size_t(p[3]);
        if (at + 12 + n > file.size()) break;
        const uLong crc = crc32(0, p + 4, uInt(4 + n));
        const unsigned char *c = p + 8 + n;
        EXPECT_EQ(crc, uLong(c[0]) << 24 | uLong(c[1]) << 16 | uLong(c[2]) << 8 | uLong(c[3]));
        out.emplace_back(file.substr(at + 4, 4), file.substr(at + 8, n));
        at += 12 + n;
    }
    return out;
}

/// The zlib stream of all IDAT chunks inflated (the filtered rows), and the other chunks.
std::pair<std::string, std::vector<std::pair<std::string, std::string>>> pngParts(const std::string &file,
                                                                                size_t rawBytes) {
    std::string stream;
    std::vector<std::pair<std::string, std::string>> others;
    for (const auto &chunk : pngChunks(file))
        if (chunk.first == "IDAT") stream += chunk.second;
        else others.push_back(chunk);
    std::string raw(rawBytes + 1, '\0'); // one more: a longer stream shows as a size mismatch
    uLongf n = uLongf(raw.size());
    EXPECT_EQ(uncompress(reinterpret_cast<Bytef *>(raw.data()), &n,
                         reinterpret_cast<const Bytef *>(stream.data()), uLong(stream.size())),
              Z_OK);
    raw.resize(n);
    return {raw, others};
}

} // namespace

TEST(WritePng, LargeImagesAreCompressedInSegmentsWithLibpngsFilters) {
    // Above 256 KiB of filtered rows the image data is filtered and deflated in
    // segments in parallel (png_write.cpp). The file must still hold the same pixels
    // as OpenImageIO's (libpng's) file, the same chunks besides IDAT, the same
    // filtered rows (libpng's filter choice, row by row), and be the same bytes at
    // any thread count.
    for (const int nc : {1, 3, 4}) {
        const int w = 517, h = 613; // several segments, rows not dividing them evenly
        std::vector<uint8_t> pixels(size_t(w) * size_t(h) * size_t(nc));
        for (size_t i = 0; i < pixels.size(); ++i) {
            const size_t p = i / size_t(nc), x = p % size_t(w), y = p / size_t(w);
            const uint8_t noise = uint8_t((i * 2654435761u) >> 11);
            // Bands of gradients, noise, flat paper and thin strokes: every filter wins somewhere.
            const size_t band = (y / 37) % 4;
            pixels[i] = band == 0 ? uint8_t(x + 3 * y + 11 * (i % size_t(nc)))
                        : band == 1 ? noise
                        : band == 2 ? uint8_t(250)
                                    : uint8_t((x + y) % 9 == 0 ? 20 : 245);
        }
        std::vector<unsigned char> ours, oneThread;
        std::string error;
        ASSERT_TRUE(encodePng8(w, h, nc, pixels.data(), ours, error)) << error;
        {
            tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
            ASSERT_TRUE(encodePng8(w, h, nc, pixels.data(), oneThread, error)) << error;
        }
        EXPECT_TRUE(ours == oneThread) << nc;
        const fs::path dir = rosy::test::freshDir("image", "png-large-" + std::to_string(nc));
        const fs::path file = dir / "ours.png", theirs = dir / "oiio.png";
        std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char *>(ours.data()),
                                                    std::streamsize(ours.size()));
        const ReadBack stored = readBack(file);
        ASSERT_EQ(stored.spec.width, w);
        ASSERT_EQ(stored.spec.nchannels, nc);
        EXPECT_TRUE(stored.bytes == pixels) << nc;
        OIIO::ImageSpec spec(w, h, nc, OIIO::TypeDesc::UINT8);
        spec.attribute("DateTime", "");
        spec.attribute("oiio:ColorSpace", "sRGB");
        if (nc == 4) {
            spec.channelnames = {"R", "G", "B", "A"};
            spec.alpha_channel = 3;
            spec.attribute("oiio:UnassociatedAlpha", 1);
        }
        auto out = OIIO::ImageOutput::create("png");
        ASSERT_TRUE(out && out->open(theirs.string(), spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
        ASSERT_TRUE(out->close());
        const size_t rawBytes = size_t(h) * (size_t(w) * size_t(nc) + 1);
        ASSERT_GT(rawBytes, size_t(256) << 10) << "the premise: more than one segment";
        const auto a = pngParts(slurp(file), rawBytes), b = pngParts(slurp(theirs), rawBytes);
        EXPECT_EQ(a.first.size(), rawBytes);
        EXPECT_TRUE(a.first == b.first) << nc << ": the filtered rows differ from libpng's";
        EXPECT_TRUE(a.second == b.second) << nc << ": the chunks besides IDAT differ";
    }
}

TEST(WritePng, LibpngErrorsComeBackAsMessages) {
    // libpng reports errors by longjmp into encodePng8(); each exit must come back as
    // false with a message, the file in memory kept within its bound
    // (tests/fuzz/fuzz_png.cpp drives the same exits with fuzzed shapes and bounds).
    std::vector<uint8_t> pixels(64 * 48 * 3);
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = uint8_t((i * 2654435761u) >> 13);
    std::vector<unsigned char> full, bounded;
    std::string error;
    ASSERT_TRUE(encodePng8(64, 48, 3, pixels.data(), full, error)) << error;
    ASSERT_GT(full.size(), 100u);
    // The bound cuts the file in the header, among the rows and in the last chunk.
    for (size_t bound : {size_t(0), size_t(20), full.size() / 2, full.size() - 1}) {
        error.clear();
        EXPECT_FALSE(encodePng8(64, 48, 3, pixels.data(), bounded, error, bound)) << bound;
        EXPECT_EQ(error, "PNG: the encoded image is larger than its bound") << bound;
        EXPECT_LE(bounded.size(), bound);
    }
    ASSERT_TRUE(encodePng8(64, 48, 3, pixels.data(), bounded, error, full.size())) << error;
    EXPECT_TRUE(bounded == full);
    // The same bound cuts in a large image's data, compressed in segments (its IDAT
    // chunks written through libpng as well).
    std::vector<uint8_t> large(400 * 300 * 3);
    for (size_t i = 0; i < large.size(); ++i) large[i] = uint8_t((i * 2654435761u) >> 13);
    ASSERT_TRUE(encodePng8(400, 300, 3, large.data(), full, error)) << error;
    for (size_t bound : {size_t(100), full.size() / 2, full.size() - 1}) {
        error.clear();
        EXPECT_FALSE(encodePng8(400, 300, 3, large.data(), bounded, error, bound)) << bound;
        EXPECT_EQ(error, "PNG: the encoded image is larger than its bound") << bound;
        EXPECT_LE(bounded.size(), bound);
    }
    // A side over libpng's limit (10^6) is rejected in png_set_IHDR, before any row
    // is read: the one row of pixels given is never touched past its end.
    error.clear();
    EXPECT_FALSE(encodePng8(1'000'001, 2, 1, pixels.data(), bounded, error));
    EXPECT_EQ(error.rfind("PNG: ", 0), 0u) << error;
    EXPECT_GT(error.size(), 5u);
    EXPECT_FALSE(encodePng8(0, 2, 1, pixels.data(), bounded, error));
    EXPECT_EQ(error, "PNG: unsupported image shape");
}
