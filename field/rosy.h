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

/// std::remainder(a, 2π) (π, 2π: the doubles M_PI, 2 M_PI), bit for bit, without the
/// library call for |a| < 3π. The remainder a − n·2π (n the integer nearest a / 2π, ties
/// to even) is always a double, so where n is 0 it is a, and where n is ±1 the
/// subtraction a ∓ 2π has it as its exact result; n = ±1 holds exactly when that
/// difference lies strictly within ±π (rounding is monotone and π is a double) and is
/// not zero.
inline double remainderTwoPi(double a) {
    if (std::abs(a) <= M_PI) return a; // n = 0 (a tie at ±π goes to the even n = 0)
    const double d = a > 0 ? a - 2.0 * M_PI : a + 2.0 * M_PI;
    if (std::abs(d) < M_PI && d != 0) return d;
    // |a| >= 3π, a tie at ±3π, a = ±2π (whose remainder is a zero with a's sign), NaN
    // and infinities.
    return std::remainder(a, 2.0 * M_PI);
}

/// std::fmod(a, 2π), bit for bit, without the library call for 0 <= a < 4π: the result
/// a − n·2π (n = trunc(a / 2π)) is always a double, so where n is 0 it is a, and where
/// n is 1 (exactly when 2π <= a < 4π, both bounds doubles) the subtraction a − 2π has
/// it as its exact result.
inline double fmodTwoPi(double a) {
    if (a >= 0 && a < 2.0 * M_PI) return a;
    if (a >= 2.0 * M_PI && a < 4.0 * M_PI) return a - 2.0 * M_PI;
    return std::fmod(a, 2.0 * M_PI); // negative, 4π and beyond, NaN and infinities
}

/// Wraps an angle into (−π, π].
inline double wrapAngle(double a) {
    a = remainderTwoPi(a);
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
