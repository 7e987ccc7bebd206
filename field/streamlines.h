#pragma once
/// \file streamlines.h
/// Streamlines of N-RoSy fields on triangle meshes (Palacios & Zhang 2007, Sec. 4).
///
/// Inside face f the field is the barycentric interpolation of the three corner
/// representation vectors expressed in f's frame (TangentFrames::faceValues); its
/// member directions at a point are γ⁻¹ of the interpolated value. A streamline
/// follows, at each step, the member closest to its current heading, so it works for
/// every N (for odd N a line only runs forward along members). Steps are straight in
/// the face plane, with the direction taken at the segment's midpoint (implicit
/// midpoint rule, a few fixed-point iterations), and cut at the face's edge. Across
/// an edge the heading is unfolded into the neighbour: it keeps its angle to the
/// shared edge.

#include "field/frames.h"
#include "field/rosy.h"

#include <vector>

namespace rosy::field {

/// Why a streamline ended.
enum class StreamlineStop {
    MaxLength,   ///< reached StreamlineOptions::maxLength
    MaxSteps,    ///< reached StreamlineOptions::maxSteps segments
    Boundary,    ///< left the mesh through a boundary edge
    Singularity, ///< entered a face with a nonzero index
    Closed,      ///< came back to its start, heading the same way
    ZeroField,   ///< the interpolated representation vector vanished (no direction)
    Stalled,     ///< the field turns back at an edge (the line cannot advance)
};

/// "max-length", "max-steps", "boundary", "singularity", "closed", "zero-field", "stalled".
const char *toString(StreamlineStop stop);

struct StreamlineOptions {
    /// Longest straight segment, world units. ≤ 0: half the mesh's mean edge length.
    double stepLength = 0;
    /// Length at which tracing stops, world units. ≤ 0: no limit (maxSteps still applies).
    double maxLength = 0;
    /// Maximum number of segments (edge crossings count as segment ends).
    int maxSteps = 100000;
    /// Stop on entering a face with a nonzero index (needs the faceIndex argument).
    bool stopAtSingularFaces = true;
    /// Follow the field backwards: at each point the negation of the member closest to
    /// the reversed heading. Matters for odd N only (incoming separatrices).
    bool reverseField = false;
    /// Also trace backwards from the seed (heading −direction, reverseField flipped) and
    /// prepend that half, so the polyline runs along the field.
    bool bothDirections = false;
    /// Closing distance, world units: the line is Closed when a segment passes this
    /// close to the start point while heading the same way. ≤ 0: half the step length.
    double closeTolerance = 0;
    /// Walk straight along `direction3D` until the start face's edge before following
    /// the field: for leaving a singular face along a separatrix direction.
    bool leaveStartFaceStraight = false;
};

/// A traced polyline on the surface.
struct Streamline {
    std::vector<Vec3> points; ///< world positions, in tracing order (≥ 1 point)
    std::vector<int> faces;   ///< face holding each point (the face entered, for edge points)
    double length = 0;        ///< world length of the polyline
    StreamlineStop stop = StreamlineStop::MaxSteps;          ///< end of the forward half
    StreamlineStop stopBackward = StreamlineStop::MaxSteps;  ///< start end (bothDirections only)
};

/// Traces a streamline of `field` from a point of `face`.
/// \param face        seed face in [0, #F)
/// \param barycentric seed point in the face's corner order (clamped into the triangle and renormalized)
/// \param direction3D initial heading (world; projected into the face plane). The
///        member closest to it is followed. A heading normal to the face falls back
///        to the face's x axis.
/// \param faceIndex   optional #F face index numerators (faceIndexNumerators) for
///        stopAtSingularFaces; null: only ZeroField stops at singularities.
/// Never throws on data; every end is a StreamlineStop. Deterministic.
Streamline traceStreamline(const TangentFrames &frames, const RosyField &field, int face,
                           const Vec3 &barycentric, const Vec3 &direction3D,
                           const StreamlineOptions &options, const std::vector<int> *faceIndex = nullptr);

/// Barycentric coordinates (corner order of `face`) of the projection of world
/// point p onto face's plane; not clamped.
Vec3 barycentricOf(const Mesh &mesh, int face, const Vec3 &p);

} // namespace rosy::field
