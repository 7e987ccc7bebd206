#pragma once
/// \file shading.h
/// Tone: how much light reaches each visible point (Lambert with cast shadows and
/// optional ambient occlusion), the input the hatching density follows
/// (illustration.h); the lights a scene and a field picture use.

#include "field/mesh.h"
#include "renderer/view/camera.h"
#include "renderer/view/embree_scene.h"
#include "renderer/view/gbuffer.h"
#include "renderer/output/image.h"
#include "styles/style.h"

#include <cstdint>
#include <vector>

namespace rosy::renderer {

/// A light for the preview. Neither kind falls off with distance, so an intensity
/// means the same at any scene scale.
struct Light {
    enum class Type { Directional, Point };
    Type type = Type::Directional;
    /// Directional: direction from the scene TOWARD the light (any length > 0).
    Vec3 direction = Vec3(0, 1, 0);
    /// Point: world position of the light.
    Vec3 position = Vec3::Zero();
    /// Scale of the light's Lambert term (>= 0); 1 lights a facing surface fully.
    double intensity = 1.0;
};

struct ShadingOptions {
    /// Tone floor in [0, 1] for surfaces no light reaches.
    double ambient = 0.15;
    /// Trace an occlusion ray toward each light (cast shadows).
    bool shadows = true;
    /// Ambient occlusion: cosine-weighted occlusion rays per pixel; 0 = off.
    int aoSamples = 0;
    /// Ambient occlusion: length of the occlusion rays in world units (> 0 when
    /// aoSamples > 0); geometry farther away does not occlude.
    double aoRadius = 0.0;
    /// Ambient occlusion: seed of the sample directions (the scene's seed).
    uint32_t aoSeed = 1;
};

/// Ambient occlusion per pixel (row-major like the G-buffer; 1 for background and
/// with aoSamples == 0): the cosine-weighted fraction of the hemisphere around the
/// shading normal (flipped toward the viewer like the tone's) from which no
/// geometry lies within options.aoRadius,
///   AO(p) = (1/π) ∫_{H(n)} V(p, ω, radius) (n · ω) dω,
/// estimated with options.aoSamples rays drawn from the cosine-weighted
/// distribution (Malley's method: uniform points on the unit disk lifted to the
/// hemisphere), stratified in the disk's radius. A direction below the face's own
/// plane counts as occluded (the surface itself blocks it). Random numbers come
/// from (aoSeed, pixel index, sample index) alone, so the result is identical for
/// any thread count. Rays go through RayScene::occludedMany.
std::vector<float> ambientOcclusion(const GBuffer &gbuffer, const RayScene &scene, const field::Mesh &mesh,
                                    const Camera &camera, const ShadingOptions &options);

/// Per-pixel tone in [0, 1] (1 = bright, row-major like the G-buffer):
/// tone = ambient * AO + (1 - ambient) * min(1, sum_i intensity_i * max(0, n . l_i) * visible_i),
/// AO = ambientOcclusion() when options.aoSamples > 0, else 1.
/// Background pixels get 1 (paper). Normals of surfaces seen from behind (open meshes)
/// are flipped toward the viewer. Parallel over rows, thread-count independent.
std::vector<double> shadeLambert(const GBuffer &gbuffer, const RayScene &scene,
                                 const field::Mesh &mesh, const Camera &camera,
                                 const std::vector<Light> &lights, const ShadingOptions &options);

/// RGB image (channels R, G, B; linear light) of a tone buffer in the style's colours.
Image toneImage(const std::vector<double> &tone, int width, int height, const styles::Style &style);

} // namespace rosy::renderer
