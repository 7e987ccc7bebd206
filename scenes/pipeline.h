#pragma once
/// \file pipeline.h
/// The one path from a parsed scene to a drawing, called by every command, test
/// and benchmark so that they all run the product users run:
///
///   SceneDesc ─ buildScene ─▶ Scene ─▶ TangentFrames ─▶ field (buildField, the
///   scene's edits) ─▶ singularities ─▶ RayScene ─▶ Illustration (hatching)
///                                                └──▶ field picture (picture.kind: field)
///
/// renderScene() runs all of it; buildSceneField() stops after the singularities.
/// The pieces loadScene(), buildSceneField(LoadedScene...) and drawHatching() are
/// public for callers that draw several fields of one scene (compareScene(),
/// compare.h, behind `rosyhatch compare`).
/// Stages pick their behaviour through PipelineOptions, never by being skipped in
/// a copy of the chain. Nothing here writes files: the results are plain values.

#include "field/edits.h"
#include "field/field_builder.h"
#include "field/frames.h"
#include "field/scan_noise.h"
#include "field/separatrices.h"
#include "field/singularities.h"
#include "renderer/view/embree_scene.h"
#include "renderer/field_picture.h"
#include "renderer/illustration.h"
#include "renderer/output/image.h"
#include "scenes/print_units.h"
#include "scenes/scene.h"

#include <tbb/collaborative_call_once.h>
#include <tbb/global_control.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rosy::scenes {

/// Wall-clock milliseconds per stage, in the order the stages ran.
using StageTimings = std::vector<std::pair<std::string, double>>;

/// What the callers of the pipeline choose. The defaults run the scene as
/// `rosyhatch render` does.
struct PipelineOptions {
    /// Mesh loading limits (--max-faces).
    field::LoadOptions load;
    /// Worker threads during the call: unset = the scene's `threads`; 0 = all
    /// cores. The drawing is the same for any value.
    std::optional<int> threads;
    /// Replaces the scene's field symmetry order N when > 0.
    int nSym = 0;
    /// Applies the scene's `field.edits`. Their ids name singularities of the
    /// scene's own field, so callers that change N usually turn them off.
    bool applyEdits = true;
    /// Field-only entry: also trace the separatrices of the field (stage
    /// "separatrices"; SceneFieldResult::separatrices).
    bool separatrices = false;
    /// Field-only entry: when edits were applied, keep the field as it was before
    /// them with its singularities (and separatrices, with `separatrices`), in
    /// SceneFieldResult::unedited (stage "unedited"), e.g. to draw it beside the edited one.
    bool keepUnedited = false;
    /// Kept between calls on one loaded scene (the studio's session): what the field
    /// derives from the mesh alone (field::FieldCache; must be for the loaded
    /// scene's frames). The field is the same to the bit with or without it.
    field::FieldCache *fieldCache = nullptr;
    /// Kept between calls on one loaded scene (the studio's rebuilds): the number of
    /// singularities of an earlier field on the scene's own surface that was judged a
    /// noisy scan's by a wide margin (noiseJudgementCarries()), for a field spec that
    /// differs from this one at most in its design elements. The field on the surface
    /// itself is then not built again (on a 568k-face scan the larger half of a
    /// rebuild): it goes to the smoothed copy straight away. Unset: judged as usual.
    std::optional<size_t> judgedNoisy;
    /// Runs right after the scene is built, before any field work: may change the
    /// scene (a benchmark subdivides the mesh) or refuse it by throwing (the CLI's
    /// memory check). Counted in the "load" stage's time.
    std::function<void(Scene &)> afterLoad;
    /// Called as each stage ends with its name and milliseconds (progress, live timings).
    std::function<void(const std::string &stage, double ms)> onStage;
    /// Called as each stage run on the calling thread starts, with its name (load,
    /// frames, field, singularities, scan_field, separatrices, unedited,
    /// field_picture): a progress display can name the stage running, also one that
    /// only some scenes have (scan_field: a noisy scan's field on its smoothed copy,
    /// minutes on millions of faces), and bvh when the field is done and the drawing
    /// waits for the ray scene built beside it. The view's other stages (gbuffer,
    /// tone, …) run beside the field or inside the illustration, which shows its own
    /// progress.
    std::function<void(const std::string &stage)> onStageStart;
    /// Measure the hatching (Illustration::hatch: spacing violations, strokes near
    /// singularities; about a sixth of the hatching stage). Only reports read it.
    bool measureHatching = true;
    /// Draw the strokes into ink layers and the composite image (IllustrationInput::raster).
    /// Off when the only outputs are vectors (SVG): the illustration's `layers` and
    /// `composite` stay empty.
    bool raster = true;
    /// Print mode (scenes/print_units.h): the style's lengths are millimetres on the
    /// page and the hatching is traced at a resolution that serves them
    /// (applyPrintUnits() on a copy of the scene, before it is loaded; its warnings
    /// go through warn() as kind "print", RenderResult::print says what it chose).
    /// `rosyhatch render` turns it on for an SVG output or --paper. Field pictures
    /// (picture.kind: field) ignore it.
    bool print = false;
    /// Print mode only: trace at the scene's camera.resolution, converting the
    /// millimetres at its scale, instead of the resolution of page.px_mm. Unset: kept
    /// exactly when `raster` is on (a raster output is drawn at the scene's resolution).
    std::optional<bool> printKeepsResolution;
};

