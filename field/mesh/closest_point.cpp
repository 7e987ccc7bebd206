#include "field/mesh/closest_point.h"

#include <algorithm>
#include <utility>

namespace rosy::field {

// Regions of the triangle's plane by the signs of barycentric-like dot products:
// vertex regions first, then edges, then the inside.
Vec3 closestPointOnTriangle(const Vec3 &p, const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double den = d1 - d3;
        return den > 0 ? Vec3(a + ab * (d1 / den)) : a;
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double den = d2 - d6;
        return den > 0 ? Vec3(a + ac * (d2 / den)) : a;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double den = (d4 - d3) + (d5 - d6);
        return den > 0 ? Vec3(b + (c - b) * ((d4 - d3) / den)) : b;
    }
    const double sum = va + vb + vc;
    if (!(sum > 0)) { // degenerate: the best of the three edges
        Vec3 best = a;
        double bestD = (p - a).squaredNorm();
        for (const auto &[u, w] : {std::pair<Vec3, Vec3>{a, b}, {b, c}, {c, a}}) {
            const Vec3 e = w - u;
            const double len2 = e.squaredNorm();
            const double t = len2 > 0 ? std::clamp((p - u).dot(e) / len2, 0.0, 1.0) : 0.0;
            const Vec3 q = u + t * e;
            if ((p - q).squaredNorm() < bestD) bestD = (p - q).squaredNorm(), best = q;
        }
        return best;
    }
    const double v = vb / sum, w = vc / sum;
    return a + ab * v + ac * w;
}

} // namespace rosy::field
