#include "field/winding_number.h"

#include <cmath>

namespace rosy::field {

namespace {

/// Van Oosterom and Strackee: the solid angle of triangle (a, b, c) seen from the origin.
double solidAngle(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    // atan2 keeps the half-angle's quadrant: the solid angle is 2 atan2(num, den).
    return 2 * std::atan2(num, den);
}

} // namespace

double windingNumber(const Mesh &mesh, const Vec3 &p) {
    double sum = 0;
    for (const Face &f : mesh.faces())
        sum += solidAngle(mesh.position(f[0]) - p, mesh.position(f[1]) - p, mesh.position(f[2]) - p);
    return sum / (4 * M_PI);
}

double windingNumber(const std::vector<Vec3> &positions, const std::vector<std::array<int, 3>> &triangles,
                     const Vec3 &p) {
    double sum = 0;
    for (const std::array<int, 3> &t : triangles)
        sum += solidAngle(positions[size_t(t[0])] - p, positions[size_t(t[1])] - p, positions[size_t(t[2])] - p);
    return sum / (4 * M_PI);
}

} // namespace rosy::field