/// Limits oneTBB's worker threads while it lives: `threads` when set, else the
/// scene's `threads`; 0 (either way) leaves all cores.
class ThreadLimit {
public:
    ThreadLimit(const SceneDesc &desc, std::optional<int> threads);

private:
    std::optional<tbb::global_control> m_control;
};

/// A built scene and its tangent frames: what every field on the scene shares.
/// Both live on the heap because the frames, fields and ray scenes made from them
/// keep pointers to the mesh; moving a LoadedScene keeps those valid.
struct LoadedScene {
    std::unique_ptr<Scene> scene;
    std::unique_ptr<field::TangentFrames> frames; ///< of scene->mesh

    /// scene->mesh smoothed at field::kScanSmoothingRadius, with its frames
    /// (field::smoothAtScale()): where the fields of a noisy scan are computed
    /// (buildSceneField()). Built on the first call and shared by every later one —
    /// compare's panels, the studio's rebuilds — since it depends on the mesh alone;
    /// concurrent first calls wait for one build (and help it). Needs `frames`.
    std::shared_ptr<const field::SmoothedSurface> smoothedCopy() const;

private:
    /// On the heap: the once-flag cannot move with the scene.
    struct CopyCache {
        tbb::collaborative_once_flag once;
        std::shared_ptr<const field::SmoothedSurface> copy;
    };
    std::shared_ptr<CopyCache> m_copyCache = std::make_shared<CopyCache>();
};

/// A noisy scan's field as the view reads it: the smoothed copy it was computed on
/// (SceneFieldResult::smoothedSurface, field/scan_noise.h) and the field on the copy's
/// frames (SceneFieldResult::smoothedField, before being carried back). The picture
/// then takes its shape from the copy: the tone's normals and the contours
/// (renderer::reshadeWithNormalsOf(), stage "scan_tone") and the face planes the
/// screen field projects the members into; rays and visibility stay on the scan.
struct FieldOnCopy {
    const field::SmoothedSurface &copy;
    const field::RosyField &field; ///< on *copy.frames
};

/// One field on a loaded scene, as drawn.
struct SceneFieldResult {
    field::FieldSpec spec;                ///< the scene's, with PipelineOptions::nSym applied
    field::FieldResult field;             ///< field.field: after the edits
    std::vector<field::AppliedEdit> edits; ///< the scene's edits as applied (empty when off)
    field::SingularityReport singularities; ///< of field.field
    std::vector<field::Separatrix> separatrices; ///< of field.field, with PipelineOptions::separatrices
    /// The field before the edits (PipelineOptions::keepUnedited, when there were edits).
    struct Unedited {
        field::RosyField field;
        field::SingularityReport singularities;
        std::vector<field::Separatrix> separatrices; ///< with PipelineOptions::separatrices
    };
    std::optional<Unedited> unedited;
    /// Set when the field on the scene's own surface was judged to be scan noise
    /// (field::fieldIsScanNoise()): the smoothed copy the field, edits, singularities
    /// and separatrices were then computed on (field/scan_noise.h). `field.field` and
    /// `unedited->field` are carried back to the scene's vertices; the singularities
    /// keep their faces, placed on the scene's surface; separatrices lie on the copy.
    std::shared_ptr<const field::SmoothedSurface> smoothedSurface;
    /// With smoothedSurface: how many singularities the field on the scene's own
    /// surface had, and their density (field::singularityDensity()).
    size_t noisySingularities = 0;
    double noisyDensity = 0;
    /// With smoothedSurface: milliseconds of the "scan_field" stage spent smoothing the
    /// copy and building its frames (0 when the loaded scene had made it already).
    double smoothingMs = 0;
    /// With smoothedSurface: field.field as it is on the copy (before being carried back).
    field::RosyField smoothedField;
    /// The frames the singularities and separatrices belong to: the smoothed copy's
    /// when there is one, else `own` (the scene's).
    const field::TangentFrames &fieldFrames(const field::TangentFrames &own) const {
        return smoothedSurface ? *smoothedSurface->frames : own;
    }
    /// field.field on fieldFrames(): smoothedField when there is a copy.
    const field::RosyField &fieldOnFieldFrames() const { return smoothedSurface ? smoothedField : field.field; }
    /// The field on the smoothed copy, for drawHatching() / finishHatching(); empty
    /// when the field is on the scene's own surface.
    std::optional<FieldOnCopy> onCopy() const {
        if (!smoothedSurface) return std::nullopt;
        return FieldOnCopy{*smoothedSurface, smoothedField};
    }
};

