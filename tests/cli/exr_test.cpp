// The EXR of `rosyhatch render` as a compositor reads it: read back with
// OpenImageIO itself (not through our image layer), the camera matrices checked
// by projecting known world points the OpenEXR way (row vector times matrix,
// divide by w) and finding them where a pinhole camera of that field of view
// must put them; Z, the ink matte, the hidden-contour layer and the filter-safe
// field pair checked against what they are defined to hold (README, "EXR").

#include "cli_util.h"

#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

namespace fs = std::filesystem;

namespace {

fs::path workDir() { return rosy::test::testOutputDir("exr-cli"); }

using rosy::test::CliRun;

CliRun run(const std::string &args, const std::string &tag) { return rosy::test::runRosyhatch(workDir(), args, tag); }

constexpr double kPi = 3.14159265358979323846;

/// An EXR read with OpenImageIO: spec (attributes) and all channels by name.
struct Exr {
    OIIO::ImageSpec spec;
    std::map<std::string, std::vector<float>> channels;
    float at(const std::string &name, int x, int y) const {
        return channels.at(name)[size_t(y) * size_t(spec.width) + size_t(x)];
    }
    /// The header's M44f, row-major as Imath stores it; NaNs if absent or of another type.
    std::array<float, 16> matrix(const std::string &name) const {
        std::array<float, 16> m;
        m.fill(NAN);
        const OIIO::ParamValue *p = spec.find_attribute(name);
        if (p && p->type() == OIIO::TypeMatrix44) std::copy_n(static_cast<const float *>(p->data()), 16, m.begin());
        return m;
    }
};

Exr readExr(const fs::path &path) {
    Exr exr;
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) return exr;
    exr.spec = in->spec();
    const size_t n = size_t(exr.spec.width) * size_t(exr.spec.height), nc = size_t(exr.spec.nchannels);
    std::vector<float> all(n * nc);
    in->read_image(0, 0, 0, exr.spec.nchannels, OIIO::TypeDesc::FLOAT, all.data());
    for (size_t c = 0; c < nc; ++c) {
        std::vector<float> v(n);
        for (size_t i = 0; i < n; ++i) v[i] = all[i * nc + c];
        exr.channels[exr.spec.channelnames[c]] = v;
    }
    return exr;
}

/// OpenEXR's way: [x y z 1] · M, then divide by w (Imath's multVecMatrix).
std::array<double, 3> transformPoint(const std::array<float, 16> &m, double x, double y, double z) {
    double out[4];
    for (int c = 0; c < 4; ++c) out[c] = x * m[size_t(c)] + y * m[size_t(4 + c)] + z * m[size_t(8 + c)] + m[size_t(12 + c)];
    return {out[0] / out[3], out[1] / out[3], out[2] / out[3]};
}

// Unit sphere at the origin, camera on +z at distance 5 looking at it, 40° vertical
// field of view, a 64 x 48 image (not square, so width and height cannot be swapped).
const char *kSphereScene = "mesh: {primitive: icosphere, subdivisions: 4}\n"
                           "camera: {position: [0, 0, 5], look_at: [0, 0, 0], fov: 40, resolution: [64, 48]}\n";

} // namespace

