#pragma once
/// \file square_lattice.h
/// Arithmetic of the square (rectangular) lattices of the position field (N = 4),
/// shared by the remesher (remesh.cpp) and the dislocation moves (dislocations.cpp).
/// Each vertex i holds a lattice: origin o_i, axes q_i and w_i = n_i × q_i, spacings
/// s_i along q_i and s2_i along w_i. Internal to remesh/.

#include "field/mesh.h"

#include <Eigen/Core>

#include <cmath>
#include <vector>

namespace rosy::remesh {

using field::Vec3;

/// The point nearest to the midpoint of p0, p1 that lies in both tangent planes
/// (x = m + α n0 + β n1 with n0·x = n0·p0 and n1·x = n1·p1, regularized where the
/// planes are nearly parallel).
inline Vec3 middlePoint(const Vec3 &p0, const Vec3 &n0, const Vec3 &p1, const Vec3 &n1) {
    const Vec3 m = 0.5 * (p0 + p1);
    const double c = n0.dot(n1);
    const double r0 = n0.dot(p0 - m), r1 = n1.dot(p1 - m);
    const double den = 1 - c * c + 1e-4;
    const double alpha = (r0 - c * r1) / den, beta = (r1 - c * r0) / den;
    return m + alpha * n0 + beta * n1;
}

/// N = 4: which of q1, n1×q1, −q1, −n1×q1 (0 to 3) is closest to q0 (the first
/// of equals). Odd: q1's lattice axes are swapped against q0's, and so are its two
/// spacings.
inline int compatIndex4(const Vec3 &q0, const Vec3 &q1, const Vec3 &n1) {
    const double d0 = q0.dot(q1), d1 = q0.dot(n1.cross(q1));
    int best = 0;
    double bestDot = d0;
    if (d1 > bestDot) bestDot = d1, best = 1;
    if (-d0 > bestDot) bestDot = -d0, best = 2;
    if (-d1 > bestDot) best = 3;
    return best;
}

/// The vertices' lattices, as the remesher's finest level holds them.
struct SquareLattices {
    const std::vector<Vec3> &p, &n, &q, &o;
    const std::vector<double> &s, &s2;
};

/// N = 4: the integer offset of edge i -> j, j's lattice point minus i's in i's
/// lattice: the lattice point of i nearest the two tangent planes' middle point,
/// j's lattice point nearest that (j's axes turned onto i's by compatIndex4), and
/// the difference of their indices. With `residual`, also the remainder
/// (that second point minus the first, in i's lattice units): the offset the two
/// lattices would have without rounding is the integer one plus it.
inline Eigen::Vector2i squareOffset(const SquareLattices &F, int i, int j, Eigen::Vector2d *residual = nullptr) {
    const int rot = compatIndex4(F.q[i], F.q[j], F.n[j]);
    const Vec3 wjOwn = F.n[j].cross(F.q[j]);
    const Vec3 qj = rot == 0 ? F.q[j] : rot == 1 ? wjOwn : rot == 2 ? Vec3(-F.q[j]) : Vec3(-wjOwn);
    const double sj = rot & 1 ? F.s2[j] : F.s[j], sj2 = rot & 1 ? F.s[j] : F.s2[j];
    const Vec3 wi = F.n[i].cross(F.q[i]), wj = F.n[j].cross(qj);
    auto coords = [](const Vec3 &d, const Vec3 &q, const Vec3 &w, double s, double s2) {
        return Eigen::Vector2d(q.dot(d) / s, w.dot(d) / s2);
    };
    auto nearest = [&](const Vec3 &o, const Vec3 &q, const Vec3 &w, double s, double s2, const Vec3 &p) {
        const Eigen::Vector2d c = coords(p - o, q, w, s, s2);
        return Vec3(o + std::round(c.x()) * s * q + std::round(c.y()) * s2 * w);
    };
    const Vec3 m = middlePoint(F.p[i], F.n[i], F.p[j], F.n[j]);
    const Vec3 oi = nearest(F.o[i], F.q[i], wi, F.s[i], F.s2[i], m);
    const Vec3 oj = nearest(F.o[j], qj, wj, sj, sj2, oi);
    const Eigen::Vector2d ki = coords(F.o[i] - oi, F.q[i], wi, F.s[i], F.s2[i]);
    const Eigen::Vector2d kj = coords(F.o[j] - oj, qj, wj, sj, sj2);
    if (residual) *residual = coords(oj - oi, F.q[i], wi, F.s[i], F.s2[i]);
    return {int(std::lround(kj.x())) - int(std::lround(ki.x())), int(std::lround(kj.y())) - int(std::lround(ki.y()))};
}

} // namespace rosy::remesh