/// How far above field::kScanNoiseDensity a judgement must be to carry over to
/// fields that differ only in their design elements (PipelineOptions::judgedNoisy):
/// the noise's singularities come from the surface's connection turning at random
/// around single faces, which no element changes: four elements move the 568k-face
/// scan-like elephant's 43,159 by about a hundred (docs/studio.md), not by half. Near
/// the threshold every field is judged anew.
constexpr double kCarriedNoiseMargin = 2.0;

/// Whether `r` was judged a noisy scan's by kCarriedNoiseMargin or more, so that
/// PipelineOptions::judgedNoisy may carry its judgement (r.noisySingularities) to a
/// field of the same loaded scene and spec but its design elements.
inline bool noiseJudgementCarries(const SceneFieldResult &r) {
    return r.smoothedSurface && r.noisyDensity >= kCarriedNoiseMargin * field::kScanNoiseDensity;
}

/// The field stage of a scene on its own: the loaded scene and its field.
struct SceneField {
    LoadedScene loaded;
    SceneFieldResult field;
    /// load, frames, field (build and edits), singularities.
    StageTimings timingsMs;
};

/// Everything renderScene() made. Exactly one of `illustration` (picture.kind:
/// hatching) and `fieldPicture` (picture.kind: field) is set.
struct RenderResult : SceneField {
    std::unique_ptr<renderer::RayScene> rays;           ///< hatching only
    std::optional<renderer::Illustration> illustration; ///< hatching: strokes, layers, composite
    std::vector<field::Separatrix> separatrices;        ///< field pictures with `separatrices: true`
    std::optional<renderer::Image> fieldPicture;        ///< the field picture (linear RGB + alpha)
    std::optional<renderer::FieldDrawing> fieldDrawing; ///< its fill and strokes (fieldPictureStrokes() for an SVG)
    /// What print mode chose (PipelineOptions::print, hatching only): the lengths on
    /// paper, the traced resolution, the pen and plotter tolerances for the SVG writer.
    std::optional<PrintSetup> print;
    // timingsMs continues with bvh and the illustration's stages (gbuffer, tone,
    // screen_field, hatching, contours, raster), or separatrices and field_picture.
};

/// Builds the scene's objects (buildScene()), runs options.afterLoad, then the
/// tangent frames. Stages "load" and "frames" go to `timings` when given.
/// \throws what buildScene() and options.afterLoad throw.
LoadedScene loadScene(const SceneDesc &desc, const PipelineOptions &options = {}, StageTimings *timings = nullptr);

/// The field of `fieldDesc` (symmetry replaced by options.nSym when > 0) on a
/// loaded scene: buildField(), the edits when options.applyEdits, and the
/// singularities of the result. Stages "field" and "singularities", then
/// "separatrices" and "unedited" when options ask for them.
/// \throws InputError at an edit's location when it cannot be applied.
SceneFieldResult buildSceneField(const LoadedScene &loaded, const FieldDesc &fieldDesc,
                                 const PipelineOptions &options = {}, StageTimings *timings = nullptr);

/// The field-only pipeline (`rosyhatch field`): loadScene() then buildSceneField()
/// under the thread limit of options.threads / the scene's `threads`.
SceneField buildSceneField(const SceneDesc &desc, const PipelineOptions &options = {});

