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
/// faces whose positions are smoothed at a world scale (smoothAtScale(), which does
/// not shrink the shape) until the noise is gone and the shape is left; frames, field, edits, singularities and separatrices
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

/// The smoothed copy's smoothing radius relative to the bounding-box diagonal: a world
/// scale, the same part of the shape at any resolution (docs/hatching.md: at 0.006 the
/// copies of scan-like elephants of 568k and 9.1M faces have 94 and 96 singularities
/// against the clean elephant's 108; 20 rounds of Taubin smoothing, a scale in edges,
/// left 126 and 418).
constexpr double kScanSmoothingRadius = 0.006;
/// ... and at least this many mean edge lengths: on a coarser scan the noise is the
/// same part of an edge and needs the same reach in edges (a 136k-face ellipsoid, 260
/// edges across, keeps 72 singularities at 0.006 of its diagonal, 1.5 edges, and 8 at 4, its
/// clean version's count).
constexpr double kScanSmoothingEdges = 4.0;

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
    double radius = 0; ///< world units
};

/// `mesh` with the same vertices and faces, its interior vertices smoothed at `radius`
/// (world units) and boundary vertices held: x₁ = A⁻¹ x₀ with A = I + tL, L the
/// uniform graph Laplacian and t = (radius / mean edge)², one implicit diffusion step
/// of that reach; then the low-pass of the displacement, A⁻¹(x₁ − x₀), taken back out
/// (the shape's shrinkage), so the filter is 1 − (tk / (1 + tk))² for a Laplacian
/// eigenvalue k: flat to second order at the shape's scale, zero for the noise. Two
/// conjugate-gradient solves, matrix-free and parallel, the same bits for any thread
/// count. Vertices may move along the surface (up to about the radius on very uneven
/// triangles); the field is carried back by vertex, and a field varies at the
/// smoothing length (FieldSpec::smoothingLength, 0.08 of the diagonal), far above it.
SmoothedSurface smoothAtScale(const Mesh &mesh, double radius);
/// smoothAtScale() at kScanSmoothingRadius times the bounding-box diagonal or
/// kScanSmoothingEdges mean edge lengths, whichever is longer.
SmoothedSurface smoothAtScale(const Mesh &mesh);

/// `field` (on `from`'s vertices) carried to `to`, a mesh with the same vertices:
/// each vertex's first member projected onto `to`'s tangent plane there, its
/// magnitude kept; a member that projects to nothing (the planes perpendicular)
/// gives a zero vector.
RosyField carryField(const TangentFrames &from, const RosyField &field, const TangentFrames &to);

/// `report` (found on a mesh with the same faces as `onto`) with each position
/// recomputed on `onto` from its face and barycentric coordinates.
SingularityReport placedOn(SingularityReport report, const Mesh &onto);

} // namespace rosy::field
