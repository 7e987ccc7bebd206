#include "renderer/shading.h"

#include "core/parallel.h"

#include <algorithm>
#include <cmath>

namespace rosy::renderer {

std::vector<double> shadeLambert(const GBuffer &g, const RayScene &scene, const field::Mesh &mesh,
                                 const Camera &camera, const std::vector<Light> &lights,
                                 const ShadingOptions &options) {
    std::vector<double> tone(g.nPixels(), 1.0);
    double ambient = std::clamp(options.ambient, 0.0, 1.0);
    parallelFor(
        0, g.height,
        [&](int64_t y) {
            for (int x = 0; x < g.width; ++x) {
                size_t i = size_t(g.index(x, int(y)));
                int f = g.faceId[i];
                if (f < 0) continue;
                const Vec3 p = g.position(i);
                Vec3 n = g.normal(i);
                Vec3 ng = mesh.faceNormal(f);
                // The back of an open surface is lit like its front, as seen.
                if (ng.dot(camera.toViewer(p)) < 0.0) {
                    n = -n;
                    ng = -ng;
                }
                // Embree intersects in float: push shadow rays off the surface by a few
                // float ulps of the coordinates to avoid self-shadowing acne.
                double eps = 1e-4 * (scene.sceneRadius() + p.cwiseAbs().maxCoeff());
                double light = 0.0;
                for (const Light &L : lights) {
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
                    double ndl = n.dot(l);
                    if (!(ndl > 0.0)) continue;
                    // Where the interpolated normal sees the light but the flat face does
                    // not (near the terminator), a shadow ray would hit the neighbouring
                    // faces; treat those points as lit so the terminator stays smooth.
                    if (options.shadows && ng.dot(l) > 0.0) {
                        Ray shadow;
                        shadow.origin = p + eps * ng;
                        shadow.dir = l;
                        shadow.tMin = 0.0;
                        shadow.tMax = tMax;
                        if (scene.occluded(shadow)) continue;
                    }
                    light += L.intensity * ndl;
                }
                tone[i] = ambient + (1.0 - ambient) * std::clamp(light, 0.0, 1.0);
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
