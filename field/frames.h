#pragma once
/// \file frames.h
/// Per-vertex tangent frames and the discrete parallel transport between them
/// (Palacios & Zhang 2007, Eq. 14–15, made intrinsic as in geometry-central).
///
/// Frames. Around an interior vertex v the corner angles of its faces are
/// rescaled by s_v = 2π / Θ_v, Θ_v their sum, so that it sees a flat cone of 2π.
/// Boundary vertices keep their true angles (s_v = 1, a wedge of Θ_v). The angle of the
/// first outgoing halfedge (Mesh::outgoingBegin) is 0; the others follow
/// counter-clockwise at the rescaled cumulative corner angles. A tangent vector
/// at v is an angle (and length) in this polar chart.
///
/// Transport. A vector keeps its angle to the edge as it moves along it
/// (P&Z Section 5.1). Moving from v_j to v_i across halfedge h = (i → j) rotates
/// member angles by Δθ_ij = angle(i→j at i) − (angle(j→i at j) + π); a
/// representation vector is multiplied by e^{i N Δθ_ij}. The curvature that the
/// rescaling removes from the vertices reappears as a holonomy in each face,
/// K_f = Σ_corners s_v α − π. Discrete Gauss–Bonnet: Σ_f K_f + Σ_boundary (π − Θ_v)
/// = 2πχ exactly (the second sum is the boundary's geodesic turning).
///
/// Face frames. Each face has an orthonormal frame in its plane whose x axis runs
/// along its first halfedge; vertexToFace(h) is the rigid rotation taking angles
/// at tail(h) to that face's frame (exact along the edges of the face).

#include "field/mesh.h"
#include "field/mesh/uninitialized.h"
#include "field/rosy.h"

#include <vector>

namespace rosy::field {

class TangentFrames {
public:
    explicit TangentFrames(const Mesh &mesh);

    const Mesh &mesh() const { return *m_mesh; }

    /// Angle of halfedge h's direction (tail → head) in tail(h)'s frame, [0, 2π).
    double halfedgeAngle(int h) const { return m_angleOut[h]; }
    /// Angle of the direction head(h) → tail(h) in head(h)'s frame, [0, 2π).
    /// Defined for boundary halfedges too.
    double reverseAngle(int h) const { return m_angleIn[h]; }
    /// Rotation (radians, wrapped to (−π, π]) applied to a member vector moved from
    /// head(h)'s frame to tail(h)'s frame along the edge of h.
    double transportAngle(int h) const { return m_transport[h]; }
    /// Rescaled angle sum factor s_v (1 on flat interior vertices and on the boundary).
    double vertexScale(int v) const { return m_scale[v]; }
    /// Total intrinsic angle of v's chart: 2π inside, the true angle sum Θ_v on the boundary.
    double angleTotal(int v) const { return m_angleTotal[v]; }
    /// Holonomy of face f, K_f = Σ s_v α_v − π (radians).
    double faceHolonomy(int f) const { return m_faceHolonomy[f]; }

    /// Moves representation vector u (N-RoSy of order nSym) from head(h)'s frame to tail(h)'s.
    Complex transport(int h, Complex u, int nSym) const {
        return u * std::polar(1.0, nSym * m_transport[h]);
    }

    // --- extrinsic embedding of the vertex frames (for curvature input and drawing)
    /// Unit vertex normal (angle-weighted).
    const Vec3 &normal(int v) const { return m_normal[v]; }
    /// Intrinsic angle at v of a 3D direction d (projected to v's tangent plane).
    /// Piecewise linear in the projected wedge angles, exact along edges. 0 if d ∥ normal.
    double angleOfTangent(int v, const Vec3 &d) const;
    /// Unit 3D tangent direction at v for intrinsic angle phi (inverse of angleOfTangent).
    Vec3 tangentOfAngle(int v, double phiRad) const;

    // --- face frames
    /// Face frame axes: x along halfedge 3f, y = n × x (both unit, in the face plane).
    Vec3 faceAxisX(int f) const { return m_faceX[f]; }
    Vec3 faceAxisY(int f) const { return m_faceY[f]; }
    /// Rotation (radians) from tail(h)'s vertex frame to face(h)'s frame.
    double vertexToFace(int h) const { return m_vertexToFace[h]; }
    /// Representation vectors of the three corners of f, rotated into f's frame.
    std::array<Complex, 3> faceValues(int f, const RosyField &field) const;
    /// 2D coordinates of a 3D point in f's frame (origin at the face's first vertex).
    Vec2 toFace2D(int f, const Vec3 &p) const;
    /// 3D direction (unit, in the face plane) of a face-frame angle.
    Vec3 faceDirection(int f, double angleRad) const {
        return std::cos(angleRad) * m_faceX[f] + std::sin(angleRad) * m_faceY[f];
    }

private:
    void knots(int v, std::vector<double> &phi, std::vector<double> &psi) const;
    void tangentBasis(int v, Vec3 &e1, Vec3 &e2) const;

    // Sized without initial values: the constructor's parallel loops write every element.
    template <typename T>
    using Array = detail::UninitializedVector<T>;
    const Mesh *m_mesh;
    Array<double> m_angleOut, m_angleIn, m_transport; // #3F
    Array<double> m_scale;                           // #V
    Array<double> m_faceHolonomy;                    // #F
    Array<Vec3> m_normal;                            // #V
    Array<double> m_projAngle; // CSR like the rings: projected cumulative angle of each ring halfedge
    Array<double> m_projTotal; // #V: projected angle at the end of the last wedge
    Array<double> m_angleTotal; // #V: 2π inside, Θ_v on the boundary
    Array<Vec3> m_faceX, m_faceY;                    // #F
    Array<double> m_vertexToFace;                    // #3F
};

} // namespace rosy::field
