#pragma once
/// \file illustration.h
/// The pen-and-ink pipeline, stage by stage on plain values:
///   G-buffer → tone → screen field → hatches + contours → one stroke list →
///   ink layers → composite over paper (and the EXR with its channels).
/// The field is given (built and edited by the caller), so the renderer knows
/// nothing of how it was designed.

#include "field/frames.h"
#include "field/rosy.h"
#include "field/singularities.h"
#include "renderer/camera.h"
#include "renderer/contours.h"
#include "renderer/gbuffer.h"
#include "renderer/hatching.h"
#include "renderer/image.h"
#include "renderer/inspect.h"
#include "renderer/raster.h"
#include "renderer/screen_field.h"
#include "renderer/shading.h"
#include "renderer/strokes.h"
#include "styles/style.h"

#include <string>
#include <utility>
#include <vector>

namespace rosy::renderer {

class RayScene;

struct IllustrationInput {
    const field::Mesh *mesh = nullptr;
    const field::TangentFrames *frames = nullptr; ///< of *mesh
    const field::RosyField *field = nullptr;      ///< the hatch field (any N; 2 and 4 are the usual)
    const field::SingularityReport *singularities = nullptr; ///< of *field (findSingularities)
    const RayScene *scene = nullptr;              ///< built from *mesh
    const Camera *camera = nullptr;
    std::vector<Light> lights;
    ShadingOptions shading;
    styles::Style style;
    /// Measure the hatching (Illustration::hatch: spacing violations, strokes near
    /// singularities; about a sixth of the hatching stage). Off when nobody reads it.
    bool measureHatching = true;
};

struct Illustration {
    GBuffer gbuffer;
    std::vector<float> targetDensity; ///< #pixels, ink coverage the tone asks for
    ScreenField screen;
    StrokeList strokes; ///< hatches (in creation order) then contours
    InkLayers layers;
    Image composite;    ///< linear RGB + alpha over paper
    HatchReport hatch;  ///< measured independently of the tracer (measureHatches), if asked
    ContourReport contours;
    std::vector<std::pair<std::string, double>> timingsMs; ///< gbuffer, tone, screen_field, hatching, contours, raster
};

/// Runs the whole pipeline. Deterministic for any thread count.
Illustration renderIllustration(const IllustrationInput &input);

/// The EXR of an illustration: final image plus the named channels of raster.h.
Image illustrationExr(const Illustration &illustration);

/// The channels `rosyhatch inspect` reads from the EXR, taken from the illustration
/// in memory (same values as illustrationExr() writes), with the style's nominal
/// spacing and cross density as the EXR header would carry them.
InkMaps illustrationInkMaps(const Illustration &illustration, const styles::HatchStyle &style);

/// The nominal hatch spacing (px) at mid density, stored in the EXR header so
/// `rosyhatch inspect` can blur at the right scale.
double nominalHatchSpacingPx(const styles::HatchStyle &style);

} // namespace rosy::renderer
