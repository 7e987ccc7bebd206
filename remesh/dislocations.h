#pragma once
/// \file dislocations.h
/// The position field's dislocations moved into pairs and into the field's
/// singularities (docs/remeshing.md, "Dislocations moved"). N = 4.
///
/// Around a triangle of the position field's finest level whose field has no
/// singularity, the three edges' integer lattice offsets (remesh/square_lattice.h)
/// should add up to zero once turned into one lattice; a triangle where they add up
/// to b ≠ 0 (its Burgers vector) is a dislocation: the lattice gains a row there,
/// and the extraction makes a triangle with a valence-5 corner. Written from the
/// idea of QuadriFlow (Huang et al. 2018, "QuadriFlow: a scalable and robust method
/// for quadrangulation"), its integer offsets made consistent before extraction; our
/// own search and solve, no code of theirs:
///
/// 1. Each unit of each b is moved, across the triangles' shared edges, to the
///    cheapest place that takes it: a triangle with the opposite unit (the two
///    cancel), a singular triangle whose translation class it completes (a cone of
///    a quarter turn absorbs a translation of even |x| + |y|, one of a half turn one
///    with both components even), or an open boundary — and, with a finite
///    `conePenalty`, a cone near enough that the unit leaves one unit outside its
///    class (the cone with a dislocation beside it). Crossing an edge changes its
///    integer offset by one unit; the cost is how much farther that puts the offset
///    from the real-valued one the two lattices have (1 + 2 δ·(t − c) for the unit
///    δ, offset t and real offset c: near zero where the rounding was a toss-up,
///    about 1 where it was clear; at least `costFloor`). Dijkstra's search per unit;
///    in passes whose largest cost doubles up to `reach` (in lattice spacings of
///    clear edges), so the cheap moves are made first. Edges at a fixed lattice point (a feature line, a corner, a pinned
///    singularity) are not crossed.
/// 2. The lattice points are solved again for the changed offsets: least squares of
///    o_j − o_i − T_ij over all edges (T_ij the offset's vector in i's lattice), each
///    o_i in its tangent plane, with a weak pull `anchor` to where it was; since the
///    points fitted the old offsets, only their change is solved for, so nothing moves
///    far from the moves (the whole mismatch solved instead moved a CAD part's
///    boundary: ALSTOM_TEST4's distance 0.09 % -> 1.09 %). Conjugate gradients
///    (Jacobi), parallel over vertices, the same result for any thread count.
/// 3. Every vertex takes the point of its new lattice nearest to it again, so the
///    extraction sees the changed offsets in the positions.
///
/// The price is strain: the rows a move adds or removes spread over the lattice
/// around the path (edge-length CV and corner angles grow with `reach`).

#include "remesh/square_lattice.h"

#include <array>
#include <limits>
#include <vector>

namespace rosy::remesh {

/// The finest level of the position field, as the moves read and change it.
struct DislocationInput {
    const std::vector<Vec3> &p, &n, &q;
    std::vector<Vec3> &o; ///< lattice points: solved again and rounded when a move was made
    const std::vector<double> &s, &s2;
    const std::vector<int> &adjOffset, &adj;          ///< CSR neighbours, sorted
    const std::vector<std::array<int, 3>> &triangles; ///< the level's faces, consistently oriented
    /// Lattice points the remesher keeps where they are: pinned singular points, and
    /// points on feature lines and at their corners (onLine, corner: empty when there
    /// are none). These, thin parts (a spacing below L / 2, which only their caps
    /// give: moves there lost a wall of CGAL's femur, distance 1.18 % -> 2.08 %), the
    /// rings around all of them (DislocationOptions::heldRings) and the places where
    /// the surface bends with a radius below half the spacing are held: not moved,
    /// not crossed.
    const std::vector<char> &pinned, &onLine, &corner;
    double L; ///< the target edge length
};

struct DislocationOptions {
    /// The largest cost of one unit's move, in lattice spacings of a path across
    /// edges whose rounding was clear (each such edge of the level costs about 1; the
    /// cap is this times the level's edges per spacing, so the same reach means the
    /// same distance whether the input was subdivided once or not); infinity: every
    /// move that can be made; 0: none.
    double reach = 20;
    /// Passes of the search, the k-th (from 0) with the largest cost reach / 2^(passes − 1 − k).
    int passes = 5;
    double costFloor = 0.01;
    /// The kept lattice points and thin parts (DislocationInput) and this many rings
    /// of neighbours around them are neither moved nor crossed (a boundary corner
    /// lost its output vertex otherwise: CGAL's blobby_3cc, two-sided distance
    /// 0.57 % -> 1.32 % without).
    int heldRings = 2;
    /// A cone may also take a unit that leaves it one unit outside its class: the
    /// cone with a dislocation beside it, an irregular vertex next to the singularity
    /// instead of one farther away. Such a move costs this much more, in lattice
    /// spacings as `reach`; infinity: a cone takes only what completes its class.
    double conePenalty = std::numeric_limits<double>::infinity();
    /// ... and only this near the cone (lattice spacings, the penalty included): with
    /// an unbounded reach a unit without a partner crossed a CAD part to the nearest
    /// cone (CGAL's P: p90 corner deviation 4.9° -> 12.2° with `remove`, 5.8° within 20).
    double coneReach = 20;
    /// Weight of each lattice point's pull to where it was, against 1 per edge (the
    /// strain of a move spreads about 1 / √anchor edges from its path; 0.001 lowered
    /// bunny00's p90 corner deviation by 0.2–0.4° but moved the surface on two CGAL
    /// meshes: colored_tetra's distance 0.35 % -> 1.01 %, cow's 0.54 % -> 1.10 %).
    double anchor = 0.005;
    /// Relative residual of the conjugate gradients.
    double tolerance = 1e-3;
    int maxIterations = 1000;
};

struct DislocationStats {
    int before = 0; ///< triangles with b ≠ 0 (singular ones not counted)
    int moved = 0;  ///< units moved
    int left = 0;   ///< triangles with b ≠ 0 after the moves
    int conesWithOneBefore = 0; ///< singular triangles outside their class (a dislocation beside the cone)
    int conesWithOne = 0;       ///< the same after the moves
    int iterations = 0;
};

/// Moves the dislocations of `in` (see above). Leaves `in.o` as it was when no
/// move is made.
DislocationStats moveDislocations(const DislocationInput &in, const DislocationOptions &options);

} // namespace rosy::remesh
