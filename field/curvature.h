#pragma once
/// \file curvature.h
/// Per-vertex curvature tensor of a triangle mesh, after Rusinkiewicz 2004,
/// "Estimating Curvatures and Their Derivatives on Triangle Meshes" (3DPVT).
///
/// Each face fits a second fundamental form II_f by least squares so that
/// II_f · e ≈ Δn for its three edges e (Δn the difference of the angle-weighted
/// vertex normals along e). Each vertex then averages the II_f of its faces,
/// re-expressed in the vertex tangent frame, weighted by the vertex's mixed
/// Voronoi area inside each face (Meyer et al. 2003), and diagonalizes the result.
///
/// Sign convention: II = dn/dx with outward normals, so a convex surface has
/// positive curvature. A sphere of radius r with outward (CCW) faces gives
/// kMax = kMin = +1/r; a saddle has kMin < 0 < kMax; flipping all faces flips
/// every sign.

#include "field/mesh.h"

#include <vector>

namespace rosy::field {

/// How the vertex normals that drive the fit are averaged from face normals.
enum class NormalWeighting {
    /// Weighted by corner angle (Mesh::vertexNormal): robust on scans and slivers,
    /// but only first-order accurate at irregular vertices, which biases the
    /// curvatures by a few percent that does not vanish under refinement (about 6%
    /// on a subdivided octahedron projected to a sphere).
    Angle,
    /// Max 1999, "Weights for computing vertex normals from facet normals": face
    /// normal × sin(angle) / (|e1| |e2|), exact for vertices on a sphere, as in
    /// Rusinkiewicz's paper. More accurate on smooth, well-shaped meshes; sliver
    /// faces (see computeCurvature) are left out because they would dominate.
    Max,
};

/// Options of computeCurvature().
struct CurvatureOptions {
    /// Vertex normal weighting; the reported VertexCurvature::normal uses it too.
    NormalWeighting normals = NormalWeighting::Max; // exact on spheres (see curvature_test)
    /// Rounds of 1-ring tensor averaging after the estimate (0 = off, the default).
    /// Each round replaces every vertex tensor by the area-weighted mean of its own
    /// and its ring neighbours' tensors, each rotated into the vertex tangent
    /// plane. Useful on noisy scans; it blurs features by about one ring per round.
    /// Must be >= 0 (negative values are treated as 0).
    int smoothingRounds = 0;
};

/// The curvature estimate at one vertex. All vectors are in world coordinates.
struct VertexCurvature {
    /// Unit vertex normal (CurvatureOptions::normals; by default Mesh::vertexNormal).
    /// If every face around the vertex has zero area it is +z and the curvatures are 0.
    Vec3 normal = Vec3::UnitZ();
    /// Unit tangent direction of maximal normal curvature.
    Vec3 dirMax = Vec3::UnitX();
    /// Unit tangent direction of minimal normal curvature; dirMin = normal × dirMax.
    Vec3 dirMin = Vec3::UnitY();
    /// Principal curvatures in 1/world units, kMax >= kMin, signed (see file comment).
    /// At an exact umbilic (kMax == kMin, e.g. a plane) dirMax is the first axis of
    /// the vertex frame, the projection of the vertex's first outgoing edge; near
    /// umbilics (a sphere) the directions are noise. Either way they are
    /// meaningless: callers detect |kMax − kMin| ≈ 0 and fall back.
    double kMax = 0;
    double kMin = 0;
    /// Mixed Voronoi area of the vertex (world units²): the weight used here. The
    /// areas of all vertices sum to the surface area.
    double area = 0;
};

/// Estimates the curvature tensor at every vertex.
/// \param mesh any clean mesh (boundaries and several components are fine).
/// \returns #V entries, indexed like mesh.positions().
/// Robustness: zero-area and sliver faces (2·area < 1e-6 · longest edge²) get zero
/// weight; a vertex with no usable face gets zero curvature; creases give large but
/// finite curvatures, the output never holds NaN or infinities. Boundary vertices
/// use only the faces they have, so their estimate is one-sided.
/// Deterministic: bit-identical results for any thread count. Empty mesh -> empty.
/// Cost: linear; about 20 ms for 38k vertices on 2 cores (no smoothing).
std::vector<VertexCurvature> computeCurvature(const Mesh &mesh,
                                              const CurvatureOptions &options = {});

/// How anisotropic the whole surface is: the area-weighted mean of |kMax − kMin|
/// over the area-weighted mean of |kMax| + |kMin|,
///
///     ρ = Σ_v A_v |kMax − kMin| / Σ_v A_v (|kMax| + |kMin|),   A_v = VertexCurvature::area.
///
/// ρ is in [0, 1] and scale-invariant (both sums scale with 1/length; a mesh scaled
/// by 1e-9 or 1e9 gives the same ρ). It is 0 on a sphere (kMax = kMin everywhere)
/// and on a plane (0/0 is reported as 0), 1 on a developable surface such as a
/// cylinder (kMin = 0), πR / (πR + 2r) on a torus with radii R > r. Near-umbilic
/// regions contribute little, so ρ measures how much of the surface has a real
/// principal direction.
///
/// kMinCurvatureAnisotropy is the threshold below which the principal directions of
/// the whole mesh count as noise (buildField then falls back to the smoothest field
/// with a `no-curvature-direction` warning). Why 0.02 (measured 2026-11-23): on a
/// sphere |kMax − kMin| is rounding noise with the default Max normals (ρ ≈ 1e-15 on
/// icospheres, 9e-5 on the float-stored CGAL sphere.ply) and discretisation error
/// with angle-weighted normals (ρ ≤ 0.008 on icospheres of levels 1–5), so 0.02
/// leaves a margin of 2.5 over the worst noise. Spheroids stretched by 2, 5 and 10%
/// give ρ = 0.013, 0.032 and 0.064: a shape needs its axes to differ by about 3% to
/// keep its curvature field. Every real mesh we ship or test is far above: 0.74–0.91
/// for the CGAL sample meshes (bunny 0.78, homer 0.74, fandisk 0.90), 0.39 for the
/// ellipsoid 1.5 : 1 : 0.75, 0.84 for the torus 2 : 0.6, 1 for a cylinder.
/// Known limit: a plane whose vertices carry rounding noise (say a tilted plane
/// stored in float) has noise curvatures with ρ ≈ 0.5 and is not detected; an
/// exactly planar mesh is.
constexpr double kMinCurvatureAnisotropy = 0.02;
double curvatureAnisotropy(const std::vector<VertexCurvature> &curvature);

/// Mean curvature H = (kMax + kMin) / 2 (1/world units; a sphere of radius r gives 1/r).
inline double meanCurvature(const VertexCurvature &c) { return 0.5 * (c.kMax + c.kMin); }
/// Gaussian curvature K = kMax · kMin (1/world units²).
inline double gaussianCurvature(const VertexCurvature &c) { return c.kMax * c.kMin; }

} // namespace rosy::field
