#pragma once
/// \file compare.h
/// One scene drawn along several fields, as in Palacios & Zhang 2007, Figure 1:
/// the same field source built as each N-RoSy (a–b), or variants of the scene's
/// field — as built, topologically edited, globally smoothed (c–d). The scene is
/// loaded once (loadScene()); every field goes through buildSceneField() and every
/// hatched panel through beginHatchingBeside() (once, shared) and finishHatching(),
/// the path `rosyhatch render` takes.

#include "field/rosy.h"
#include "field/singularities.h"
#include "renderer/output/image.h"
#include "scenes/pipeline.h"
#include "scenes/scene.h"

#include <limits>
#include <string>
#include <vector>

namespace rosy::scenes {

/// What to compare. With `variants` empty, one panel per entry of `symmetries`.
struct CompareSpec {
    /// One panel per N: the scene's field source built as an N-RoSy; the scene's
    /// edits apply only to the panel of the scene's own N (their ids name its field).
    std::vector<int> symmetries{2, 4};
    enum class Variant {
        Original, ///< the scene's field as built, without its edits
        Edited,   ///< the scene's edits; without any, the closest opposite pairs cancelled
        Smoothed, ///< the paper's global smoothing of the field as built
    };
    /// One panel per variant, in this order (at most 8 panels either way).
    std::vector<Variant> variants;
    int smoothIterations = 60;   ///< Smoothed: relaxation iterations (>= 1)
    double smoothStrength = 0.5; ///< Smoothed: relaxation strength in (0, 1]
    /// Edited without scene edits: pairs to cancel; -1 cancels until as few
    /// singularities remain as the smoothed panel has (or 20 fewer without one).
    int cancelPairs = -1;
    bool fieldPictures = false; ///< panels show the field instead of the hatching
    bool separatrices = false;  ///< field pictures: with each singularity's separatrices
};

/// One panel of a comparison.
struct ComparePanel {
    /// "(a) 4-RoSy, edited: 12 singularities".
    std::string label;
    field::RosyField field;
    field::SingularityReport singularities; ///< of `field`
    /// A noisy scan's smoothed copy the field came from (field/scan_noise.h; `field`
    /// is carried back from it) and the field on it, which the screen field reads.
    std::shared_ptr<const field::SmoothedSurface> scanCopy;
    field::RosyField fieldOnCopy;
    renderer::Image picture;                ///< at the scene camera's resolution
    /// Hatching panels: inspect's seam fraction of the ink and the stroke list's
    /// figures (NaN / 0 for field pictures).
    double seamFraction = std::numeric_limits<double>::quiet_NaN();
    int strokesNearSingularities = 0;
    double stubFraction = std::numeric_limits<double>::quiet_NaN();
};

struct Comparison {
    LoadedScene loaded;
    std::vector<ComparePanel> panels; ///< labeled (a), (b), ... in order
    /// load, frames, fields, bvh (hatching only), panels.
    StageTimings timingsMs;
};

/// Builds and draws every panel of `spec` for the scene (options.nSym and
/// options.applyEdits are set per panel; the rest of `options` applies to all).
/// \throws what loadScene(), buildSceneField() and the edits throw.
Comparison compareScene(const SceneDesc &desc, const CompareSpec &spec, const PipelineOptions &options = {});

} // namespace rosy::scenes
