#include "renderer/view/shading.h"
#include "renderer/output/large_buffer.h"

#include "core/error.h"
#include "core/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace rosy::renderer {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// 64 well-mixed bits from (seed, pixel, sample): SplitMix64's finalizer over a
/// combination of the three, so every pixel's samples depend on nothing else.
uint64_t sampleBits(uint32_t seed, uint64_t pixel, uint32_t sample) {
    uint64_t z = (uint64_t(seed) << 32 | sample) ^ (pixel * 0xD1B54A32D192ED03ull);
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/// Unit vectors t, b with (t, b, n) right-handed and orthonormal, continuous in n
/// except across n.z = 0 where the sign branch flips (Duff et al. 2017).
void orthonormalBasis(const Vec3 &n, Vec3 &t, Vec3 &b) {
    const double sign = std::copysign(1.0, n.z());
    const double a = -1.0 / (sign + n.z());
    const double c = n.x() * n.y() * a;
    t = Vec3(1.0 + sign * n.x() * n.x() * a, sign * c, -sign * n.x());
    b = Vec3(c, sign + n.y() * n.y() * a, -n.y());
}

/// Shading normal and face normal of covered pixel i, both turned toward the viewer
/// (the back of an open surface is shaded like its front, as seen).
void viewerNormals(const GBuffer &g, const std::vector<Vec3> &faceNormals, const Camera &camera, size_t i,
                   const Vec3 &p, Vec3 &n, Vec3 &ng) {
    n = g.normal(i);
    ng = faceNormals[size_t(g.faceId[i])];
    if (ng.dot(camera.toViewer(p)) < 0.0) {
        n = -n;
        ng = -ng;
    }
}

/// Ray offset off the surface: Embree intersects in float, so a few float ulps of
/// the coordinates avoid self-intersection acne. Relative to the scene's size and
/// position, so the same at any scale.
double surfaceOffset(const RayScene &scene, const Vec3 &p) {
    return 1e-4 * (scene.sceneRadius() + p.cwiseAbs().maxCoeff());
}

} // namespace

std::vector<float> ambientOcclusion(const GBuffer &g, const RayScene &scene, const field::Mesh &mesh,
                                    const Camera &camera, const ShadingOptions &options) {
    std::vector<float> ao;
    assignLarge(ao, g.nPixels(), 1.0f);
    const std::vector<Vec3> &faceNormals = mesh.faceNormals();
    const int nSamples = options.aoSamples;
    if (nSamples <= 0) return ao;
    ROSY_CHECK(options.aoRadius > 0.0);
    parallelFor(
        0, g.height,
        [&](int64_t y) {
            std::vector<Ray> rays(static_cast<size_t>(nSamples));
            std::unique_ptr<bool[]> blocked(new bool[size_t(nSamples)]);
            for (int x = 0; x < g.width; ++x) {
                const size_t i = size_t(g.index(x, int(y)));
                if (g.faceId[i] < 0) continue;
                const Vec3 p = g.position(i);
                Vec3 n, ng, t, b;
                viewerNormals(g, faceNormals, camera, i, p, n, ng);
                orthonormalBasis(n, t, b);
                const Vec3 origin = p + surfaceOffset(scene, p) * ng;
                int count = 0; // rays traced; the rest point below the face and count as occluded
                for (int k = 0; k < nSamples; ++k) {
                    const uint64_t bits = sampleBits(options.aoSeed, i, uint32_t(k));
                    // Uniform on the unit disk, stratified in r²; lifted to the
                    // hemisphere that is the cosine-weighted distribution.
                    const double r2 = (k + double(bits >> 40) * 0x1p-24) / nSamples;
                    const double phi = 2.0 * kPi * double(bits & 0xFFFFFFu) * 0x1p-24;
                    const double r = std::sqrt(r2);
                    const Vec3 d = r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(1.0 - r2) * n;
                    if (!(d.dot(ng) > 0.0)) continue;
                    Ray &ray = rays[size_t(count++)];
                    ray.origin = origin;
                    ray.dir = d;
                    ray.tMin = 0.0;
                    ray.tMax = options.aoRadius;
                }
                scene.occludedMany(rays.data(), count, blocked.get());
                int open = 0;
                for (int k = 0; k < count; ++k) open += blocked[size_t(k)] ? 0 : 1;
                ao[i] = float(double(open) / nSamples);
            }
        },
        1);
    return ao;
}

