#include "scenes/pipeline.h"

#include "core/diagnostics.h"
#include "core/progress.h"
#include "remesh/edge_lines.h"
#include "remesh/remesh.h"
#include "renderer/field_picture.h"

#include <fmt/format.h>
#include <tbb/task_group.h>

#include <chrono>
#include <cmath>
#include <exception>
#include <optional>

namespace rosy::scenes {

namespace {

/// Times one stage, records it in `timings` (when given) and tells options.onStageStart
/// and options.onStage.
template <typename F>
auto timed(const std::string &stage, StageTimings *timings, const PipelineOptions &options, F &&work) {
    if (options.onStageStart) options.onStageStart(stage);
    const auto start = std::chrono::steady_clock::now();
    auto result = work();
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (timings) timings->emplace_back(stage, ms);
    if (options.onStage) options.onStage(stage, ms);
    return result;
}

} // namespace

ThreadLimit::ThreadLimit(const SceneDesc &desc, std::optional<int> threads) {
    const int n = threads ? *threads : desc.threads.value;
    if (n > 0) m_control.emplace(tbb::global_control::max_allowed_parallelism, size_t(n));
}

namespace {

/// The "load" stage: buildScene() and options.afterLoad.
std::unique_ptr<Scene> loadSceneObjects(const SceneDesc &desc, const PipelineOptions &options,
                                        StageTimings *timings) {
    return timed("load", timings, options, [&] {
        auto scene = std::make_unique<Scene>(buildScene(desc, options.load));
        if (options.afterLoad) options.afterLoad(*scene);
        return scene;
    });
}

/// The "frames" stage.
std::unique_ptr<field::TangentFrames> buildFrames(const Scene &scene, const PipelineOptions &options,
                                                  StageTimings *timings) {
    return timed("frames", timings, options, [&] { return std::make_unique<field::TangentFrames>(scene.mesh); });
}

/// What beginIllustration() reads: the scene's mesh, camera, lights, shading and
/// style and the ray scene (not the frames: they may still be being built).
renderer::IllustrationInput viewInput(const Scene &scene, const renderer::RayScene &rays) {
    renderer::IllustrationInput in;
    in.mesh = &scene.mesh;
    in.scene = &rays;
    in.camera = &scene.camera;
    in.lights = scene.lights;
    in.shading = scene.shading;
    in.style = scene.style;
    return in;
}

} // namespace

std::shared_ptr<const field::SmoothedSurface> LoadedScene::smoothedCopy() const {
    ROSY_CHECK(frames && m_copyCache);
    tbb::collaborative_call_once(m_copyCache->once, [&] {
        m_copyCache->copy = std::make_shared<const field::SmoothedSurface>(field::smoothAtScale(frames->mesh()));
    });
    return m_copyCache->copy;
}

LoadedScene loadScene(const SceneDesc &desc, const PipelineOptions &options, StageTimings *timings) {
    LoadedScene loaded;
    loaded.scene = loadSceneObjects(desc, options, timings);
    loaded.frames = buildFrames(*loaded.scene, options, timings);
    return loaded;
}

SceneFieldResult buildSceneField(const LoadedScene &loaded, const FieldDesc &fieldDesc,
                                 const PipelineOptions &options, StageTimings *timings) {
    SceneFieldResult out;
    out.spec = fieldDesc.spec;
    if (options.nSym > 0) out.spec.nSym = options.nSym;
    const bool editing = options.applyEdits && !fieldDesc.edits.empty();
    const field::TangentFrames &frames = *loaded.frames;
    const field::Mesh &mesh = frames.mesh();
    std::optional<field::RosyField> unedited;
    // Whether the field on the surface itself is scan noise (field/scan_noise.h),
    // judged on the field before any edits: their ids name the singularities the
    // user saw, which on a noisy scan are the smoothed copy's. An earlier judgement of
    // this loaded scene may stand for it (PipelineOptions::judgedNoisy).
    bool noisy = false;
    if (options.judgedNoisy) {
        noisy = true;
        out.noisySingularities = *options.judgedNoisy;
    } else {
        out.field = timed("field", timings, options, [&] {
            field::FieldResult r = field::buildField(frames, out.spec, options.fieldCache);
            if (editing) {
                const size_t n = field::findSingularities(frames, r.field).singularities.size();
                if ((noisy = field::fieldIsScanNoise(mesh, n))) {
                    out.noisySingularities = n;
                    return r;
                }
                if (options.keepUnedited) unedited = r.field;
                out.edits = field::applyFieldEdits(frames, r.field, fieldDesc.edits);
            }
            return r;
        });
    }
    if (!noisy) {
        out.singularities = timed("singularities", timings, options,
                                  [&] { return field::findSingularities(frames, out.field.field); });
        noisy = !editing && field::fieldIsScanNoise(mesh, out.singularities.singularities.size());
        if (noisy) out.noisySingularities = out.singularities.singularities.size();
    }
    if (noisy) {
        // Everything again on the smoothed copy; the scene's frames get the field carried back.
        out.noisyDensity = field::singularityDensity(mesh, out.noisySingularities);
        out.smoothedSurface = timed("scan_field", timings, options, [&] {
            out.field = {}; // the noise's field and its curvature: not kept beside the copy's
            const auto smoothingStart = std::chrono::steady_clock::now();
            std::shared_ptr<const field::SmoothedSurface> copy = loaded.smoothedCopy();
            out.smoothingMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                                        smoothingStart).count();
            const field::TangentFrames &smooth = *copy->frames;
            field::FieldResult r = field::buildField(smooth, out.spec);
            // Kept on the copy: its singularities are found there, below, then it is carried back.
            if (editing && options.keepUnedited) unedited = r.field;
            if (editing) out.edits = field::applyFieldEdits(smooth, r.field, fieldDesc.edits);
            out.singularities = field::placedOn(field::findSingularities(smooth, r.field), mesh);
            out.smoothedField = r.field;
            r.field = field::carryField(smooth, r.field, frames);
            out.field = std::move(r);
            return copy;
        });
        warn(mesh.name(), "scan-noise",
             fmt::format("the field on this surface has {} singularities, {:.0f} per ({:g} x diagonal)^2 of surface "
                         "(clean meshes have a few): its noise, not its shape; the field was computed on a copy "
                         "smoothed at {:g} x diagonal, which has {}, and carried back",
                         out.noisySingularities, out.noisyDensity, field::kScanNoiseScale,
                         field::kScanSmoothingRadius, out.singularities.singularities.size()));
    }
    const field::TangentFrames &fieldFrames = out.fieldFrames(frames);
    if (options.separatrices)
        out.separatrices = timed("separatrices", timings, options, [&] {
            return field::traceSeparatrices(fieldFrames, out.fieldOnFieldFrames(), out.singularities.singularities);
        });
    if (unedited)
        out.unedited = timed("unedited", timings, options, [&] {
            SceneFieldResult::Unedited u{std::move(*unedited), {}, {}};
            u.singularities = field::findSingularities(fieldFrames, u.field);
            if (options.separatrices)
                u.separatrices = field::traceSeparatrices(fieldFrames, u.field, u.singularities.singularities);
            if (out.smoothedSurface) {
                u.singularities = field::placedOn(std::move(u.singularities), mesh);
                u.field = field::carryField(fieldFrames, u.field, frames);
            }
            return u;
        });
    return out;
}

