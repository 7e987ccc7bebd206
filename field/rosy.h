#pragma once
/// \file rosy.h
/// N-way rotational symmetries (N-RoSy) by their representation vector
/// (Palacios & Zhang 2007, Section 3). An N-RoSy with member angle θ and
/// strength R is stored as the complex number γ = R e^{i N θ}; sums and scalar
/// multiples of N-RoSys are the sums and multiples of their representation
/// vectors (Eq. 3), which is independent of which member vector was picked
/// (Eq. 2: N(θ + 2πk/N) ≡ Nθ mod 2π).

#include <Eigen/Core>

#include <cmath>
#include <complex>
#include <vector>

namespace rosy::field {

using Complex = std::complex<double>;

/// Wraps an angle into (−π, π].
inline double wrapAngle(double a) {
    a = std::remainder(a, 2.0 * M_PI);
    return a <= -M_PI ? a + 2.0 * M_PI : a;
}

/// γ(s) for the N-RoSy whose member vectors are at angles θ + 2πk/N, strength R ≥ 0.
inline Complex representation(double thetaRad, int nSym, double strength = 1.0) {
    return std::polar(strength, nSym * thetaRad);
}

/// γ⁻¹: the angle of the first member vector (in [0, 2π/N) up to rounding) of
/// the N-RoSy with representation vector u. Undefined (returns 0) for u = 0.
inline double memberAngle(Complex u, int nSym) {
    double a = std::arg(u) / nSym;
    return a < 0 ? a + 2.0 * M_PI / nSym : a;
}

/// All N member angles θ + 2πk/N, k = 0..N−1, of the N-RoSy with representation u.
inline std::vector<double> memberAngles(Complex u, int nSym) {
    std::vector<double> out(nSym);
    double a = memberAngle(u, nSym);
    for (int k = 0; k < nSym; ++k) out[k] = a + 2.0 * M_PI * k / nSym;
    return out;
}

/// A vertex-based N-RoSy field (Section 4.3): one representation vector per
/// vertex, expressed in that vertex's tangent frame (see frames.h). |u_v| is the
/// field's strength at v; u_v = 0 marks a vertex with no preferred direction.
struct RosyField {
    int nSym = 4;
    Eigen::VectorXcd u; ///< #V representation vectors in vertex frames
};

} // namespace rosy::field
