#pragma once
/// \file editing.h
/// Topological editing of N-RoSy fields (Palacios & Zhang 2007, Sec. 5.2):
/// cancelling a pair of singularities of opposite index and moving one
/// singularity, each by replacing the field only inside a small disk-shaped
/// region R of faces around the singularities involved.
///
/// Region. R is grown from the first singular face, one face at a time, cheapest
/// first by the sum of distances from the face centroid to the two foci (the two
/// singularities, or the singularity and the target point: an ellipse around
/// them), until it holds the second face; then it is dilated ring by ring. A face
/// joins only if R stays a topological disk (it shares one edge with R and brings a
/// new vertex, or shares two edges), so R never encloses a hole. Other singular
/// faces never join, which keeps them, their index and their vertices untouched.
///
/// Solve. Vertices strictly inside R (interior mesh vertices whose whole fan lies
/// in R) are free; every other vertex is a Dirichlet value equal to its current
/// one (plus, for a move, the target face's corners, fixed to an Eq. 13 element).
/// The free vertices solve the transported Laplace equation (Eq. 14–15) with
/// cotangent weights, assembled on the region only, so an edit costs
/// O(size of R), not O(size of the mesh). Outside R's interior the field is left
/// bit for bit as it was, so all singularities outside R keep face and index.
///
/// Because the boundary values are kept, the total index inside R cannot change;
/// the edit succeeds when, after the solve, R holds no singular face (cancel) or
/// exactly the target face with the moved index (move). Otherwise R grows by one
/// ring and the solve is repeated, up to EditOptions::maxRounds times.

#include "core/error.h"
#include "field/frames.h"
#include "field/rosy.h"
#include "field/singularities.h"

#include <utility>
#include <vector>

namespace rosy::field {

struct EditOptions {
    /// Dilation rounds (one ring of faces each) before giving up.
    int maxRounds = 8;
    /// Rings added before the first solve: the ellipse-grown region alone is often a
    /// strip one face wide, which has no interior vertex to relax.
    int initialRings = 1;
    /// Where the edit was asked for ("--cancel #2", "scene.yaml:14:7"), used as the
    /// location of every InputError; empty: the mesh's name.
    FileLoc where;
};

/// What an edit did. Data only: callers decide what to print.
struct EditResult {
    std::vector<int> regionFaces; ///< faces of the final region R, ascending ids
    int freeVertices = 0;         ///< vertices whose value was replaced
    int rounds = 0;               ///< solves performed (1 = the first region worked)
    int targetFace = -1;          ///< move: the face now holding the singularity
};

/// Cancels singularities `a` and `b` (indices into findSingularities(frames,
/// field).singularities, the list sorted by face id) of indices +1/N and −1/N.
/// On success `field` changes only at vertices strictly inside the returned region,
/// and the field has exactly these two singularities fewer.
/// \throws InputError (naming both ids and the reason) and leaves `field`
///   unchanged if an id is out of range, a == b, the indices are not +1/N and −1/N,
///   no disk region avoiding the other singularities joins them, the region has no
///   interior vertex (both touch the mesh boundary), no region within
///   options.maxRounds rings removes them, or the region's solve fails on
///   degenerate geometry (the message names the solver's cause).
EditResult cancelPair(const TangentFrames &frames, RosyField &field, int a, int b,
                      const EditOptions &options = {});

/// Moves first-order singularity `s` (index into findSingularities(...).singularities)
/// into the face nearest to `target` (world units; snapped to the surface). Inside
/// the region the target face's corners take the Eq. 13 element of the same order,
/// its phase fitted to the current field at the target; the rest of the region is
/// relaxed. Moving into the singularity's own face is a no-op (rounds = 0).
/// \throws InputError and leaves `field` unchanged if `s` is out of range or not
///   first order, the target is off the surface (farther than 5% of the bounding-box
///   diagonal), lies in another singular face or on the mesh boundary, or no region
///   within options.maxRounds rings yields exactly one singularity, in the target face,
///   or the region's solve fails on degenerate geometry (naming the solver's cause).
EditResult moveSingularity(const TangentFrames &frames, RosyField &field, int s, const Vec3 &target,
                           const EditOptions &options = {});

/// Indices (i, j) into `singularities` of a first-order pair of opposite signs with
/// i near `p` and j near `q`: the pair minimising |p − pos_i| + |q − pos_j|
/// (Euclidean, world units; ties go to the lower ids), for "cancel the pair near
/// these points". \throws InputError if the list has no such pair.
/// `where` locates the InputError.
std::pair<int, int> nearestOppositePair(const std::vector<Singularity> &singularities, const Vec3 &p,
                                        const Vec3 &q, const FileLoc &where = {});

} // namespace rosy::field