SceneField buildSceneField(const SceneDesc &desc, const PipelineOptions &options) {
    const ThreadLimit limit(desc, options.threads);
    SceneField out;
    out.loaded = loadScene(desc, options, &out.timingsMs);
    out.field = buildSceneField(out.loaded, desc.field, options, &out.timingsMs);
    return out;
}

renderer::Illustration beginHatching(const Scene &scene, const renderer::RayScene &rays,
                                     bool contoursBesideHatching) {
    renderer::IllustrationInput in = viewInput(scene, rays);
    in.contoursBesideHatching = contoursBesideHatching;
    return renderer::beginIllustration(in);
}

namespace {

/// style.hatch.lines: quad_mesh: the field's quad remesh (remesh::remesh(), edge
/// hatch.quad_edge_px on screen at the mesh's bounding-box centre) and its edge lines.
std::vector<renderer::SurfaceLine> quadMeshLines(const LoadedScene &loaded, const field::RosyField &rosyField,
                                                 const field::SingularityReport &singularities, bool progress) {
    const Scene &scene = *loaded.scene;
    if (4 % rosyField.nSym != 0)
        throw InputError(FileLoc{scene.mesh.name()},
                         fmt::format("style.hatch.lines: quad_mesh hatches along a quad mesh, which needs a 4-RoSy "
                                     "field (or a 2- or 1-RoSy, which with its perpendicular makes one); this field "
                                     "has N = {}",
                                     rosyField.nSym),
                         "set field.symmetry: 4 (or 2), or hatch.lines: field");
    // A 1- or 2-RoSy and its perpendicular are a cross: the 4-RoSy whose angle is
    // the same, γ₄ = |γ| (γ / |γ|)^(4 / N).
    field::RosyField cross = rosyField;
    if (rosyField.nSym != 4) {
        cross.nSym = 4;
        for (Eigen::Index v = 0; v < cross.u.size(); ++v) {
            const double r = std::abs(rosyField.u[v]);
            cross.u[v] = r > 0 ? r * std::pow(rosyField.u[v] / r, 4 / rosyField.nSym) : field::Complex(0, 0);
        }
    }
    Vec3 lo, hi;
    scene.mesh.bounds(lo, hi);
    const double pxPerWorld = scene.camera.projectJacobian(0.5 * (lo + hi)).norm() / std::sqrt(2.0);
    if (!(pxPerWorld > 0) || !std::isfinite(pxPerWorld))
        throw InputError(FileLoc{scene.mesh.name()},
                         "style.hatch.lines: quad_mesh: the camera sees the mesh's centre at no size, so no edge "
                         "length follows from hatch.quad_edge_px",
                         "frame the mesh (camera.auto: true)");
    remesh::RemeshOptions options;
    options.edgeLength = scene.style.hatch.quadEdgePx / pxPerWorld;
    // Seconds on a large picture (bunny00 at 1024²: about four times the rest of the
    // render), so the terminal shows it (after about a second, core/progress.h).
    std::optional<Progress> bar;
    if (progress) bar.emplace("remeshing", std::vector<ProgressStage>{{"quad mesh", 95}, {"lines", 5}});
    remesh::RemeshResult mesh;
    try {
        mesh = remesh::remesh(*loaded.frames, cross, singularities, options);
    } catch (const InputError &e) { // said of `remesh --edge`; here the edge is the style's
        throw InputError(FileLoc{scene.mesh.name()},
                         fmt::format("style.hatch.lines: quad_mesh: the quad mesh's edge of {} px at this camera "
                                     "is {:.3g} world units, too short to remesh ({})",
                                     scene.style.hatch.quadEdgePx, options.edgeLength, e.message()),
                         "raise style.hatch.quad_edge_px or lower camera.resolution");
    }
    if (bar) bar->beginStage(1);
    std::vector<renderer::SurfaceLine> lines;
    for (remesh::EdgeLine &l : remesh::edgeLines(mesh.poly))
        lines.push_back({std::move(l.points), std::move(l.normals), l.closed, std::move(l.families), l.parity});
    if (bar) bar->finish();
    return lines;
}

} // namespace

