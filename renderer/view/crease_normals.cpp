#include "renderer/view/crease_normals.h"

#include "core/parallel.h"

#include <cmath>

namespace rosy::renderer {

std::vector<Vec3> creaseAwareCornerNormals(const field::Mesh &mesh, double creaseAngleRad) {
    const int nF = mesh.nFaces();
    std::vector<Vec3> faceNormal(static_cast<size_t>(nF));
    std::vector<Vec3> out(static_cast<size_t>(mesh.nHalfedges()), Vec3::Zero());
    std::vector<double> angle(static_cast<size_t>(mesh.nHalfedges()));
    parallelFor(0, nF, [&](int64_t f) {
        faceNormal[size_t(f)] = mesh.faceNormal(int(f));
        for (int k = 0; k < 3; ++k) angle[size_t(3 * f + k)] = mesh.cornerAngle(int(3 * f + k));
    }, 1024);
    const double cosCrease = std::cos(creaseAngleRad);
    // An edge between faces a and b is smooth unless both have a normal and those
    // differ by more than the crease angle.
    auto smooth = [&](int a, int b) {
        const Vec3 &na = faceNormal[size_t(a)], &nb = faceNormal[size_t(b)];
        if (na.squaredNorm() == 0 || nb.squaredNorm() == 0) return true;
        return na.dot(nb) >= cosCrease;
    };

    parallelFor(0, nF, [&](int64_t f64) {
        const int f = int(f64);
        for (int k = 0; k < 3; ++k) {
            const int h0 = 3 * f + k; // leaves the corner's vertex v inside face f
            const int steps = mesh.degree(mesh.tail(h0));
            Vec3 sum = angle[size_t(h0)] * faceNormal[size_t(f)];
            // Counter-clockwise: across the edge of the halfedge entering v.
            int h = h0, n = 0;
            bool closed = false;
            for (; n < steps; ++n) {
                const int t = mesh.twin(field::Mesh::prev(h));
                if (t < 0 || !smooth(field::Mesh::faceOf(h), field::Mesh::faceOf(t))) break;
                if (t == h0) {
                    closed = true; // back at f: the whole fan is smooth
                    break;
                }
                h = t;
                sum += angle[size_t(h)] * faceNormal[size_t(field::Mesh::faceOf(h))];
            }
            // Clockwise: across the edge of the halfedge leaving v, up to the crease
            // (or boundary) on the other side; the faces walked above are beyond it.
            h = h0;
            for (int m = n; !closed && m < steps; ++m) {
                const int t = mesh.twin(h);
                if (t < 0 || !smooth(field::Mesh::faceOf(h), field::Mesh::faceOf(t))) break;
                h = field::Mesh::next(t);
                if (h == h0) break;
                sum += angle[size_t(h)] * faceNormal[size_t(field::Mesh::faceOf(h))];
            }
            const double len = sum.norm();
            out[size_t(h0)] = len > 0 ? Vec3(sum / len) : faceNormal[size_t(f)];
        }
    }, 256);
    return out;
}

} // namespace rosy::renderer
