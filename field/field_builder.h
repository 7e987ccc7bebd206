#pragma once
/// \file field_builder.h
/// From a field specification (what a scene's `field:` block or the `rosyhatch
/// field` flags say) to an N-RoSy field: the one place that chains curvature,
/// design elements, curvature-aligned smoothing and the paper's global smoothing.

#include "field/curvature.h"
#include "field/design.h"
#include "field/features.h"
#include "field/frames.h"
#include "field/smoothing.h"

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rosy::field {

enum class FieldSource {
    Curvature, ///< principal directions (2-RoSy: the major direction; 4-RoSy: both)
    Smoothest, ///< Knöppel 2013 globally smoothest field
    Design,    ///< design elements relaxed over the mesh (P&Z Sec. 5.1)
};

/// "curvature", "smoothest", "design".
const char *toString(FieldSource source);

struct FieldSpec {
    int nSym = 4;                        ///< N in [1, kMaxSymmetry]
    FieldSource source = FieldSource::Curvature;
    CurvatureOptions curvature;
    /// Curvature source: relative smoothing length of the curvature-aligned smooth
    /// field (see alignedField); 0 keeps the raw per-vertex principal directions.
    /// 0.08 by what the hatching shows: on scenes/bunny.yaml 64 singularities and
    /// 87 px mean hatch length, against 92 and 71 px at 0.04 and 2408 and 35 px for
    /// the raw directions (docs/field-choice.md).
    double smoothingLength = 0.08;
    /// Design elements (source design; with source curvature they become
    /// constraints over the curvature field).
    std::vector<DesignElement> elements;
    LaplaceWeights weights = LaplaceWeights::MeanValue;
    /// The paper's global smoothing afterwards: iterations and strength in (0, 1].
    int globalSmoothingIterations = 0;
    double globalSmoothingStrength = 0.5;
    /// Feature alignment (field/features.h): with an angle D in (0, 180), the field
    /// is constrained (Dirichlet) to have a member along the feature curves — edges
    /// whose faces' normals differ by more than D, and boundary edges — at every
    /// curve vertex but the corners; the rest follows from the source as usual
    /// (the smoothest source then becomes the field aligned to the smoothest one
    /// with the curves fixed). 0 (the default): off. Scene key `field.features.angle`.
    double featureAngleDeg = 0;
    /// Crease curves shorter than this (relative to the bounding-box diagonal) are
    /// not constrained (findFeatureCurves' minCurveLength); `rosyhatch remesh` uses
    /// 2 L. Scene key `field.features.min_length`; default 0: every crease.
    double featureMinLength = 0;
};

constexpr int kMaxSymmetry = 12;

/// The field and what it cost.
struct FieldResult {
    RosyField field;
    /// The curvature source's per-vertex curvature, shared with the FieldCache that
    /// computed it (read-only: no copy per build); null for the other sources.
    std::shared_ptr<const std::vector<VertexCurvature>> curvature;
    std::map<std::string, double> timingsMs; ///< per stage: curvature, solve, smoothing
    /// The smoothest field's eigen-solve (method, iterations, any fallback and why),
    /// when the field came from smoothestField(): the smoothest source, or the
    /// curvature source's fallback on a surface without anisotropy.
    std::optional<EigenSolveReport> eigenSolve;
};

/// Representation vectors of the curvature field: u_v = a_v e^{iNφ_v}, φ_v the
/// angle of the major direction in v's frame, a_v = |kMax − kMin| divided by its
/// 90th percentile over the mesh and clamped to 1, so a few creases do not
/// outweigh everything else. All zero on a mesh without any anisotropy.
RosyField curvatureField(const TangentFrames &frames, const std::vector<VertexCurvature> &curvature,
                         int nSym);

/// What buildField() derives from the mesh alone, kept between calls on one mesh:
/// the curvature and its guide field (per CurvatureOptions and N), the connection
/// Laplacian (per N), the vertex areas, the smoothest field (per N) and where design
/// elements snap (per position). An interactive session (`rosyhatch studio`) keeps
/// one, so that adding a design element recomputes only what depends on the
/// elements: the constrained solve and what follows. Every entry is made by the
/// same function buildField() calls without a cache, and buildField() without a
/// cache uses a fresh one, so a field is the same to the bit with or without it
/// (a pure function of the mesh and the spec, never of the calls before; test:
/// FieldCache.*). Warnings of a cached step (smoothest-fallback) are given once.
/// Thread-safe; its entries live as long as the cache.
class FieldCache {
public:
    /// For fields on `frames` (which must outlive the cache).
    explicit FieldCache(const TangentFrames &frames);
    ~FieldCache();
    FieldCache(const FieldCache &) = delete;
    FieldCache &operator=(const FieldCache &) = delete;

    const TangentFrames &frames() const;
    /// computeCurvature(mesh, options), computed once and shared (never modified).
    std::shared_ptr<const std::vector<VertexCurvature>> curvature(const CurvatureOptions &options);
    /// curvatureAnisotropy(curvature(options)).
    double curvatureAnisotropy(const CurvatureOptions &options);
    /// curvatureField(frames, curvature(options), nSym).
    const RosyField &curvatureGuide(const CurvatureOptions &options, int nSym);
    /// connectionLaplacian(frames, nSym).
    const SparseMatrixC &connectionLaplacian(int nSym);
    /// vertexAreas(mesh).
    const Eigen::VectorXd &vertexAreas();
    /// smoothestField(frames, nSym).
    const SmoothestResult &smoothest(int nSym);
    /// snapToSurface(mesh, p) of each element's position.
    std::vector<SnappedElement> snapped(const std::vector<DesignElement> &elements);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// Builds the field. `cache`, when given, must be for `frames`; the field is the
/// same with or without it (see FieldCache). \throws InputError for N outside [1, kMaxSymmetry], bad
/// design elements, a design source without elements, or a solver that fails on the
/// mesh (a factorization or solve on numerically singular, degenerate geometry; the
/// message names the solver's cause). With the curvature source,
/// a mesh whose curvatureAnisotropy() is below kMinCurvatureAnisotropy (planar or
/// nearly umbilic, e.g. a sphere: its principal directions are noise) falls back to
/// the smoothest field with a `no-curvature-direction` warning.
FieldResult buildField(const TangentFrames &frames, const FieldSpec &spec, FieldCache *cache = nullptr);

/// Checks N, throwing InputError at `where` when it is out of range.
void checkSymmetry(int nSym, const std::string &where);

} // namespace rosy::field
