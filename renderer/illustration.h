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
#include "renderer/view/camera.h"
#include "renderer/strokes/contours.h"
#include "renderer/view/gbuffer.h"
#include "renderer/strokes/hatching.h"
#include "renderer/strokes/quad_lines.h"
#include "renderer/output/image.h"
#include "renderer/evaluation/inspect.h"
#include "renderer/output/raster.h"
#include "renderer/strokes/screen_field.h"
#include "renderer/view/shading.h"
#include "renderer/output/strokes.h"
#include "styles/style.h"

#include <string>
#include <utility>
#include <vector>

namespace rosy::renderer {

class RayScene;

/// Print mode's ink calibration (HatchStyle::calibrateInk): the hatching is traced
/// this many times, each after the first with its spacings scaled by the previous
/// trace's ink over the tone's (toneInkPx), and the trace whose ink is nearest the
/// tone's is kept. The gain is held to [kMinSpacingGain, kMaxSpacingGain]: a trace
/// far off the tone (a picture a few spacings wide) corrects the next by at most that.
inline constexpr int kInkCalibrationTraces = 3;
/// Print mode warns when the kept trace's ink is further than this from the tone's
/// (Illustration::inkFill): issue 18's 5 % between pictures of one scene.
inline constexpr double kInkFillTolerance = 0.05;
inline constexpr double kMinSpacingGain = 0.5;
inline constexpr double kMaxSpacingGain = 2.0;

/// How much of the hatch report a drawing computes (IllustrationInput::measureHatching).
enum class HatchMeasure { None, Counts, All };

struct IllustrationInput {
    const field::Mesh *mesh = nullptr;
    /// Of *mesh, or of a mesh with the same vertices and faces that `field` lives on (a
    /// noisy scan's smoothed copy, field/scan_noise.h).
    const field::TangentFrames *frames = nullptr;
    const field::RosyField *field = nullptr;      ///< the hatch field (any N; 2 and 4 are the usual)
    const field::SingularityReport *singularities = nullptr; ///< of *field (findSingularities)
    const RayScene *scene = nullptr;              ///< built from *mesh
    const Camera *camera = nullptr;
    std::vector<Light> lights;
    ShadingOptions shading;
    styles::Style style;
    /// What to measure of the hatching (Illustration::hatch): All (measureHatches():
    /// spacing violations and the other pairwise measures, about a sixth of the
    /// hatching stage), Counts (countHatches(): strokes, stubs, strokes near
    /// singularities) or None, when nobody reads it.
    HatchMeasure measureHatching = HatchMeasure::All;
    /// Draw the strokes into ink layers and the composite (the "raster" stage).
    /// Off when only vector output (SVG) is written: `layers` and `composite` then
    /// stay empty and no "raster" timing is recorded.
    bool raster = true;
    /// Show the terminal progress display of finishIllustration() (core/progress.h).
    /// Off when several illustrations are drawn at once.
    bool progress = true;
    /// beginIllustration() leaves the contours to finishIllustration(), which traces
    /// them in a task beside the hatching (whose tracer is sequential, so a core is
    /// free there; the tracer's own loops are isolated from the task so that its
    /// thread never picks the task up). The strokes are the same either way.
    /// For one illustration (render); off when several finish from one begun
    /// illustration (compare), which would trace them once each.
    bool contoursBesideHatching = false;
    /// style.hatch.lines == QuadMesh: the quad mesh's edge lines the hatches follow
    /// (quadLineHatches(); scenes::finishHatching() remeshes). Null: the field's
    /// streamlines (traceHatches()), whatever the style says.
    const std::vector<SurfaceLine> *quadLines = nullptr;
};

struct Illustration {
    GBuffer gbuffer;
    std::vector<float> targetDensity; ///< #pixels, ink coverage the tone asks for
    ScreenField screen;
    StrokeList strokes; ///< hatches (in creation order) then contours
    InkLayers layers;   ///< empty when IllustrationInput::raster is off
    Image composite;    ///< linear RGB + alpha over paper; empty when IllustrationInput::raster is off
    HatchReport hatch;  ///< measured independently of the tracer (measureHatches), if asked
    /// Print mode (HatchStyle::calibrateInk): the HatchStyle::spacingGain of the trace
    /// kept (kInkCalibrationTraces); 1 otherwise.
    double spacingGain = 1.0;
    /// Print mode: the kept trace's hatch ink over the tone's (hatchInkPx / toneInkPx;
    /// 1 when the tone asks for none), and the share of the tone's ink asked at or
    /// below the densest spacing, where the calibration cannot add lines. 1 and 0
    /// outside print mode. Off by more than kInkFillTolerance, the line density on
    /// paper is not the tone's and depends on the picture's size (the pipeline warns).
    double inkFill = 1.0;
    double inkAtMinSpacing = 0.0;
    ContourReport contours;
    /// The contours between beginIllustration() and finishIllustration(), which
    /// moves them to the end of `strokes`; empty after it.
    StrokeList contourStrokes;
    /// Set by beginIllustration() when IllustrationInput::contoursBesideHatching
    /// left the contours to finishIllustration().
    bool contoursPending = false;
    /// Set by reshadeWithNormalsOf(): the mesh (same vertices and faces as
    /// IllustrationInput::mesh, at other positions: a noisy scan's smoothed copy) the
    /// shading normals, the tone and the contours' silhouettes and creases were taken
    /// from; IllustrationInput::frames are then its frames. Null: the input's mesh.
    const field::Mesh *shapeMesh = nullptr;
    std::vector<std::pair<std::string, double>> timingsMs; ///< gbuffer, tone, screen_field, hatching, contours, raster
    // For the EXR: the camera as OpenEXR's standard attributes (Camera::worldToCamera(),
    // Camera::worldToNdc()) and the ink colour its premultiplied RGB carries.
    Eigen::Matrix4d worldToCamera = Eigen::Matrix4d::Identity();
    Eigen::Matrix4d worldToNdc = Eigen::Matrix4d::Identity();
    styles::Rgb ink = {0.0, 0.0, 0.0};
};

/// Runs the whole pipeline: beginIllustration() then finishIllustration().
/// Deterministic for any thread count.
Illustration renderIllustration(const IllustrationInput &input);

/// The stages that need no field: G-buffer, tone (targetDensity) and contours
/// (held in `contourStrokes`). Reads input.mesh, scene, camera, lights, shading
/// and style; input.frames, field and singularities may still be null, so a
/// caller can run this while the field is being built (scenes::renderScene()).
Illustration beginIllustration(const IllustrationInput &input);

/// A begun illustration's shading normals (GBuffer::vertexNormals, cornerNormals) and
/// tone taken from `normalsOf` instead, a mesh with the same vertices and faces as
/// input.mesh at other positions: on a noisy scan the smoothed copy its field came
/// from (field/scan_noise.h), so that the tone, and the tangent planes the screen
/// field projects into, are the shape's and not the noise's; the contours are drawn
/// from `normalsOf` too (again at once when beginIllustration() drew them already),
/// their visibility still against the input's own surface. Stage "scan_tone".
/// `normalsOf` must outlive the illustration's finishIllustration().
void reshadeWithNormalsOf(Illustration &begun, const IllustrationInput &input, const field::Mesh &normalsOf);

/// The rest on a begun illustration: screen field, hatching (in print mode traced
/// kInkCalibrationTraces times, keeping the trace nearest the tone's ink) and its measurement,
/// the contours appended after the hatches, raster. The result, timings included
/// (in the order gbuffer, tone, screen_field, hatching, contours, raster), is
/// exactly renderIllustration()'s.
void finishIllustration(Illustration &begun, const IllustrationInput &input);

/// The EXR of an illustration, for `rosyhatch inspect` and for compositors. Channels
/// (illustrationExrChannelNames(), in that order; OpenEXR files list them sorted):
///  - R G B A: the ink over nothing, premultiplied as OpenEXR expects: A = the ink
///    coverage of the composite (ink.coverage), R G B = style ink colour × A, so
///    `A over paper` gives the PNG's picture and `A over a plate` puts the drawing on it;
///  - tone.target, ink.coverage, ink.hatch0, ink.hatch1, ink.contour (raster.h) and
///    ink.hidden: the hidden-contour layer, dashed, at full strength (the composite
///    draws it at CompositeOptions::hiddenOpacity);
///  - Z: camera-space depth (Camera::depth, world units), +infinity where the pixel
///    sees nothing (OpenEXR's convention; the former `depth` channel held 0 there);
///  - N.x N.y N.z, field.angle0, field.angle1, mask: as raster.h;
///  - field.cos, field.sin: mask × (cos Kθ, sin Kθ) of θ = field.angle0, K =
///    fieldHarmonic(N): the hatch directions as a vector that filters (blur,
///    resample) without wrapping, where the angle jumps at π and between labels.
/// Header: the camera as the standard M44f attributes `worldToCamera` and
/// `worldToNDC` (row-vector form, Imath's: the transposes of Camera's matrices),
/// `rosy:symmetry` (N) and `rosy:field_harmonic` (K).
Image illustrationExr(const Illustration &illustration);

/// The channel names of illustrationExr(), in order.
const std::vector<std::string> &illustrationExrChannelNames();

/// K of the EXR's field.cos/field.sin for an N-RoSy: the line directions an N-RoSy
/// draws repeat every π/N for odd N and 2π/N for even N, so K = 2N (odd) or N (even).
int fieldHarmonic(int nSym);

/// The channels `rosyhatch inspect` reads from the EXR, taken from the illustration
/// in memory (same values as illustrationExr() writes), with the style's nominal
/// spacing and cross density as the EXR header would carry them.
InkMaps illustrationInkMaps(const Illustration &illustration, const styles::HatchStyle &style);

/// The nominal hatch spacing (px) at mid density, stored in the EXR header so
/// `rosyhatch inspect` can blur at the right scale.
double nominalHatchSpacingPx(const styles::HatchStyle &style);

} // namespace rosy::renderer