TEST(ExrCli, CameraMatricesProjectKnownPointsToTheirPixels) {
    std::ofstream(workDir() / "sphere.yaml") << kSphereScene;
    ASSERT_EQ(run("render sphere.yaml -o sphere.exr -q", "sphere").exitCode, 0);
    const Exr exr = readExr(workDir() / "sphere.exr");
    ASSERT_EQ(exr.spec.width, 64);
    const std::array<float, 16> toCamera = exr.matrix("worldToCamera"), toNdc = exr.matrix("worldToNDC");
    ASSERT_FALSE(std::isnan(toCamera[0])) << "no M44f worldToCamera";
    ASSERT_FALSE(std::isnan(toNdc[0])) << "no M44f worldToNDC";

    // Camera space (OpenEXR: left-handed, x right, y up, z forward): the origin is 5
    // in front, +x world is right, +y world is up.
    const auto o = transformPoint(toCamera, 0, 0, 0);
    EXPECT_NEAR(o[0], 0.0, 1e-5);
    EXPECT_NEAR(o[1], 0.0, 1e-5);
    EXPECT_NEAR(o[2], 5.0, 1e-5);
    const auto px = transformPoint(toCamera, 1, 2, 0);
    EXPECT_NEAR(px[0], 1.0, 1e-5);
    EXPECT_NEAR(px[1], 2.0, 1e-5);
    EXPECT_NEAR(px[2], 5.0, 1e-5);

    // NDC: (0, 0) top-left corner, (1, 1) bottom-right, y down. A pinhole of vertical
    // fov 40° at distance z puts camera-space (x, y) at pixel
    //   (W/2 + f x / z, H/2 − f y / z),  f = (H/2) / tan(20°).
    const double f = 24.0 / std::tan(20.0 * kPi / 180.0);
    const std::array<std::array<double, 3>, 4> points = {{{0, 0, 0}, {0.6, 0.3, 0.7}, {-0.5, -0.4, 0.2}, {1, 1, -1}}};
    for (const auto &p : points) {
        const auto ndc = transformPoint(toNdc, p[0], p[1], p[2]);
        const double z = 5.0 - p[2];
        EXPECT_NEAR(ndc[0] * 64.0, 32.0 + f * p[0] / z, 1e-3) << p[0] << " " << p[1] << " " << p[2];
        EXPECT_NEAR(ndc[1] * 48.0, 24.0 - f * p[1] / z, 1e-3) << p[0] << " " << p[1] << " " << p[2];
    }

    // A point on the sphere's surface facing the camera: at the pixel the matrix puts it,
    // the render sees the sphere at the camera-space depth the matrix gives it (Z),
    // within the tessellation's error.
    const double s = 1.0 / std::sqrt(0.3 * 0.3 + 0.2 * 0.2 + 0.9 * 0.9);
    const double q[3] = {0.3 * s, 0.2 * s, 0.9 * s};
    const auto ndc = transformPoint(toNdc, q[0], q[1], q[2]);
    const int ix = int(std::floor(ndc[0] * 64.0)), iy = int(std::floor(ndc[1] * 48.0));
    ASSERT_TRUE(ix >= 0 && ix < 64 && iy >= 0 && iy < 48);
    EXPECT_LT(iy, 24) << "a point above the axis is in the upper half";
    EXPECT_GT(ix, 32) << "a point right of the axis is in the right half";
    EXPECT_EQ(exr.at("mask", ix, iy), 1.0f);
    EXPECT_NEAR(exr.at("Z", ix, iy), transformPoint(toCamera, q[0], q[1], q[2])[2], 0.02);
    // The pixel at the centre sees the sphere's pole at depth 5 − 1.
    EXPECT_NEAR(exr.at("Z", 32, 24), 4.0, 0.01);
}

TEST(ExrCli, OrthographicMatricesToo) {
    std::ofstream(workDir() / "ortho.yaml")
        << "mesh: {primitive: icosphere}\n"
           "camera: {projection: orthographic, position: [0, 0, 5], look_at: [0, 0, 0], height: 3, "
           "resolution: [64, 48]}\n";
    ASSERT_EQ(run("render ortho.yaml -o ortho.exr -q", "ortho").exitCode, 0);
    const Exr exr = readExr(workDir() / "ortho.exr");
    const std::array<float, 16> toNdc = exr.matrix("worldToNDC");
    ASSERT_FALSE(std::isnan(toNdc[0]));
    // 48 pixels show 3 world units: 16 px per unit, whatever the depth.
    for (const double z : {0.0, 0.9}) {
        const auto ndc = transformPoint(toNdc, 1.0, 0.5, z);
        EXPECT_NEAR(ndc[0] * 64.0, 32.0 + 16.0, 1e-3);
        EXPECT_NEAR(ndc[1] * 48.0, 24.0 - 8.0, 1e-3);
    }
    EXPECT_NEAR(exr.at("Z", 32, 24), 4.0, 0.01);
}

