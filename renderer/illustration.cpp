#include "renderer/illustration.h"
#include "renderer/large_buffer.h"

#include "core/error.h"
#include "core/progress.h"
#include "renderer/embree_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace rosy::renderer {
namespace {
using Clock = std::chrono::steady_clock;
} // namespace

double nominalHatchSpacingPx(const styles::HatchStyle &style) {
    // A light mid-tone, where most of a drawing's hatches sit: blurring at this
    // scale measures tone without averaging dark regions into their neighbours.
    return localSpacingPx(0.25, style);
}

Illustration renderIllustration(const IllustrationInput &in) {
    ROSY_CHECK(in.mesh && in.frames && in.field && in.singularities && in.scene && in.camera);
    const Camera &camera = *in.camera;
    Illustration out;
    // One bar over the six stages; it only shows on a terminal after about a second.
    Progress progress("rendering", 6);
    auto t0 = Clock::now();
    auto lap = [&](const char *stage) {
        auto t = Clock::now();
        out.timingsMs.emplace_back(stage, std::chrono::duration<double, std::milli>(t - t0).count());
        t0 = t;
        progress.advance();
    };
    out.gbuffer = renderGBuffer(*in.scene, *in.mesh, camera);
    lap("gbuffer");

    // Tone → target ink density through the style's tone curve.
    const std::vector<double> tone = shadeLambert(out.gbuffer, *in.scene, *in.mesh, camera, in.lights, in.shading);
    assignLarge(out.targetDensity, out.gbuffer.nPixels(), 0.0f);
    const double gamma = in.style.hatch.toneGamma;
    // The curve saturates at the darkest coverage the style can draw: asking for
    // more would leave the whole shadow side short of its target by construction.
    const double darkest = maxHatchDensity(in.style.hatch);
    for (size_t i = 0; i < tone.size(); ++i)
        if (out.gbuffer.faceId[i] >= 0)
            out.targetDensity[i] = float(std::min(darkest, std::pow(std::clamp(1.0 - tone[i], 0.0, 1.0), gamma)));
    lap("tone");

    out.screen = computeScreenField(out.gbuffer, *in.frames, *in.field, *in.singularities, camera);
    lap("screen_field");

    out.strokes = traceHatches(out.screen, out.targetDensity, out.gbuffer, in.style.hatch, in.style.seed);
    if (in.measureHatching) out.hatch = measureHatches(out.strokes, out.screen, out.targetDensity, in.style.hatch);
    lap("hatching");

    StrokeList contours = extractContours(*in.mesh, camera, *in.scene, out.gbuffer, in.style.contour, &out.contours);
    // Contour ids start at kContourIdBase, so every stroke's id stays unique.
    for (Stroke &s : contours.strokes) out.strokes.strokes.push_back(std::move(s));
    out.strokes.width = out.gbuffer.width;
    out.strokes.height = out.gbuffer.height;
    lap("contours");

    out.layers = rasterizeStrokes(out.strokes);
    out.composite = compositeInk(out.layers, in.style);
    lap("raster");
    progress.finish();
    return out;
}

Image illustrationExr(const Illustration &il) {
    SurfaceChannels surface;
    const size_t n = il.gbuffer.nPixels();
    surface.targetDensity = il.targetDensity;
    surface.depth.assign(n, 0.0f);
    surface.normalX.assign(n, 0.0f);
    surface.normalY.assign(n, 0.0f);
    surface.normalZ.assign(n, 0.0f);
    surface.mask.assign(n, 0.0f);
    for (size_t i = 0; i < n; ++i) {
        if (il.gbuffer.faceId[i] < 0) continue;
        surface.depth[i] = il.gbuffer.depth[i];
        const Vec3 nrm = il.gbuffer.normal(i);
        surface.normalX[i] = float(nrm.x());
        surface.normalY[i] = float(nrm.y());
        surface.normalZ[i] = float(nrm.z());
        surface.mask[i] = 1.0f;
    }
    surface.angle0 = il.screen.angle0;
    surface.angle1 = il.screen.angle1;
    return inkExrImage(il.layers, il.composite, surface);
}

InkMaps illustrationInkMaps(const Illustration &il, const styles::HatchStyle &style) {
    // Through the EXR image itself, so the values (float rounding, zeroed angles off
    // the object) are exactly those `rosyhatch inspect` would read from the file.
    const Image exr = illustrationExr(il);
    const std::vector<std::string> &names = exr.channelNames;
    auto channel = [&](const char *name) {
        const auto it = std::find(names.begin(), names.end(), name);
        ROSY_CHECK(it != names.end());
        const size_t c = size_t(it - names.begin()), nc = size_t(exr.nChannels);
        std::vector<float> v(size_t(exr.width) * size_t(exr.height));
        for (size_t i = 0; i < v.size(); ++i) v[i] = exr.data[i * nc + c];
        return v;
    };
    InkMaps maps;
    maps.width = exr.width;
    maps.height = exr.height;
    maps.hatch0 = channel("ink.hatch0");
    maps.hatch1 = channel("ink.hatch1");
    maps.coverage = channel("ink.coverage");
    maps.target = channel("tone.target");
    maps.angle0 = channel("field.angle0");
    maps.angle1 = channel("field.angle1");
    maps.mask = channel("mask");
    maps.hatchSpacingPx = float(nominalHatchSpacingPx(style)); // the header stores a float
    maps.crossDensity = float(style.crossDensity);
    return maps;
}

} // namespace rosy::renderer