std::vector<double> shadeLambert(const GBuffer &g, const RayScene &scene, const field::Mesh &mesh,
                                 const Camera &camera, const std::vector<Light> &lights,
                                 const ShadingOptions &options) {
    std::vector<double> tone;
    assignLarge(tone, g.nPixels(), 1.0);
    const std::vector<Vec3> &faceNormals = mesh.faceNormals();
    double ambient = std::clamp(options.ambient, 0.0, 1.0);
    std::vector<float> ao;
    if (options.aoSamples > 0) ao = ambientOcclusion(g, scene, mesh, camera, options);
    // Per row, in three passes so that each light's shadow rays, which are parallel
    // (directional) or converge on one point, go to Embree eight neighbours at a time:
    // every (pixel, light) term's factor n·l and whether it needs a shadow ray; the
    // rays; then each pixel's sum over its lights in the lights' order, as one loop
    // over the lights would add them.
    const size_t nLights = lights.size();
    parallelFor(
        0, g.height,
        [&](int64_t y) {
            // ndl[x * nLights + j]: light j's factor at pixel x, 0 where it adds nothing
            // (facing away, at the light); rayOf[...]: index of its shadow ray, or −1.
            std::vector<double> ndl(size_t(g.width) * nLights, 0.0);
            std::vector<int> rayOf(size_t(g.width) * nLights, -1);
            std::vector<Ray> rays;
            std::vector<uint8_t> blocked;
            // Each pixel's position and normals, once for all its lights.
            std::vector<std::array<Vec3, 3>> surface(size_t(g.width));
            for (int x = 0; x < g.width; ++x) {
                const size_t i = size_t(g.index(x, int(y)));
                if (g.faceId[i] < 0) continue;
                std::array<Vec3, 3> &pnn = surface[size_t(x)];
                pnn[0] = g.position(i);
                viewerNormals(g, faceNormals, camera, i, pnn[0], pnn[1], pnn[2]);
            }
            for (size_t j = 0; j < nLights; ++j) {
                const Light &L = lights[j];
                const size_t first = rays.size();
                for (int x = 0; x < g.width; ++x) {
                    const size_t i = size_t(g.index(x, int(y)));
                    if (g.faceId[i] < 0) continue;
                    const auto &[p, n, ng] = surface[size_t(x)];
                    Vec3 l;
                    double tMax = std::numeric_limits<double>::infinity();
                    if (L.type == Light::Type::Directional) {
                        l = L.direction.normalized();
                    } else {
                        l = L.position - p;
                        double d = l.norm();
                        if (!(d > 0.0)) continue;
                        l /= d;
                        tMax = d;
                    }
                    const double c = n.dot(l);
                    if (!(c > 0.0)) continue;
                    const size_t term = size_t(x) * nLights + j;
                    ndl[term] = c;
                    // Where the interpolated normal sees the light but the flat face does
                    // not (near the terminator), a shadow ray would hit the neighbouring
                    // faces; treat those points as lit so the terminator stays smooth.
                    if (options.shadows && ng.dot(l) > 0.0) {
                        Ray shadow;
                        shadow.origin = p + surfaceOffset(scene, p) * ng;
                        shadow.dir = l;
                        shadow.tMin = 0.0;
                        shadow.tMax = tMax;
                        rayOf[term] = int(rays.size());
                        rays.push_back(shadow);
                    }
                }
                blocked.resize(rays.size());
                for (size_t k = first; k < rays.size(); k += 8) {
                    bool out[8];
                    const int m = int(std::min<size_t>(8, rays.size() - k));
                    scene.occluded8(rays.data() + k, m, out);
                    for (int q = 0; q < m; ++q) blocked[k + size_t(q)] = out[q] ? 1 : 0;
                }
            }
            for (int x = 0; x < g.width; ++x) {
                const size_t i = size_t(g.index(x, int(y)));
                if (g.faceId[i] < 0) continue;
                double light = 0.0;
                for (size_t j = 0; j < nLights; ++j) {
                    const size_t term = size_t(x) * nLights + j;
                    if (!(ndl[term] > 0.0)) continue;
                    if (rayOf[term] >= 0 && blocked[size_t(rayOf[term])]) continue;
                    light += lights[j].intensity * ndl[term];
                }
                const double occlusion = ao.empty() ? 1.0 : double(ao[i]);
                tone[i] = ambient * occlusion + (1.0 - ambient) * std::clamp(light, 0.0, 1.0);
            }
        },
        1);
    return tone;
}

Image toneImage(const std::vector<double> &tone, int width, int height, const styles::Style &style) {
    Image img(width, height, {"R", "G", "B"});
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            styles::Rgb c = styles::toneToColor(style, tone[size_t(y) * size_t(width) + size_t(x)]);
            for (int k = 0; k < 3; ++k) img.at(x, y, k) = float(c[size_t(k)]);
        }
    return img;
}

} // namespace rosy::renderer
