#include "field/singularities.h"

#include "core/parallel.h"

#include <cmath>

namespace rosy::field {
namespace {

// Angle change of the representation vector from tail(h) to head(h), with the
// head's value transported into the tail's frame, wrapped to (−π, π].
double edgeChange(const TangentFrames &frames, const RosyField &field, int h) {
    const Mesh &mesh = frames.mesh();
    const Complex ui = field.u[mesh.tail(h)], uj = field.u[mesh.head(h)];
    return wrapAngle(std::arg(uj) + field.nSym * frames.transportAngle(h) - std::arg(ui));
}

Vec3 zeroBarycentric(const std::array<Complex, 3> &w) {
    const Complex a = w[0] - w[2], b = w[1] - w[2];
    const double det = a.real() * b.imag() - b.real() * a.imag();
    const double scale = std::abs(w[0]) + std::abs(w[1]) + std::abs(w[2]);
    if (!(std::abs(det) > 1e-14 * scale * scale)) return Vec3::Constant(1.0 / 3.0);
    // Cramer's rule on b0 a + b1 b = −w2.
    const double b0 = (-w[2].real() * b.imag() + b.real() * w[2].imag()) / det;
    const double b1 = (-a.real() * w[2].imag() + w[2].real() * a.imag()) / det;
    Vec3 bc(b0, b1, 1.0 - b0 - b1);
    bc = bc.cwiseMax(0.0);
    const double s = bc.sum();
    return s > 0 ? Vec3(bc / s) : Vec3::Constant(1.0 / 3.0);
}

} // namespace

std::vector<int> faceIndexNumerators(const TangentFrames &frames, const RosyField &field) {
    const Mesh &mesh = frames.mesh();
    std::vector<double> change(mesh.nEdges());
    parallelFor(0, mesh.nEdges(), [&](int64_t e) {
        change[e] = edgeChange(frames, field, mesh.edgeHalfedge(int(e)));
    }, 4096);
    std::vector<int> k(mesh.nFaces());
    parallelFor(0, mesh.nFaces(), [&](int64_t fi) {
        const int f = int(fi);
        double total = field.nSym * frames.faceHolonomy(f);
        for (int c = 0; c < 3; ++c) {
            const int h = 3 * f + c;
            const int e = mesh.edgeOf(h);
            total += mesh.edgeHalfedge(e) == h ? change[e] : -change[e];
        }
        k[f] = int(std::lround(total / (2.0 * M_PI)));
    }, 4096);
    return k;
}

SingularityReport findSingularities(const TangentFrames &frames, const RosyField &field) {
    const Mesh &mesh = frames.mesh();
    SingularityReport report;
    const std::vector<int> k = faceIndexNumerators(frames, field);
    for (int f = 0; f < mesh.nFaces(); ++f) {
        report.indexNumeratorSum += k[f];
        if (k[f] == 0) continue;
        Singularity s;
        s.face = f;
        s.indexNumerator = k[f];
        s.nSym = field.nSym;
        s.barycentric = zeroBarycentric(frames.faceValues(f, field));
        const Face &t = mesh.face(f);
        s.position = s.barycentric[0] * mesh.position(t[0]) + s.barycentric[1] * mesh.position(t[1]) +
                     s.barycentric[2] * mesh.position(t[2]);
        report.singularities.push_back(s);
    }
    double boundaryChange = 0, turning = 0;
    for (int e = 0; e < mesh.nEdges(); ++e) {
        const int h = mesh.edgeHalfedge(e);
        if (!mesh.isBoundaryHalfedge(h)) continue;
        boundaryChange += edgeChange(frames, field, h);
        turning += M_PI - frames.angleTotal(mesh.tail(h)); // each boundary vertex once
    }
    report.boundaryIndex = turning / (2.0 * M_PI) - boundaryChange / (2.0 * M_PI * field.nSym);
    return report;
}

} // namespace rosy::field
