#include "scenes/compare.h"

#include "field/edits.h"
#include "field/separatrices.h"
#include "field/smoothing.h"
#include "renderer/view/embree_scene.h"
#include "renderer/field_picture.h"
#include "renderer/illustration.h"
#include "renderer/evaluation/inspect.h"

#include "core/parallel.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

namespace rosy::scenes {

namespace {

std::string countText(size_t n) { return std::to_string(n) + (n == 1 ? " singularity" : " singularities"); }

} // namespace

Comparison compareScene(const SceneDesc &desc, const CompareSpec &spec, const PipelineOptions &options) {
    using Variant = CompareSpec::Variant;
    Comparison out;
    auto record = [&](const char *stage, std::chrono::steady_clock::time_point start) {
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        out.timingsMs.emplace_back(stage, ms);
        if (options.onStage) options.onStage(stage, ms);
    };
    auto timed = [&](const char *stage, auto &&work) {
        const auto start = std::chrono::steady_clock::now();
        if constexpr (std::is_void_v<decltype(work())>) {
            work();
            record(stage, start);
        } else {
            auto result = work();
            record(stage, start);
            return result;
        }
    };
    out.loaded = loadScene(desc, options, &out.timingsMs);
    const LoadedScene &loaded = out.loaded;
    const Scene &scene = *loaded.scene;
    const field::TangentFrames &frames = *loaded.frames;
    const field::FieldSpec &fieldSpec = desc.field.spec;
    const char letters[] = "abcdefgh";

    std::vector<ComparePanel> &panels = out.panels;
    auto buildFields = [&] {
        if (spec.variants.empty()) {
            // The fields are independent: built side by side, each into its own slot.
            panels.resize(spec.symmetries.size());
            parallelFor(0, int64_t(spec.symmetries.size()), [&](int64_t kk) {
                const size_t k = size_t(kk);
                PipelineOptions panelOptions = options;
                panelOptions.onStage = nullptr; // called from several threads; "fields" covers them
                panelOptions.nSym = spec.symmetries[k];
                // The scene's edits name singularities of its own field: only that N gets them.
                panelOptions.applyEdits = spec.symmetries[k] == fieldSpec.nSym;
                SceneFieldResult built = buildSceneField(loaded, desc.field, panelOptions);
                ComparePanel &panel = panels[k];
                panel.scanCopy = built.smoothedSurface;
                panel.fieldOnCopy = std::move(built.smoothedField);
                panel.field = std::move(built.field.field);
                panel.singularities = std::move(built.singularities);
                const std::string edited = built.edits.empty() ? "" : ", edited";
                panel.label = std::string("(") + letters[k] + ") " + std::to_string(spec.symmetries[k]) + "-RoSy" +
                              edited + ": " + countText(panel.singularities.singularities.size());
            }, options.fieldCache ? int64_t(spec.symmetries.size()) : 1); // one cache: one at a time
            return;
        }
        // The scene's field as built; each variant starts from a copy of it.
        PipelineOptions baseOptions = options;
        baseOptions.applyEdits = false;
        const SceneFieldResult built = buildSceneField(loaded, desc.field, baseOptions);
        // On a noisy scan the variants are made on the smoothed copy the field was
        // computed on (field/scan_noise.h) and carried back like the field itself.
        const field::TangentFrames &vf = built.fieldFrames(frames);
        const field::RosyField &base = built.fieldOnFieldFrames();
        auto carriedBack = [&](ComparePanel &panel) {
            if (!built.smoothedSurface) return;
            panel.scanCopy = built.smoothedSurface;
            panel.fieldOnCopy = panel.field;
            panel.field = field::carryField(vf, panel.field, frames);
            panel.singularities = field::placedOn(std::move(panel.singularities), scene.mesh);
        };
        const std::string name = std::to_string(fieldSpec.nSym) + "-RoSy";
        const size_t baseCount = built.singularities.singularities.size();
        // The smoothed field first: an automatic edit aims at its singularity count.
        std::optional<ComparePanel> smoothed;
        if (std::find(spec.variants.begin(), spec.variants.end(), Variant::Smoothed) != spec.variants.end()) {
            smoothed.emplace();
            smoothed->field = base;
            field::relaxationSmooth(vf, smoothed->field, spec.smoothIterations, spec.smoothStrength, {},
                                    fieldSpec.weights);
            smoothed->singularities = field::findSingularities(vf, smoothed->field);
        }
        for (size_t k = 0; k < spec.variants.size(); ++k) {
            const std::string prefix = std::string("(") + letters[k] + ") " + name;
            ComparePanel panel;
            std::string what;
            if (spec.variants[k] == Variant::Original) {
                panel.field = built.field.field;
                panel.singularities = built.singularities;
                panel.scanCopy = built.smoothedSurface;
                panel.fieldOnCopy = built.smoothedField;
                what = "";
            } else if (spec.variants[k] == Variant::Smoothed) {
                panel = *smoothed;
                carriedBack(panel);
                what = ", smoothed " + std::to_string(spec.smoothIterations) + "x";
            } else {
                panel.field = base;
                if (!desc.field.edits.empty()) {
                    field::applyFieldEdits(vf, panel.field, desc.field.edits);
                    what = ", " + std::to_string(desc.field.edits.size()) + " edits";
                } else {
                    // No edits in the scene: cancel the closest pairs, as many as smoothing
                    // removed (or --cancel-pairs), so the two remedies are compared fairly.
                    size_t target = 0;
                    int maxPairs = spec.cancelPairs;
                    if (maxPairs < 0) {
                        const size_t goal = smoothed ? smoothed->singularities.singularities.size()
                                                     : (baseCount > 20 ? baseCount - 20 : 0);
                        target = std::min(goal, baseCount);
                        maxPairs = int(baseCount);
                    }
                    const int pairs = field::cancelClosestPairs(vf, panel.field, target, maxPairs);
                    what = ", " + std::to_string(pairs) + (pairs == 1 ? " pair" : " pairs") + " cancelled";
                }
                panel.singularities = field::findSingularities(vf, panel.field);
                carriedBack(panel);
            }
            panel.label = prefix + what + ": " + countText(panel.singularities.singularities.size());
            panels.push_back(std::move(panel));
        }
    };
    // What needs no field (BVH, G-buffer, tone, contours) is the same for every
    // panel: drawn once, beside the fields (as renderScene() does).
    std::optional<HatchingView> view;
    if (spec.fieldPictures) {
        timed("fields", buildFields);
    } else {
        view = beginHatchingBeside(scene, [&] { timed("fields", buildFields); });
        // On a noisy scan (field/scan_noise.h) the panels' shared tone and contours come
        // from the smoothed copy their fields came from, as renderScene()'s do.
        for (const ComparePanel &panel : panels)
            if (panel.scanCopy) {
                shadeFromSmoothedCopy(view->begun, scene, *view->rays, *panel.scanCopy);
                break;
            }
        out.timingsMs.emplace_back("bvh", view->bvhMs);
        if (options.onStage) options.onStage("bvh", view->bvhMs);
    }
    // One picture per panel, all through the scene's camera, side by side (the
    // hatching tracer is sequential); each panel's result depends on its field only.
    timed("panels", [&] {
        parallelFor(0, int64_t(panels.size()), [&](int64_t k) {
            ComparePanel &panel = panels[size_t(k)];
            if (spec.fieldPictures) {
                std::vector<field::Separatrix> seps;
                if (spec.separatrices) // on a noisy scan, of the field on its smoothed copy
                    seps = panel.scanCopy ? field::traceSeparatrices(*panel.scanCopy->frames, panel.fieldOnCopy,
                                                                     panel.singularities.singularities)
                                          : field::traceSeparatrices(frames, panel.field, panel.singularities.singularities);
                renderer::FieldPictureOptions fo;
                fo.lights = scene.lights;
                panel.picture = renderer::renderFieldPicture(scene.mesh, frames, panel.field, panel.singularities,
                                                             seps, scene.camera, fo);
                return;
            }
            std::optional<FieldOnCopy> onCopy;
            if (panel.scanCopy) onCopy.emplace(FieldOnCopy{*panel.scanCopy, panel.fieldOnCopy});
            // Only the per-stroke counts are printed: not the pairwise measures.
            renderer::Illustration il = finishHatching(view->begun, loaded, panel.field, panel.singularities, *view->rays,
                                                       renderer::HatchMeasure::Counts, true, /*progress=*/false,
                                                       onCopy ? &*onCopy : nullptr);
            // The paper's claim (4-RoSy hatching has fewer artifacts than 2-RoSy) in
            // figures: cracks in the cross-hatching and strokes crossing singularities.
            panel.seamFraction = renderer::inspectSeams(renderer::illustrationInkMaps(il, scene.style.hatch)).seamFraction;
            panel.strokesNearSingularities = il.hatch.strokesNearSingularities;
            panel.stubFraction = il.hatch.stubFraction;
            panel.picture = std::move(il.composite);
        }, 1);
    });

    return out;
}

} // namespace rosy::scenes