TEST(ExrCli, ChannelsForCompositors) {
    // A torus seen nearly edge-on, hidden contours on: the inner rim is hidden.
    std::ofstream(workDir() / "torus.yaml") << "mesh: {primitive: torus, nu: 48, nv: 24}\n"
                                               "camera: {resolution: [96, 72], direction: [0, 1, 0.2]}\n"
                                               "style: {contour: {hidden: true}}\n";
    ASSERT_EQ(run("render torus.yaml -o torus.exr -o torus.png -q", "torus").exitCode, 0);
    const Exr exr = readExr(workDir() / "torus.exr");
    ASSERT_EQ(exr.spec.width, 96);
    for (const char *name : {"R", "G", "B", "A", "Z", "ink.coverage", "ink.hidden", "field.angle0", "field.cos",
                             "field.sin", "mask"})
        EXPECT_EQ(exr.channels.count(name), 1u) << name;
    EXPECT_EQ(exr.spec.alpha_channel >= 0 ? exr.spec.channelnames[size_t(exr.spec.alpha_channel)] : "", "A");
    EXPECT_EQ(exr.spec.get_int_attribute("oiio:UnassociatedAlpha", 0), 0) << "OpenEXR alpha is premultiplied";
    EXPECT_EQ(exr.spec.get_int_attribute("rosy:symmetry", 0), 4);
    EXPECT_EQ(exr.spec.get_int_attribute("rosy:field_harmonic", 0), 4);

    // The PNG of the same render, read back (8-bit sRGB): it must be the EXR's
    // premultiplied ink over the (white) paper.
    auto png = OIIO::ImageInput::open((workDir() / "torus.png").string());
    ASSERT_TRUE(png);
    const int pc = png->spec().nchannels;
    std::vector<float> picture(size_t(96 * 72 * pc));
    ASSERT_TRUE(png->read_image(0, 0, 0, pc, OIIO::TypeDesc::FLOAT, picture.data()));
    auto toSrgb = [](double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055; };
    double hidden = 0.0, worstOver = 0.0, worstPair = 0.0;
    int background = 0, inked = 0;
    for (int y = 0; y < 72; ++y)
        for (int x = 0; x < 96; ++x) {
            const float a = exr.at("A", x, y);
            EXPECT_EQ(a, exr.at("ink.coverage", x, y));
            if (a > 0.5f) ++inked;
            for (int c = 0; c < 3; ++c) {
                const double over = exr.at(std::string(1, "RGB"[c]), x, y) + (1.0 - a);
                worstOver = std::max(worstOver, std::abs(toSrgb(over) - picture[size_t((y * 96 + x) * pc + c)]));
            }
            hidden = std::max(hidden, double(exr.at("ink.hidden", x, y)));
            const float mask = exr.at("mask", x, y), z = exr.at("Z", x, y);
            if (mask == 0.0f) {
                ++background;
                EXPECT_TRUE(std::isinf(z) && z > 0) << x << "," << y << ": " << z;
                EXPECT_EQ(exr.at("field.cos", x, y), 0.0f);
            } else {
                EXPECT_TRUE(std::isfinite(z) && z > 0);
                // (cos 4θ, sin 4θ) of the stored angle.
                const double theta = exr.at("field.angle0", x, y);
                worstPair = std::max({worstPair, std::abs(exr.at("field.cos", x, y) - std::cos(4 * theta)),
                                      std::abs(exr.at("field.sin", x, y) - std::sin(4 * theta))});
            }
        }
    EXPECT_LT(worstOver, 1.0 / 255.0 + 1e-6) << "A over paper differs from the PNG";
    EXPECT_LT(worstPair, 1e-5);
    EXPECT_GT(background, 96 * 72 / 10);
    EXPECT_GT(inked, 20) << "an ink matte, not 0 everywhere";
    EXPECT_LT(inked, 96 * 72 / 2) << "an ink matte, not 1 everywhere";
    EXPECT_EQ(hidden, 1.0) << "the hidden rim is in ink.hidden";
}
