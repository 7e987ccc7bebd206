#include "renderer/illustration.h"
#include "renderer/output/large_buffer.h"

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "renderer/view/embree_scene.h"

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

namespace rosy::renderer {
namespace {
using Clock = std::chrono::steady_clock;
} // namespace

double nominalHatchSpacingPx(const styles::HatchStyle &style) {
    // A light mid-tone, where most of a drawing's hatches sit: blurring at this
    // scale measures tone without averaging dark regions into their neighbours.
    return localSpacingPx(0.25, style);
}

namespace {

/// f() run so that, while this thread waits for f's own parallel loops, it takes no
/// other task: the contour task beside the hatching (finishIllustration()) would
/// hold up the tracer.
template <typename F> auto isolated(F &&f) { return tbb::this_task_arena::isolate(std::forward<F>(f)); }

/// The stages' order in Illustration::timingsMs, whichever ran first.
constexpr const char *kStageOrder[] = {"gbuffer", "tone", "scan_tone", "remesh", "screen_field", "hatching", "contours", "raster"};

} // namespace

namespace {

/// Tone → target ink density through the style's tone curve (Illustration::targetDensity).
void computeTargetDensity(Illustration &out, const IllustrationInput &in) {
    const std::vector<double> tone = shadeLambert(out.gbuffer, *in.scene, *in.mesh, *in.camera, in.lights, in.shading);
    assignLarge(out.targetDensity, out.gbuffer.nPixels(), 0.0f);
    const double gamma = in.style.hatch.toneGamma;
    // The curve saturates at the darkest coverage the style can draw: asking for
    // more would leave the whole shadow side short of its target by construction.
    const double darkest = maxHatchDensity(in.style.hatch);
    parallelFor(0, int64_t(tone.size()), [&](int64_t i) {
        if (out.gbuffer.faceId[size_t(i)] >= 0)
            out.targetDensity[size_t(i)] =
                float(std::min(darkest, std::pow(std::clamp(1.0 - tone[size_t(i)], 0.0, 1.0), gamma)));
    }, 16384);
}

} // namespace

void reshadeWithNormalsOf(Illustration &begun, const IllustrationInput &in, const field::Mesh &normalsOf) {
    ROSY_CHECK(in.mesh && in.scene && in.camera);
    ROSY_CHECK_EQ(normalsOf.nVertices(), in.mesh->nVertices());
    ROSY_CHECK_EQ(normalsOf.nFaces(), in.mesh->nFaces());
    const auto t0 = Clock::now();
    auto normals = std::make_shared<std::vector<Vec3>>();
    begun.gbuffer.cornerNormals = std::make_shared<const std::vector<Vec3>>(
        creaseAwareCornerNormals(normalsOf, kCreaseAngleDeg * M_PI / 180.0, normals.get()));
    begun.gbuffer.vertexNormals = std::move(normals);
    computeTargetDensity(begun, in);
    begun.shapeMesh = &normalsOf;
    if (!begun.contoursPending)
        begun.contourStrokes = extractContours(normalsOf, *in.camera, *in.scene, begun.gbuffer, in.style.contour,
                                               &begun.contours, /*scanCopy=*/true);
    begun.timingsMs.emplace_back("scan_tone",
                                 std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
}

Illustration beginIllustration(const IllustrationInput &in) {
    ROSY_CHECK(in.mesh && in.scene && in.camera);
    const Camera &camera = *in.camera;
    Illustration out;
    out.worldToCamera = camera.worldToCamera();
    out.worldToNdc = camera.worldToNdc();
    out.ink = in.style.ink;
    auto t0 = Clock::now();
    auto lap = [&](const char *name) {
        auto t = Clock::now();
        out.timingsMs.emplace_back(name, std::chrono::duration<double, std::milli>(t - t0).count());
        t0 = t;
    };
    out.gbuffer = renderGBuffer(*in.scene, *in.mesh, camera);
    lap("gbuffer");

    computeTargetDensity(out, in);
    lap("tone");

    // Contours need no field: traced here (or beside the hatching by
    // finishIllustration()), appended after the hatches by finishIllustration().
    if (in.contoursBesideHatching) {
        out.contoursPending = true;
        return out;
    }
    out.contourStrokes = extractContours(*in.mesh, camera, *in.scene, out.gbuffer, in.style.contour, &out.contours);
    lap("contours");
    return out;
}

void finishIllustration(Illustration &out, const IllustrationInput &in) {
    ROSY_CHECK(in.frames && in.field && in.singularities && in.camera);
    // Shaded from another mesh (a scan's smoothed copy): the field must be on its frames.
    ROSY_CHECK(!out.shapeMesh || &in.frames->mesh() == out.shapeMesh);
    const Camera &camera = *in.camera;
    // One display over the remaining stages, naming the running one, with the time
    // left estimated from their usual shares (--timings of scenes/bunny.yaml at 2048²);
    // it only shows on a terminal after about a second.
    std::vector<ProgressStage> stages = {{"screen field", 17}, {"hatching", 35}};
    if (in.raster) stages.push_back({"raster", 24});
    std::optional<Progress> progress;
    if (in.progress) progress.emplace("rendering", std::move(stages));
    size_t stage = 0;
    auto t0 = Clock::now();
    auto lap = [&](const char *name) {
        auto t = Clock::now();
        out.timingsMs.emplace_back(name, std::chrono::duration<double, std::milli>(t - t0).count());
        t0 = t;
        ++stage;
        if (progress) progress->beginStage(stage);
    };
    out.screen = computeScreenField(out.gbuffer, *in.frames, *in.field, *in.singularities, camera);
    lap("screen_field");

    // Contours left by beginIllustration(): a task beside the hatching's tracer, which
    // is sequential; started once the hatcher's per-pixel maps are built, as their
    // loops take every core. Both read the G-buffer; the task writes only the contour
    // members. If the hatching throws, the guard lets the task end before `out` goes.
    // The raster's blank layers and the paper under the ink need no strokes either:
    // made on the same task, so the raster stage only draws and mixes (16 MiB of
    // layers and 16 MiB of picture faulted in and the paper's grain: 5-8 ms of a 1024²
    // render). Declared before the guard, which must wait for the task first.
    InkLayers blankLayers;
    std::optional<Image> paper;
    tbb::task_group besideTask;
    struct WaitForTask {
        tbb::task_group &task;
        ~WaitForTask() {
            try {
                task.wait();
            } catch (...) { // second to the exception leaving finishIllustration()
            }
        }
    } waitForTask{besideTask};
    double contourMs = 0;
    const bool contoursHere = out.contoursPending;
    if (contoursHere) ROSY_CHECK(in.mesh && in.scene);
    bool besideStarted = false; // startBeside() was called (it may have nothing to run)
    auto startBeside = [&] {
        besideStarted = true;
        if (!contoursHere && !in.raster) return;
        besideTask.run([&] {
            if (contoursHere) {
                const auto start = Clock::now();
                out.contourStrokes =
                    extractContours(out.shapeMesh ? *out.shapeMesh : *in.mesh, camera, *in.scene, out.gbuffer,
                                    in.style.contour, &out.contours, out.shapeMesh != nullptr);
                contourMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
            }
            if (in.raster) {
                blankLayers = blankInkLayers(out.gbuffer.width, out.gbuffer.height);
                paper = paperImage(out.gbuffer.width, out.gbuffer.height, in.style);
            }
        });
    };

    styles::HatchStyle hatchStyle = in.style.hatch;
    if (in.quadLines) {
        // Lines on the surface need no calibration: their spacing is the mesh's.
        startBeside();
        hatchStyle.calibrateInk = false;
        out.strokes = isolated([&] {
            return quadLineHatches(*in.quadLines, out.screen, out.targetDensity, out.gbuffer, camera, hatchStyle,
                                   in.style.seed);
        });
        if (in.style.hatch.calibrateInk) {
            double askedAtMin = 0;
            const double asked = toneInkPx(out.screen, out.targetDensity, hatchStyle, &askedAtMin);
            out.inkFill = asked > 0 ? hatchInkPx(out.strokes) / asked : 1.0;
            out.inkAtMinSpacing = asked > 0 ? askedAtMin / asked : 0.0;
        }
    } else {
        out.strokes = isolated([&] {
            return traceHatches(out.screen, out.targetDensity, out.gbuffer, hatchStyle, in.style.seed, nullptr,
                                startBeside);
        });
    }
    ROSY_CHECK(besideStarted); // traceHatches() calls whileTracing on every path that returns
    if (hatchStyle.calibrateInk) {
        // Print mode: how much ink a Jobard-Lefer tracing lays down for the spacings
        // the tone asks for depends on the picture's size against them (line ends at
        // edges, minimum lengths of 4 d_sep, lines squeezed where the field converges:
        // fandisk drew 8 % more ink per mm² on A3 than on A4), and small dark bands a
        // few spacings wide keep their cross-hatching or lose it as the pitch moves a
        // stroke over the minimum length. So the hatching is traced again with every
        // spacing scaled by the last trace's ink over the tone's (spacingGain), twice,
        // and of the three traces the one whose ink is nearest the tone's is kept.
        double askedAtMin = 0;
        const double asked = toneInkPx(out.screen, out.targetDensity, hatchStyle, &askedAtMin);
        double drawn = hatchInkPx(out.strokes);
        out.inkFill = asked > 0 ? drawn / asked : 1.0;
        out.inkAtMinSpacing = asked > 0 ? askedAtMin / asked : 0.0;
        if (asked > 0 && drawn > 0) {
            double bestError = std::abs(drawn / asked - 1.0);
            styles::HatchStyle next = hatchStyle;
            for (int trace = 1; trace < kInkCalibrationTraces; ++trace) {
                next.spacingGain = std::clamp(next.spacingGain * drawn / asked, kMinSpacingGain, kMaxSpacingGain);
                StrokeList strokes = isolated(
                    [&] { return traceHatches(out.screen, out.targetDensity, out.gbuffer, next, in.style.seed); });
                drawn = hatchInkPx(strokes);
                if (!(drawn > 0)) break;
                if (std::abs(drawn / asked - 1.0) < bestError) {
                    bestError = std::abs(drawn / asked - 1.0);
                    out.inkFill = drawn / asked;
                    out.strokes = std::move(strokes);
                    hatchStyle = next;
                }
            }
        }
        out.spacingGain = hatchStyle.spacingGain;
    }
    if (in.measureHatching == HatchMeasure::All)
        out.hatch = isolated([&] { return measureHatches(out.strokes, out.screen, out.targetDensity, hatchStyle); });
    else if (in.measureHatching == HatchMeasure::Counts)
        out.hatch = isolated([&] { return countHatches(out.strokes, out.screen, out.targetDensity, hatchStyle); });
    lap("hatching");
    besideTask.wait();  // rethrows the task's failure
    t0 = Clock::now(); // the raster's time starts after the wait
    if (contoursHere) {
        out.contoursPending = false;
        out.timingsMs.emplace_back("contours", contourMs);
    }

    // Contour ids start at kContourIdBase, so every stroke's id stays unique.
    for (Stroke &s : out.contourStrokes.strokes) out.strokes.strokes.push_back(std::move(s));
    out.contourStrokes = {};
    out.strokes.width = out.gbuffer.width;
    out.strokes.height = out.gbuffer.height;

    if (in.raster) {
        ROSY_CHECK(paper); // made beside the tracer, which starts the task on every path
        out.layers = rasterizeStrokes(out.strokes, std::move(blankLayers));
        out.composite = compositeInk(out.layers, in.style, std::move(*paper));
        lap("raster");
    }
    if (progress) progress->finish();
    std::stable_sort(out.timingsMs.begin(), out.timingsMs.end(), [](const auto &a, const auto &b) {
        auto rank = [](const std::string &name) {
            return std::find_if(std::begin(kStageOrder), std::end(kStageOrder),
                                [&](const char *s) { return name == s; }) -
                   std::begin(kStageOrder);
        };
        return rank(a.first) < rank(b.first);
    });
}

Illustration renderIllustration(const IllustrationInput &in) {
    ROSY_CHECK(in.mesh && in.frames && in.field && in.singularities && in.scene && in.camera);
    Illustration out = beginIllustration(in);
    finishIllustration(out, in);
    return out;
}

const std::vector<std::string> &illustrationExrChannelNames() {
    static const std::vector<std::string> names = {
        "R",           "G",          "B",          "A",          "tone.target", "ink.coverage", "ink.hatch0",
        "ink.hatch1",  "ink.contour", "ink.hidden", "Z",         "N.x",         "N.y",          "N.z",
        "field.angle0", "field.angle1", "field.cos", "field.sin", "mask"};
    return names;
}

int fieldHarmonic(int nSym) { return nSym % 2 != 0 ? 2 * nSym : nSym; }

namespace {

/// OpenEXR's M44f of a column-vector matrix: Imath multiplies row vectors, so the
/// file holds the transpose, row by row.
ImageAttribute exrMatrix(const char *name, const Eigen::Matrix4d &m) {
    std::array<float, 16> rows{};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) rows[size_t(4 * r + c)] = float(m(c, r));
    return ImageAttribute::matrix44(name, rows);
}

} // namespace

namespace {

constexpr size_t kExrChannels = 19; // illustrationExrChannelNames().size()

/// The illustration's per-pixel planes, where present, have one value per pixel.
void checkPlanes(const Illustration &il) {
    const size_t n = il.gbuffer.nPixels();
    const InkLayers &layers = il.layers;
    for (const std::vector<float> *v : {&layers.hatch0, &layers.hatch1, &layers.contour, &layers.hiddenContour,
                                        &il.targetDensity})
        if (!v->empty()) ROSY_CHECK_EQ(v->size(), n);
    if (!il.screen.lines.empty()) ROSY_CHECK_EQ(il.screen.lines.size(), n);
}

/// Pixel i of illustrationExr(), its channels in illustrationExrChannelNames() order,
/// into px[0, kExrChannels), which holds zeros on entry (channels 11-18 stay 0 off the
/// object). `coverage` is combinedCoverage(il.layers), k fieldHarmonic(N).
void exrPixel(const Illustration &il, const std::vector<float> &coverage, int k, size_t i, float *px) {
    const InkLayers &layers = il.layers;
    auto get = [](const std::vector<float> &v, size_t j) { return v.empty() || !std::isfinite(v[j]) ? 0.0f : v[j]; };
    const float a = coverage[i];
    for (int c = 0; c < 3; ++c) px[c] = float(il.ink[size_t(c)]) * a;
    px[3] = a;
    px[4] = get(il.targetDensity, i);
    px[5] = a;
    px[6] = get(layers.hatch0, i);
    px[7] = get(layers.hatch1, i);
    px[8] = get(layers.contour, i);
    px[9] = get(layers.hiddenContour, i);
    const bool onObject = il.gbuffer.faceId[i] >= 0;
    px[10] = onObject ? il.gbuffer.depth[i] : std::numeric_limits<float>::infinity();
    if (onObject) {
        const Vec3 nrm = il.gbuffer.normal(i);
        px[11] = float(nrm.x()), px[12] = float(nrm.y()), px[13] = float(nrm.z());
        const bool field = !il.screen.lines.empty();
        const float angle0 = field ? il.screen.angle(0, i) : 0.0f;
        px[14] = angle0;
        px[15] = field ? il.screen.angle(1, i) : 0.0f;
        px[16] = float(std::cos(double(k) * angle0));
        px[17] = float(std::sin(double(k) * angle0));
        px[18] = 1.0f;
    }
}

} // namespace

Image illustrationExr(const Illustration &il) {
    const int width = il.gbuffer.width, height = il.gbuffer.height;
    const size_t n = il.gbuffer.nPixels();
    checkPlanes(il);
    const std::vector<float> coverage = combinedCoverage(il.layers);
    Image image(width, height, illustrationExrChannelNames());
    ROSY_CHECK_EQ(size_t(image.nChannels), kExrChannels);
    image.premultipliedAlpha = true;
    const int k = fieldHarmonic(il.screen.nSym);
    parallelFor(0, int64_t(n), [&](int64_t i) {
        exrPixel(il, coverage, k, size_t(i), &image.data[size_t(i) * kExrChannels]);
    }, 4096);
    image.attributes.push_back(exrMatrix("worldToCamera", il.worldToCamera));
    image.attributes.push_back(exrMatrix("worldToNDC", il.worldToNdc));
    image.attributes.push_back(ImageAttribute::integer("rosy:symmetry", il.screen.nSym));
    image.attributes.push_back(ImageAttribute::integer("rosy:field_harmonic", k));
    return image;
}

InkMaps illustrationInkMaps(const Illustration &il, const styles::HatchStyle &style) {
    // The EXR's values pixel by pixel (exrPixel(), what illustrationExr() stores), so
    // they are exactly those `rosyhatch inspect` would read from the file (float
    // rounding, zeroed angles off the object), without the 19-channel image in memory.
    checkPlanes(il);
    const size_t n = il.gbuffer.nPixels();
    const std::vector<float> coverage = combinedCoverage(il.layers);
    const int k = fieldHarmonic(il.screen.nSym);
    const std::vector<std::string> &names = illustrationExrChannelNames();
    ROSY_CHECK_EQ(names.size(), kExrChannels);
    auto channel = [&](const char *name) {
        const auto it = std::find(names.begin(), names.end(), name);
        ROSY_CHECK(it != names.end());
        return size_t(it - names.begin());
    };
    InkMaps maps;
    maps.width = il.gbuffer.width;
    maps.height = il.gbuffer.height;
    const std::pair<std::vector<float> *, size_t> outputs[] = {
        {&maps.hatch0, channel("ink.hatch0")},    {&maps.hatch1, channel("ink.hatch1")},
        {&maps.coverage, channel("ink.coverage")}, {&maps.target, channel("tone.target")},
        {&maps.angle0, channel("field.angle0")},   {&maps.angle1, channel("field.angle1")},
        {&maps.mask, channel("mask")}};
    for (const auto &[plane, c] : outputs) plane->resize(n);
    parallelFor(0, int64_t(n), [&](int64_t i) {
        std::array<float, kExrChannels> px{};
        exrPixel(il, coverage, k, size_t(i), px.data());
        for (const auto &[plane, c] : outputs) (*plane)[size_t(i)] = px[c];
    }, 4096);
    maps.hatchSpacingPx = float(nominalHatchSpacingPx(style)); // the header stores a float
    maps.crossDensity = float(style.crossDensity);
    return maps;
}

} // namespace rosy::renderer
