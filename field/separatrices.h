#pragma once
/// \file separatrices.h
/// Separatrices of N-RoSy field singularities (Palacios & Zhang 2007, Sec. 4.2,
/// Eq. 8–12).
///
/// Near a singularity in face f the representation vector field is linear,
/// u(p* + r(cos θ, sin θ)) ≈ r J (cos θ, sin θ) with J = [[a b], [c d]] the constant
/// Jacobian of the barycentric interpolation in f's 2D frame. A ray from the
/// singularity at angle θ is a separatrix when θ is itself a member direction there
/// (Eq. 8): N θ ≡ arg(J v(θ)) (mod 2π), v(θ) = (cos θ, sin θ). Its necessary part is
/// Eq. 9, sin Nθ (a cos θ + b sin θ) − cos Nθ (c cos θ + d sin θ) = 0 (the vectors
/// e^{iNθ} and Jv are parallel); with t = tan θ it is a polynomial of degree ≤ N + 1.
/// Of each root the sign of e^{iNθ} · Jv decides:
///  - even N: f(θ + π) = −f(θ) and the sign flips with θ → θ + π, so each root in
///    [0, π) gives exactly one separatrix, at θ or θ + π (lines of an even-N field have
///    no orientation, so all are outgoing);
///  - odd N: f(θ + π) = f(θ) and the sign is the same at θ and θ + π, so every root
///    gives two rays; positive: outgoing (Eq. 8), negative: incoming (Eq. 12,
///    N θ ≡ arg(Jv) + π: the member at the ray points at the singularity).
/// Counts for first-order singularities (J conformal or anti-conformal):
///  - index −1/N (u ∝ z̄, arg Jv = −θ + c): (N + 1) θ ≡ c: N + 1 outgoing rays, and for
///    odd N also N + 1 incoming ones (N = 1, a saddle: 2 out + 2 in);
///  - index +1/N (u ∝ z, arg Jv = θ + c): (N − 1) θ ≡ c: N − 1 outgoing rays, plus
///    N − 1 incoming for odd N (N = 3: 2 + 2 = 4 rays bounding the 4 hyperbolic
///    sectors of the paper's Figure 5). For N = 1 (source, sink, centre) Eq. 9 either
///    vanishes identically (every ray is a trajectory, none is distinguished) or has no
///    root: no separatrices.

#include "field/singularities.h"
#include "field/streamlines.h"

#include <Eigen/Core>

#include <vector>

namespace rosy {
class JsonWriter;
}

namespace rosy::field {

/// One separatrix direction of a linear field in a face frame.
struct SeparatrixDirection {
    double angleRad = 0;   ///< in the face frame, [0, 2π)
    bool incoming = false; ///< odd N only: the field flows toward the singularity along it
};

/// Jacobian [[∂Re u/∂x, ∂Re u/∂y], [∂Im u/∂x, ∂Im u/∂y]] of the barycentric
/// interpolation of face f's corner representation vectors, in f's 2D frame
/// (per world unit). Zero for a degenerate face.
Eigen::Matrix2d faceJacobian(const TangentFrames &frames, const RosyField &field, int face);

/// Separatrix directions of the linear field u(v) = J v for an N-RoSy (Eq. 9–12),
/// sorted by angle. Empty when Eq. 9 vanishes identically (J a multiple of the identity
/// for N = 1 or J = 0) or has no real root.
std::vector<SeparatrixDirection> separatrixDirections(const Eigen::Matrix2d &jacobian, int nSym);

struct SeparatrixOptions {
    /// Trace options; maxLength ≤ 0 is replaced by maxLengthRelative × bbox diagonal.
    StreamlineOptions streamline;
    /// Length limit as a fraction of the bounding-box diagonal (when streamline.maxLength ≤ 0).
    double maxLengthRelative = 0.05;
};

struct Separatrix {
    int singularity = -1;  ///< index into the singularity list
    double angleRad = 0;   ///< direction in the singular face's frame
    Vec3 direction3D = Vec3::Zero(); ///< unit world direction of the ray
    bool incoming = false; ///< odd N: the field flows toward the singularity along it
    Streamline line;       ///< from the singularity's position outwards
};

/// All separatrices of all singularities, traced on the surface from the
/// singularity's position (walking straight out of the singular face first, then
/// following the field; they stop at other singular faces, the boundary or the length
/// limit). Ordered by singularity, then angle. Parallel over singularities, deterministic.
std::vector<Separatrix> traceSeparatrices(const TangentFrames &frames, const RosyField &field,
                                          const std::vector<Singularity> &singularities,
                                          const SeparatrixOptions &options = {});

/// Writes `"separatrices": [{"singularity": i, "direction": [x,y,z], "incoming": b,
/// "polyline": [[x,y,z], ...]}, ...]` as a member of the currently open JSON object.
void writeSeparatricesJson(rosy::JsonWriter &json, const std::vector<Separatrix> &separatrices);

} // namespace rosy::field
