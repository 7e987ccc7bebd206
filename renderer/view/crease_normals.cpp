#include "renderer/view/crease_normals.h"

#include "core/parallel.h"

#include <cmath>

namespace rosy::renderer {

std::vector<Vec3> creaseAwareCornerNormals(const field::Mesh &mesh, double creaseAngleRad,
                                           std::vector<Vec3> *vertexNormals) {
    const std::vector<Vec3> &faceNormal = mesh.faceNormals();
    const std::vector<double> &cornerAngle = mesh.cornerAngles();
    // Every halfedge leaves exactly one vertex, so the loop below writes every entry
    // (Eigen's default constructor leaves them unset: no pass to zero them first).
    std::vector<Vec3> out(static_cast<size_t>(mesh.nHalfedges()));
    if (vertexNormals) vertexNormals->resize(size_t(mesh.nVertices()));
    const double cosCrease = std::cos(creaseAngleRad);
    // Per vertex, once around its fan: the creases (and the boundary) cut the fan into
    // sectors of consecutive faces, and every corner of a sector gets that sector's
    // angle-weighted sum. Walking the fan both ways from each face, stopping at a
    // crease, reaches exactly the face's sector, so this is the same sum in one pass.
    parallelFor(0, mesh.nVertices(), [&](int64_t v64) {
        const int v = int(v64);
        const int *ring = mesh.outgoingBegin(v);
        const int d = mesh.degree(v);
        if (d == 0) return; // not in a Mesh (fromTriangles rejects isolated vertices)
        // Each corner's face normal and weighted normal once, summed in ring order for
        // the whole fan (the operations of Mesh::vertexNormal, so the same bits).
        Vec3 localN[16], localW[16];
        std::vector<Vec3> heap;
        Vec3 *nf = localN, *w = localW;
        if (d > 16) {
            heap.resize(2 * size_t(d));
            nf = heap.data();
            w = nf + d;
        }
        Vec3 total = Vec3::Zero();
        for (int i = 0; i < d; ++i) {
            nf[i] = faceNormal[size_t(field::Mesh::faceOf(ring[i]))];
            w[i] = cornerAngle[size_t(ring[i])] * nf[i];
            total += w[i];
        }
        if (vertexNormals) {
            const double len = total.norm();
            (*vertexNormals)[size_t(v)] = len > 0 ? Vec3(total / len) : Vec3::Zero();
        }
        // The ring is counter-clockwise, each face the neighbour of the one before
        // across their shared edge (Mesh::outgoingBegin); a boundary vertex's ring
        // starts and ends at the boundary. cut(i): no smooth step from face i to i + 1.
        const bool open = mesh.isBoundaryVertex(v);
        auto cut = [&](int i) {
            if (i == d - 1 && open) return true;
            const Vec3 &a = nf[i], &b = nf[(i + 1) % d];
            if (a.squaredNorm() == 0 || b.squaredNorm() == 0) return false;
            return a.dot(b) < cosCrease;
        };
        // Start just after a cut, so that no sector wraps around; a fan without any
        // is one sector.
        int start = 0;
        for (int i = 0; i < d; ++i)
            if (cut((i + d - 1) % d)) {
                start = i;
                break;
            }
        Vec3 sum = Vec3::Zero();
        int first = start;
        for (int k = 0; k < d; ++k) {
            const int i = (start + k) % d;
            sum += w[i];
            if (k + 1 == d || cut(i)) {
                const double len = sum.norm();
                for (int j = first;; j = (j + 1) % d) {
                    const int hj = ring[j];
                    // A zero-area face and a zero sum: the face's own (zero) normal.
                    out[size_t(hj)] = len > 0 ? Vec3(sum / len) : nf[j];
                    if (j == i) break;
                }
                sum = Vec3::Zero();
                first = (i + 1) % d;
            }
        }
    }, 256);
    return out;
}

} // namespace rosy::renderer
