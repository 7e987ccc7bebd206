#pragma once
/// \file scan_noise.h
/// Fields on noisy scans: judged by what the field became, computed on a smoothed
/// copy of the surface and carried back.
///
/// On a scan whose vertices carry noise along the normal at the scale of its edges
/// (and needle triangles beside normal ones), a field built on the surface itself is
/// noise: the curvature of the noise (about σ/e², e the edge length) outweighs the
/// shape's hundreds of times, and the discrete connection itself turns at random
/// around single faces, so that even the globally smoothest field has singularities
/// everywhere (docs/hatching.md, "Fields on noisy scans"). Tell-tale: hundreds of
/// singularities within a disc of the smoothing length, where modelled meshes and
/// clean scans have a few.
///
/// The remedy keeps the mesh and moves its points: a copy with the same vertices and
/// faces whose positions are smoothed along their normals (Taubin's λ|μ, which does
/// not shrink the shape) until the noise is gone and the shape's curvature at the
/// scale of a few edges is left; frames, field, edits, singularities and separatrices
/// are computed on the copy, and the field's directions are carried back to the
/// scan's own vertices by projection onto their tangent planes. The singularities
/// keep their faces and barycentric coordinates (the faces are the same), their
/// positions are put back on the scan's surface.

#include "field/frames.h"
#include "field/rosy.h"
#include "field/singularities.h"

#include <memory>

namespace rosy::field {

/// The reference length of the judgement, relative to the bounding-box diagonal: the
/// curvature source's default smoothing length (FieldSpec::smoothingLength).
constexpr double kScanNoiseScale = 0.08;

/// Above this many singularities per (kScanNoiseScale × diagonal)² of surface area a
/// field is judged to be the surface's noise. Measured (docs/hatching.md, "Fields on
/// noisy scans"): 133 of CGAL's meshes 0.1–6.3 (b9_mesh 6.25, femur 5.4, bunny00 0.45),
/// a 270k-face scan-like armadillo at noise 0.1 5.1 (not judged), a 568k-face
/// scan-like elephant at noise 0.3 329, an 8M-face one 2,060.
constexpr double kScanNoiseDensity = 20.0;

/// Taubin λ|μ rounds of the smoothed copy: enough that the copy of a noise-0.3 scan
/// carries as many singularities as its clean original (docs/hatching.md).
constexpr int kScanSmoothingRounds = 20;

/// Singularities per (kScanNoiseScale × diagonal)² of `mesh`'s surface; 0 on a mesh
/// without area.
double singularityDensity(const Mesh &mesh, size_t nSingularities);

/// Whether a field with `nSingularities` on `mesh` is judged to be noise
/// (singularityDensity() above kScanNoiseDensity).
bool fieldIsScanNoise(const Mesh &mesh, size_t nSingularities);

/// A copy of a mesh with its positions smoothed and the frames of that copy; both on
/// the heap so that the frames' pointer to the mesh stays valid when this moves.
struct SmoothedSurface {
    std::unique_ptr<Mesh> mesh;
    std::unique_ptr<TangentFrames> frames;
    int rounds = 0;
};

/// `mesh` with the same vertices and faces, each interior vertex moved along its
/// (angle-weighted) normal by `rounds` Taubin λ|μ rounds (λ = 0.5, μ = −0.53, the
/// uniform umbrella operator's normal part: no drift along the surface, so needle
/// triangles stay where they are); boundary vertices stay. Deterministic for any
/// thread count. \throws InputError when the copy is not a valid mesh (it always is
/// for a valid input).
SmoothedSurface smoothAlongNormals(const Mesh &mesh, int rounds = kScanSmoothingRounds);

/// `field` (on `from`'s vertices) carried to `to`, a mesh with the same vertices:
/// each vertex's first member projected onto `to`'s tangent plane there, its
/// magnitude kept; a member that projects to nothing (the planes perpendicular)
/// gives a zero vector.
RosyField carryField(const TangentFrames &from, const RosyField &field, const TangentFrames &to);

/// `report` (found on a mesh with the same faces as `onto`) with each position
/// recomputed on `onto` from its face and barycentric coordinates.
SingularityReport placedOn(SingularityReport report, const Mesh &onto);

} // namespace rosy::field
