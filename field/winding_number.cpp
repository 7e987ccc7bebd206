#include "field/winding_number.h"

#include <cmath>

namespace rosy::field {

double windingNumber(const Mesh &mesh, const Vec3 &p) {
    double sum = 0;
    for (const Face &f : mesh.faces()) {
        const Vec3 a = mesh.position(f[0]) - p, b = mesh.position(f[1]) - p, c = mesh.position(f[2]) - p;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        const double num = a.dot(b.cross(c));
        const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        // atan2 keeps the half-angle's quadrant: the solid angle is 2 atan2(num, den).
        sum += 2 * std::atan2(num, den);
    }
    return sum / (4 * M_PI);
}

} // namespace rosy::field