renderer::Illustration finishHatching(renderer::Illustration begun, const LoadedScene &loaded,
                                      const field::RosyField &rosyField,
                                      const field::SingularityReport &singularities, const renderer::RayScene &rays,
                                      renderer::HatchMeasure measure, bool raster, bool progress,
                                      const FieldOnCopy *onCopy) {
    if (onCopy) shadeFromSmoothedCopy(begun, *loaded.scene, rays, onCopy->copy);
    renderer::IllustrationInput in = viewInput(*loaded.scene, rays);
    std::vector<renderer::SurfaceLine> quadLines;
    if (loaded.scene->style.hatch.lines == styles::HatchStyle::Lines::QuadMesh) {
        const auto start = std::chrono::steady_clock::now();
        quadLines = quadMeshLines(loaded, rosyField, singularities, progress);
        in.quadLines = &quadLines;
        begun.timingsMs.emplace_back(
            "remesh", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    in.frames = onCopy ? onCopy->copy.frames.get() : loaded.frames.get();
    in.field = onCopy ? &onCopy->field : &rosyField;
    in.singularities = &singularities;
    in.measureHatching = measure;
    in.raster = raster;
    in.progress = progress;
    renderer::finishIllustration(begun, in);
    return begun;
}

renderer::Illustration drawHatching(const LoadedScene &loaded, const field::RosyField &rosyField,
                                    const field::SingularityReport &singularities, const renderer::RayScene &rays,
                                    renderer::HatchMeasure measure, bool raster, const FieldOnCopy *onCopy) {
    return finishHatching(beginHatching(*loaded.scene, rays), loaded, rosyField, singularities, rays, measure,
                          raster, /*progress=*/true, onCopy);
}

void shadeFromSmoothedCopy(renderer::Illustration &begun, const Scene &scene, const renderer::RayScene &rays,
                           const field::SmoothedSurface &copy) {
    if (begun.shapeMesh == copy.mesh.get()) return;
    renderer::reshadeWithNormalsOf(begun, viewInput(scene, rays), *copy.mesh);
}

HatchingView beginHatchingBeside(const Scene &scene, const std::function<void()> &fieldWork,
                                 bool contoursBesideHatching,
                                 const std::function<void(const std::string &stage)> &onStageStart) {
    HatchingView out;
    tbb::task_group view;
    view.run([&] {
        const auto start = std::chrono::steady_clock::now();
        out.rays = std::make_unique<renderer::RayScene>(scene.mesh);
        out.bvhMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        out.begun = beginHatching(scene, *out.rays, contoursBesideHatching);
    });
    try {
        fieldWork();
    } catch (...) {
        // The task reads the scene: let it end before the caller's scene goes. Its
        // own failure, if any, is second to this one.
        try {
            view.wait();
        } catch (...) {
        }
        throw;
    }
    if (onStageStart) onStageStart("bvh"); // built beside the field: what is waited for now
    view.wait(); // rethrows the task's exception (Embree failing)
    return out;
}

namespace {

/// Print mode promises the tone's line density on paper whatever the picture's size
/// (renderer::kInkFillTolerance). Where the calibration could not reach it because
/// it was held back — most of the ink asked at the pen's densest spacing, which it
/// never goes below, or its gain at a bound — say so and what to change. A trace
/// off by the tracer's own scatter (fig1-symmetry's 105 % at gain 1) has no remedy
/// to offer and is left to --report's ink_fill.
void warnInkOffTheTone(const std::string &where, const renderer::Illustration &il) {
    if (std::abs(il.inkFill - 1.0) <= renderer::kInkFillTolerance) return;
    const bool atPenLimit = il.inkFill < 1.0 && il.inkAtMinSpacing > 0.5;
    const bool gainHeld = (il.inkFill < 1.0 && il.spacingGain <= renderer::kMinSpacingGain) ||
                          (il.inkFill > 1.0 && il.spacingGain >= renderer::kMaxSpacingGain);
    if (!atPenLimit && !gainHeld) return;
    std::string message = fmt::format("the hatching lays down {:.0f} % of the ink the tone asks for", 100.0 * il.inkFill);
    if (atPenLimit)
        message += fmt::format(" ({:.0f} % of that is asked at page.min_spacing_mm, the densest spacing the pen is "
                               "given, which the calibration never goes below)",
                               100.0 * il.inkAtMinSpacing);
    else
        message += fmt::format(" with every spacing scaled by {} (the calibration's bound)", il.spacingGain);
    message += ", so its line density on paper is not the tone's and depends on the picture's size; ";
    message += il.inkFill < 1.0 ? "use a larger page or picture, or a finer pen with a smaller page.min_spacing_mm"
                                : "use a smaller page or picture, or a wider pen";
    warn(where, "print", message);
}

/// renderScene() for `picture.kind: hatching`: after the load, the frames, field and
/// singularities on this thread with what needs no field (Embree BVH, G-buffer, tone)
/// beside them (beginHatchingBeside()); then finishHatching(), whose sequential tracer
/// leaves a core to the contours, traced beside it. The view's stages reach `timings`
/// and options.onStage from this thread, after the field's, in the order bvh, gbuffer,
/// tone, screen_field, hatching, contours, raster; their times overlap the field's
/// (contours: the hatching's).
RenderResult renderHatching(const SceneDesc &desc, const PipelineOptions &options, RenderResult out) {
    out.loaded.scene = loadSceneObjects(desc, options, &out.timingsMs);
    HatchingView view = beginHatchingBeside(
        *out.loaded.scene,
        [&] {
            out.loaded.frames = buildFrames(*out.loaded.scene, options, &out.timingsMs);
            out.field = buildSceneField(out.loaded, desc.field, options, &out.timingsMs);
        },
        true, options.onStageStart);
    out.timingsMs.emplace_back("bvh", view.bvhMs);
    if (options.onStage) options.onStage("bvh", view.bvhMs);
    out.rays = std::move(view.rays);
    // A noisy scan's field came from a smoothed copy: so do the tone and the planes
    // the screen field projects into (FieldOnCopy).
    const std::optional<FieldOnCopy> onCopy = out.field.onCopy();
    out.illustration = finishHatching(std::move(view.begun), out.loaded, out.field.field.field,
                                      out.field.singularities, *out.rays,
                                      options.measureHatching ? renderer::HatchMeasure::All : renderer::HatchMeasure::None,
                                      options.raster, /*progress=*/true, onCopy ? &*onCopy : nullptr);
    for (const auto &[stage, ms] : out.illustration->timingsMs) {
        out.timingsMs.emplace_back(stage, ms);
        if (options.onStage) options.onStage(stage, ms);
    }
    if (out.print) warnInkOffTheTone(desc.path, *out.illustration);
    return out;
}

} // namespace

RenderResult renderScene(const SceneDesc &sceneDesc, const PipelineOptions &options) {
    const ThreadLimit limit(sceneDesc, options.threads);
    RenderResult out;
    // Print mode rewrites the camera resolution and the style's lengths before the
    // scene is built, so the G-buffer, tone and tracer all run at the print pitch.
    std::optional<SceneDesc> printed;
    if (options.print && sceneDesc.picture.kind.value != PictureDesc::Kind::Field) {
        printed = sceneDesc;
        out.print = applyPrintUnits(*printed, options.printKeepsResolution.value_or(options.raster));
        for (const std::string &w : out.print->warnings) warn(sceneDesc.path, "print", w);
    }
    const SceneDesc &desc = printed ? *printed : sceneDesc;
    if (desc.picture.kind.value != PictureDesc::Kind::Field) return renderHatching(desc, options, std::move(out));
    out.loaded = loadScene(desc, options, &out.timingsMs);
    out.field = buildSceneField(out.loaded, desc.field, options, &out.timingsMs);
    const field::TangentFrames &frames = *out.loaded.frames;
    const field::RosyField &rosyField = out.field.field.field;
    const field::SingularityReport &singularities = out.field.singularities;
    // picture.kind: field
    if (desc.picture.separatrices.value)
        out.separatrices = timed("separatrices", &out.timingsMs, options, [&] {
            return field::traceSeparatrices(out.field.fieldFrames(frames), out.field.fieldOnFieldFrames(),
                                            singularities.singularities);
        });
    renderer::FieldPictureOptions pictureOptions;
    // Without a `lights` key the picture keeps its own light rather than the
    // default key light buildScene() adds for hatching.
    if (desc.lightsGiven) pictureOptions.lights = out.loaded.scene->lights;
    // The drawing (fill and strokes) for an SVG, and its pixels: renderFieldPicture()
    // is exactly rasterizeFieldDrawing(drawFieldPicture()).
    out.fieldPicture = timed("field_picture", &out.timingsMs, options, [&] {
        out.fieldDrawing = renderer::drawFieldPicture(out.loaded.scene->mesh, frames, rosyField, singularities,
                                                      out.separatrices, out.loaded.scene->camera, pictureOptions);
        return renderer::rasterizeFieldDrawing(*out.fieldDrawing);
    });
    return out;
}

} // namespace rosy::scenes
