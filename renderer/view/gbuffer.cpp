#include "renderer/view/gbuffer.h"

#include "core/error.h"
#include "core/parallel.h"
#include "renderer/output/large_buffer.h"

#include <cmath>

namespace rosy::renderer {

Vec3 GBuffer::position(size_t i) const {
    const field::Face &f = mesh->face(faceId[i]);
    const double u = barycentric[i].x(), v = barycentric[i].y();
    return (1.0 - u - v) * mesh->position(f[0]) + u * mesh->position(f[1]) + v * mesh->position(f[2]);
}

Vec3 GBuffer::normal(size_t i) const {
    const int face = faceId[i];
    const field::Face &f = mesh->face(face);
    const std::vector<Vec3> &vn = *vertexNormals;
    const double u = barycentric[i].x(), v = barycentric[i].y();
    const Vec3 nrm = (1.0 - u - v) * vn[size_t(f[0])] + u * vn[size_t(f[1])] + v * vn[size_t(f[2])];
    const double len = nrm.norm();
    // Opposite vertex normals can cancel on very sharp creases.
    return len > 1e-12 ? Vec3(nrm / len) : mesh->faceNormal(face);
}

Vec3 GBuffer::creaseNormal(size_t i) const {
    const int face = faceId[i];
    const Vec3 *c = cornerNormals->data() + 3 * size_t(face);
    const double u = barycentric[i].x(), v = barycentric[i].y();
    const Vec3 nrm = (1.0 - u - v) * c[0] + u * c[1] + v * c[2];
    const double len = nrm.norm();
    return len > 1e-12 ? Vec3(nrm / len) : mesh->faceNormal(face);
}

GBuffer renderGBuffer(const RayScene &scene, const field::Mesh &mesh, const Camera &camera) {
    GBuffer g;
    g.width = camera.width();
    g.height = camera.height();
    g.mesh = &mesh;
    const size_t n = g.nPixels();
    // Huge pages where the planes span them (large_buffer.h); every pixel is
    // written again in the parallel loop below, misses too.
    assignLarge(g.faceId, n, -1);
    assignLarge(g.barycentric, n, Eigen::Vector2f(Eigen::Vector2f::Zero()));
    assignLarge(g.depth, n, 0.0f);

    // Vertex normals and crease-aware corner normals once, in one pass over the
    // vertices' fans, not three times per pixel.
    auto normals = std::make_shared<std::vector<Vec3>>();
    g.cornerNormals = std::make_shared<const std::vector<Vec3>>(
        creaseAwareCornerNormals(mesh, kCreaseAngleDeg * M_PI / 180.0, normals.get()));
    g.vertexNormals = std::move(normals);

    const Vec3 eye = camera.position(), forward = camera.forward();
    parallelFor(
        0, g.height,
        [&](int64_t y) {
            // Packets of 8 neighbouring rays: coherent primary rays share most of
            // their traversal, which Embree's packet kernels exploit.
            Ray rays[8];
            Hit hits[8];
            for (int x0 = 0; x0 < g.width; x0 += 8) {
                const int count = std::min(8, g.width - x0);
                for (int k = 0; k < count; ++k) rays[k] = camera.generateRay(x0 + k + 0.5, double(y) + 0.5);
                scene.intersect8(rays, count, hits);
                for (int k = 0; k < count; ++k) {
                    const Hit &hit = hits[k];
                    const size_t i = size_t(g.index(x0 + k, int(y)));
                    if (!hit.valid()) {
                        g.faceId[i] = -1;
                        g.barycentric[i] = Eigen::Vector2f::Zero();
                        g.depth[i] = 0.0f;
                        continue;
                    }
                    ROSY_CHECK_LT(hit.faceId, mesh.nFaces());
                    g.faceId[i] = hit.faceId;
                    g.barycentric[i] = Eigen::Vector2f(float(hit.u), float(hit.v));
                    g.depth[i] = float((g.position(i) - eye).dot(forward));
                }
            }
        },
        1);
    return g;
}

} // namespace rosy::renderer
