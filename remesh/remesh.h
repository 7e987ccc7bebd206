#pragma once
/// \file remesh.h
/// Field-aligned remeshing: a quad-dominant (4-RoSy) or triangle-dominant
/// (6-RoSy) polygon mesh whose edges follow a given N-RoSy field, with edges of
/// a target length L. Method (docs/remeshing.md): a position field in the manner
/// of Jakob et al. 2015, "Instant field-aligned meshes" — our field gives the
/// orientation as is; each vertex gets a point of a local lattice (squares of
/// side L, or triangles), made consistent with its neighbours' lattices up to the
/// field's rotational symmetry and integer translations by Gauss–Seidel
/// smoothing on a hierarchy of vertex clusters; for N = 4 the lattice's
/// dislocations are then moved into partners and singularities where that costs
/// little (remesh/dislocations.h); extraction collapses the edges
/// whose endpoints name the same lattice point, keeps those whose endpoints are
/// neighbouring lattice points, and builds faces from the resulting graph.
///
/// The output is the same bytes for any thread count: the position sweeps run
/// colour by colour (a fixed greedy colouring; vertices of one colour are not
/// neighbours and are updated in parallel), everything else in a fixed order.

#include "field/frames.h"
#include "field/mesh/poly_mesh.h"
#include "field/rosy.h"
#include "field/singularities.h"

#include <limits>
#include <map>
#include <string>
#include <vector>

