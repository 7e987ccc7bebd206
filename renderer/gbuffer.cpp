#include "renderer/gbuffer.h"

#include "core/error.h"
#include "core/parallel.h"

namespace rosy::renderer {

GBuffer renderGBuffer(const RayScene &scene, const field::Mesh &mesh, const Camera &camera) {
    GBuffer g;
    g.width = camera.width();
    g.height = camera.height();
    size_t n = g.nPixels();
    // Sized but not filled here: every pixel is written once in the parallel loop
    // below (misses too), so the first touch of these ~76 MB at 1024² is spread
    // over the threads instead of a serial fill.
    g.faceId.resize(n);
    g.barycentric.resize(n);
    g.position.resize(n);
    g.normal.resize(n);
    g.depth.resize(n);

    // Vertex normals once, not three times per pixel.
    std::vector<Vec3> vertexNormals(size_t(mesh.nVertices()));
    parallelFor(0, mesh.nVertices(), [&](int64_t v) { vertexNormals[size_t(v)] = mesh.vertexNormal(int(v)); });

    parallelFor(
        0, g.height,
        [&](int64_t y) {
            for (int x = 0; x < g.width; ++x) {
                Ray ray = camera.generateRay(x + 0.5, double(y) + 0.5);
                Hit hit = scene.intersect(ray);
                size_t i = size_t(g.index(x, int(y)));
                if (!hit.valid()) {
                    g.faceId[i] = -1;
                    g.barycentric[i] = Vec2::Zero();
                    g.position[i] = Vec3::Zero();
                    g.normal[i] = Vec3::Zero();
                    g.depth[i] = 0.0;
                    continue;
                }
                ROSY_CHECK_LT(hit.faceId, mesh.nFaces());
                const field::Face &f = mesh.face(hit.faceId);
                double w0 = 1.0 - hit.u - hit.v;
                g.faceId[i] = hit.faceId;
                g.barycentric[i] = Vec2(hit.u, hit.v);
                g.position[i] = w0 * mesh.position(f[0]) + hit.u * mesh.position(f[1]) +
                                hit.v * mesh.position(f[2]);
                Vec3 nrm = w0 * vertexNormals[size_t(f[0])] + hit.u * vertexNormals[size_t(f[1])] +
                           hit.v * vertexNormals[size_t(f[2])];
                double len = nrm.norm();
                // Opposite vertex normals can cancel on very sharp creases.
                g.normal[i] = len > 1e-12 ? Vec3(nrm / len) : mesh.faceNormal(hit.faceId);
                g.depth[i] = camera.depth(g.position[i]);
            }
        },
        1);
    return g;
}

} // namespace rosy::renderer
