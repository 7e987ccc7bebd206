#pragma once
/// \file streamline_network.h
/// The paper's own remesher (Palacios & Zhang 2007, Sec. 6.2, in the manner of Alliez
/// et al. 2003): evenly spaced streamlines of a 4-RoSy field at spacing L in both of
/// its directions — the separatrices of every singularity first, when asked, each for
/// a limited distance as the paper does —
/// intersected on the surface; the crossings are the vertices, the pieces of line
/// between consecutive crossings the edges, and the faces come from the rotation
/// system of the arrangement (at each crossing its edges in counter-clockwise order
/// about the surface normal). `rosyhatch remesh --method streamlines`; the position
/// field (remesh.h) stays the default because it measures better (docs/remeshing.md,
/// "The streamline network, measured").
///
/// Placement follows Jobard and Lefer's evenly spaced streamlines, on the surface: a
/// line stops where it comes closer than StreamlineNetworkOptions::stopDistance to a
/// line running its way (or to itself further back); new lines start at L along the
/// lines already placed (the crossing direction) and at L across them, walked along
/// the field's other member, where no line running their way is nearer than
/// seedDistance. Ends beyond a line's first and last crossing are cut off. Everything
/// runs in a fixed order, so the output is the same for any thread count.

#include "remesh/remesh.h"

namespace rosy::remesh {

struct StreamlineNetworkOptions {
    double edgeLength = 0;     ///< L, the spacing of the lines, world units (> 0)
    bool separatrices = false; ///< trace every singularity's separatrices before any other line
    /// With `separatrices`: each is traced this far (× L) from its singularity before
    /// any other line, the paper's "we first trace all the separatrices for a certain
    /// distance", and runs on from there as an ordinary line in its turn; infinity: all
    /// of it first. Measured (docs/remeshing.md, "Separatrices in the network"): all of
    /// it first, the separatrices of nearby singularities run beside one another across
    /// the surface and the faces around the singularities are the large polygons the
    /// paper's Figure 4 shows without them; 6 L first, the singular points get rings of
    /// quads (Figure 4's two-ring p90 27–36° → 10–14° at six lengths), for more
    /// irregular vertices.
    double separatrixLength = 6;
    /// Jobard and Lefer's d_test: a line stops this close (× L) to a line running its way.
    double stopDistance = 0.5;
    /// Jobard and Lefer's d_sep test for seeds: refused this close (× L) to a line running their way.
    double seedDistance = 0.9;
    /// The surface's area over L² (about the number of crossings) above which the
    /// network is refused (InputError: the edge length is too short), as
    /// RemeshOptions::maxVertices bounds the position field.
    long long maxVertices = 20'000'000;
};

/// Remeshes the closed surface frames.mesh() along the 4-RoSy `field` with the
/// streamline network. `singularities` is the field's (findSingularities).
/// \throws InputError if N is not 4, the edge length or the separatrix length is not
///   positive (the separatrix length may be infinite), the edge length not finite, the
///   mesh has a boundary (the network does not follow boundaries: use the position
///   field) or the surface's area over L² exceeds options.maxVertices.
RemeshResult remeshStreamlines(const field::TangentFrames &frames, const field::RosyField &field,
                               const field::SingularityReport &singularities,
                               const StreamlineNetworkOptions &options);

} // namespace rosy::remesh