/// The pen-and-ink drawing of `rosyField` (with its singularities) on a loaded
/// scene through the scene's camera, lights, shading and style; `rays` must be
/// built from loaded.scene->mesh. `onCopy`: as finishHatching().
renderer::Illustration drawHatching(const LoadedScene &loaded, const field::RosyField &rosyField,
                                    const field::SingularityReport &singularities, const renderer::RayScene &rays,
                                    renderer::HatchMeasure measure = renderer::HatchMeasure::All, bool raster = true,
                                    const FieldOnCopy *onCopy = nullptr);

/// drawHatching() in two halves, the one path every hatching takes (renderScene(),
/// compareScene(), drawHatching()): beginHatching() runs what needs no field
/// (G-buffer, tone, contours: renderer::beginIllustration()) and reads only the
/// scene, not its frames; finishHatching() draws one field on it (screen field,
/// hatching, raster: renderer::finishIllustration()), on a copy when several fields
/// share one begun drawing. `progress` off: no terminal display (for panels drawn
/// side by side). `contoursBesideHatching` moves the contours into finishHatching(),
/// beside the hatching (for a single drawing). `onCopy`: a noisy scan's field on its
/// smoothed copy (rosyField being the field carried back): the begun drawing is
/// shaded from the copy first, unless shadeFromSmoothedCopy() did that already (for
/// panels that share it).
renderer::Illustration beginHatching(const Scene &scene, const renderer::RayScene &rays,
                                     bool contoursBesideHatching = false);
renderer::Illustration finishHatching(renderer::Illustration begun, const LoadedScene &loaded,
                                      const field::RosyField &rosyField,
                                      const field::SingularityReport &singularities, const renderer::RayScene &rays,
                                      renderer::HatchMeasure measure = renderer::HatchMeasure::All, bool raster = true,
                                      bool progress = true, const FieldOnCopy *onCopy = nullptr);

/// A begun hatching's tone and shading normals from a noisy scan's smoothed copy
/// (renderer::reshadeWithNormalsOf(), stage "scan_tone"), once: a drawing already
/// shaded from `copy` is left as it is.
void shadeFromSmoothedCopy(renderer::Illustration &begun, const Scene &scene, const renderer::RayScene &rays,
                           const field::SmoothedSurface &copy);

/// What a hatching needs no field for: the Embree ray scene of the mesh, the begun
/// drawing (beginHatching()) and the BVH's build time.
struct HatchingView {
    std::unique_ptr<renderer::RayScene> rays;
    renderer::Illustration begun;
    double bvhMs = 0;
};

/// Runs `fieldWork` on this thread while a oneTBB task beside it builds the
/// HatchingView of `scene`, so the field and the view share the cores; returns the
/// view once both have ended. The result is that of running them one after the
/// other: the task reads only `scene`, which fieldWork must not change. If fieldWork
/// throws, the task is waited for (its own failure, if any, dropped) and the
/// exception rethrown; else a failure of the task (Embree) is rethrown.
/// `contoursBesideHatching`: the contours are left to finishHatching()
/// (renderer::IllustrationInput::contoursBesideHatching); for a single drawing.
/// `onStageStart` (PipelineOptions::onStageStart), when set, is told "bvh" on this
/// thread once fieldWork has returned: the view is what the caller waits for then.
HatchingView beginHatchingBeside(const Scene &scene, const std::function<void()> &fieldWork,
                                 bool contoursBesideHatching = false,
                                 const std::function<void(const std::string &stage)> &onStageStart = {});

/// The whole pipeline: print mode when options.print (applyPrintUnits() on a copy
/// of `desc`), buildSceneField(), then the scene's picture — the
/// hatching (ray scene, renderIllustration()) or, for `picture.kind: field`, the
/// field picture (separatrices when the scene asks for them; the scene's lights
/// only when it has a `lights` key, else the picture's own light).
/// For hatching, what needs no field (BVH, G-buffer, tone) runs beside the frames
/// and the field (beginHatchingBeside()), then finishHatching(), with the contours
/// beside its hatching; the drawing is the same as run in sequence.
/// Their stages are reported after the field's (timings overlap).
/// \throws IoError / InputError from loading, editing and options.afterLoad;
///   std::runtime_error if Embree fails.
RenderResult renderScene(const SceneDesc &desc, const PipelineOptions &options = {});

} // namespace rosy::scenes