namespace rosy::remesh {

using field::Vec3;

/// RemeshOptions::dislocationReach of `rosyhatch remesh --dislocations move`: the
/// moves that cost little (docs/remeshing.md, "Dislocations moved").
inline constexpr double kDislocationReachMove = 20;
/// RemeshOptions::dislocationConePenalty of `--dislocations remove`: a unit ends beside
/// a cone when no partner is within five lattice spacings more of path
/// (docs/remeshing.md, "Dislocations beside the cones").
inline constexpr double kDislocationConePenaltyRemove = 5;
/// `--dislocations remove`'s reach for partners and for cones, in lattice spacings of
/// clear path, and the weaker pull of its re-solved lattice points (RemeshOptions::
/// dislocationAnchor): the strain of its long moves spread over twice the distance
/// (docs/remeshing.md, "`remove`'s reach and pull").
inline constexpr double kDislocationReachRemove = 80;
inline constexpr double kDislocationConeReachRemove = 80;
inline constexpr double kDislocationAnchorRemove = 0.002;

struct RemeshOptions {
    /// Target edge length in world units (> 0).
    double edgeLength = 0;
    /// Pin the lattice at every singularity of index ±1/N, so that the lattice
    /// lines through it (the separatrices) become mesh edges and the singularity
    /// one irregular vertex (docs/remeshing.md, "Separatrices": measured worse, so off).
    bool separatrices = false;
    /// Gauss–Seidel sweeps per coarser hierarchy level, and on the finest level.
    /// Measured on bunny00 at L = 1 % (docs/remeshing.md): 16 coarse / 4 finest
    /// sweeps give 95.1 % quads and p90 corner deviation 11.7° against 94.9 % and
    /// 12.7° for 8 / 8, in less time (the finest level is the largest).
    int sweepsPerLevel = 16;
    int finestSweeps = 4;
    /// Rounds of smoothing of the output vertices (each halfway to its neighbours'
    /// mean, then onto the input surface). One round on bunny00: edge-length CV
    /// 0.124 -> 0.112, distance to the surface 0.29 % -> 0.40 % of the diagonal
    /// (target 0.5 %); fandisk's sharp edges suffer (input -> output 0.72 % -> 0.85 %).
    int relaxRounds = 1;
    /// The lattice spacing is L e^{λ φ} (clamped to [L/2, 2L]) with φ the scale
    /// function that absorbs the integrable part of the field's curl
    /// (docs/remeshing.md, "Where the irregular vertices come from"); λ = 0: L everywhere.
    double scaleStrength = 0;
    /// μ: the spacings along q and along n×q become L e^{λφ + μφ_q} and L e^{λφ + μφ_{n×q}}
    /// (each clamped to [L/2, 2L]), with φ_q, φ_{n×q} the scale functions that make each
    /// family's lattice coordinate closed (docs/remeshing.md, "Anisotropic scale"). N = 4.
    /// Measured at L = 1 %: 0.3 takes bunny00 from 506 irregular vertices to 471 (CV
    /// 0.112 -> 0.118, p90 angle 11.9° -> 11.5°), fandisk 255 -> 217, elephant 603 -> 521;
    /// 1 gives bunny00 362 but CV 0.159 (target 0.12). 0: L along both axes.
    double anisotropicScale = 0.3;
    /// Sharp features and boundaries (docs/remeshing.md, "Sharp features and
    /// boundaries"): with an angle D in (0, 180), the input's feature curves
    /// (field/features.h: creases whose faces' normals differ by more than D, and
    /// the boundary) constrain the position field — corners are lattice points,
    /// curve vertices keep theirs on the line along the curve — the output vertices
    /// there are put on the curves and corners (and move only along them when
    /// smoothed), the boundary's corners stay output vertices (on a ragged
    /// boundary, only where the faces traced beside them are sound), and
    /// the openings along the boundary are left open (not one narrower than about
    /// L on a ragged boundary, nor one touching another at a vertex). The field
    /// should be aligned to the same curves (FieldSpec::featureAngleDeg). 0: off.
    double featureAngleDeg = 0;
    /// Parts thinner than about L and gaps narrower than it (a tail, a finger, a
    /// tail lying on the body; measured by rays from each input vertex along its
    /// normal, both ways) get a finer lattice there: spacing 0.75 × the thickness,
    /// at least L / 4, growing back to L with distance (docs/remeshing.md, "When
    /// the topology is not kept", step 6). false: L everywhere, as before 2026-12-04.
    bool thinParts = true;
    /// The position field's dislocations moved into pairs and into the field's
    /// singularities before the extraction (remesh/dislocations.h; docs/remeshing.md,
    /// "Dislocations moved"), each unit up to this cost (DislocationOptions::reach, in
    /// lattice spacings of clear path); 0: none, infinity: all that can be moved. N = 4.
    double dislocationReach = kDislocationReachMove;
    /// A unit may also end beside a singularity (the cone takes it although it leaves
    /// the cone one unit outside its class: an irregular vertex next to the singular
    /// one) at this extra cost in lattice spacings (DislocationOptions::conePenalty);
    /// infinity: only into partners and cones it completes (`move`). `remove` uses
    /// kDislocationConePenaltyRemove.
    double dislocationConePenalty = std::numeric_limits<double>::infinity();
    /// How far from a cone a unit may end beside it (DislocationOptions::coneReach,
    /// lattice spacings of path); `remove` uses kDislocationConeReachRemove.
    double dislocationConeReach = 20;
    /// The pull of each moved lattice point to where it was (DislocationOptions::
    /// anchor); `remove` uses kDislocationAnchorRemove.
    double dislocationAnchor = 0.005;
    /// The input is subdivided until its mean edge is at most L / 2, then edges
    /// longer than L (or than a thin part's spacing) are bisected (repairs["long_edges_split"]); more vertices
    /// than this are refused (InputError: the edge length is too short).
    long long maxVertices = 20'000'000;
};

/// `rosyhatch remesh --dislocations keep|move|remove` (N = 4; docs/remeshing.md,
/// "Dislocations moved"): keep moves nothing; move (the RemeshOptions defaults) the
/// units that cost little, into partners and cones they complete; remove every unit
/// that has a partner or a cone within kDislocationReachRemove, a lone one ending
/// beside a cone, with the weaker pull.
enum class DislocationMode { Keep, Move, Remove };
void setDislocationMode(RemeshOptions &options, DislocationMode mode);

/// The polygon mesh and what it cost.
struct RemeshResult {
    int nSym = 4;
    std::vector<Vec3> positions;
    std::vector<std::vector<int>> polygons; ///< counter-clockwise seen from outside
    /// Repairs the extraction made (named counts: dangling edges removed, valence-2
    /// vertices dissolved, holes filled, faces dropped), for the report.
    std::map<std::string, int> repairs;
    std::map<std::string, double> timingsMs; ///< hierarchy, position, extraction
    /// The same polygons in OpenMesh's structure (what the writers write). Polygons
    /// OpenMesh refuses (non-manifold) are left out of both, counted in repairs.
    field::PolyMesh poly;
};

/// Remeshes frames.mesh() along `field` (N = 4 or 6). `singularities` is the
/// field's (findSingularities), used with options.separatrices.
/// \throws InputError if N is not 4 or 6 or the edge length is not positive and finite.
RemeshResult remesh(const field::TangentFrames &frames, const field::RosyField &field,
                    const field::SingularityReport &singularities, const RemeshOptions &options);

/// Compacts `positions` to the vertices `polygons` use and adds the polygons to
/// result.poly and result.polygons in order; the ones OpenMesh refuses as
/// non-manifold are left out of both and counted in repairs["faces_refused_by_openmesh"].
void intoPolyMesh(const std::vector<Vec3> &positions, const std::vector<std::vector<int>> &polygons,
                  RemeshResult &result);

} // namespace rosy::remesh
