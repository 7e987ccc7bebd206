/// \file field_picture.cpp
/// Field pictures (Palacios & Zhang 2007, Figures 3–6): a light Lambert background,
/// dense surface streamlines, separatrices and singularity dots, composited in a
/// small coloured compositor of our own (the stroke rasterizer only makes ink
/// coverage, and these pictures need several colours).

#include "renderer/field_picture.h"

#include "core/parallel.h"
#include "field/streamlines.h"
#include "renderer/view/embree_scene.h"
#include "renderer/view/gbuffer.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace rosy::renderer {
namespace {

/// Per-pixel coverage in [0, 1] of one colour group. Shapes are merged by max, so
/// the result does not depend on the order they are drawn in.
struct Coverage {
    int width = 0, height = 0;
    std::vector<float> c;
    Coverage(int w, int h) : width(w), height(h), c(size_t(w) * size_t(h), 0.0f) {}

    /// Anti-aliased round-capped segment a–b (raster units) of half width r: a pixel
    /// centre at distance d gets clamp(r + 0.5 − d, 0, 1), a one-pixel ramp.
    void segment(const Vec2 &a, const Vec2 &b, double r) {
        const int x0 = std::max(0, int(std::floor(std::min(a.x(), b.x()) - r - 1)));
        const int x1 = std::min(width - 1, int(std::ceil(std::max(a.x(), b.x()) + r + 1)));
        const int y0 = std::max(0, int(std::floor(std::min(a.y(), b.y()) - r - 1)));
        const int y1 = std::min(height - 1, int(std::ceil(std::max(a.y(), b.y()) + r + 1)));
        const Vec2 ab = b - a;
        const double len2 = ab.squaredNorm();
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const Vec2 p(x + 0.5, y + 0.5);
                const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
                const double d = (p - (a + t * ab)).norm();
                const float v = float(std::clamp(r + 0.5 - d, 0.0, 1.0));
                float &dst = c[size_t(y) * size_t(width) + size_t(x)];
                dst = std::max(dst, v);
            }
    }
    /// Filled disk of radius r around centre (a zero-length segment).
    void disk(const Vec2 &centre, double r) { segment(centre, centre, r); }
};

/// Over-composites a coverage layer of one colour (times `opacity`) onto rgb.
void composite(std::vector<float> &rgb, const Coverage &layer, const Rgb &colour, float opacity) {
    for (size_t i = 0; i < layer.c.size(); ++i) {
        const float a = layer.c[i] * opacity;
        if (a <= 0) continue;
        for (int k = 0; k < 3; ++k) rgb[3 * i + size_t(k)] = rgb[3 * i + size_t(k)] * (1 - a) + colour[size_t(k)] * a;
    }
}

/// Decides whether world points are seen by the camera, against the G-buffer.
class Visibility {
public:
    Visibility(const GBuffer &gbuffer, const Camera &camera, double diagonal)
        : m_gbuffer(gbuffer), m_camera(camera), m_diagonal(diagonal) {
        const double scale = camera.projection() == Projection::Perspective
                                 ? 2.0 * std::tan(0.5 * camera.fovYDeg() * M_PI / 180.0) / camera.height()
                                 : camera.viewHeight() / camera.height();
        m_footprintPerDepth = camera.projection() == Projection::Perspective ? scale : 0.0;
        m_footprintConst = camera.projection() == Projection::Perspective ? 0.0 : scale;
    }

    /// True if p lies in front of the camera and on (not behind) the visible surface.
    /// The 3x3 pixel neighbourhood is searched because a point's own pixel centre
    /// may miss a silhouette or hit a steep neighbouring facet; the tolerance grows
    /// with the pixel footprint so grazing surfaces keep their lines.
    bool visible(const Vec3 &p, double slack = 1.0) const {
        const double d = m_camera.depth(p);
        if (!(d > 0)) return false;
        const Vec2 r = m_camera.project(p);
        if (!r.allFinite()) return false;
        const int px = int(std::floor(r.x())), py = int(std::floor(r.y()));
        if (px < -1 || py < -1 || px > m_gbuffer.width || py > m_gbuffer.height) return false;
        const double footprint = m_footprintConst + m_footprintPerDepth * d;
        const double tol = slack * (0.004 * m_diagonal + 3.0 * footprint);
        for (int y = py - 1; y <= py + 1; ++y)
            for (int x = px - 1; x <= px + 1; ++x) {
                if (x < 0 || y < 0 || x >= m_gbuffer.width || y >= m_gbuffer.height) continue;
                const size_t i = size_t(m_gbuffer.index(x, y));
                if (m_gbuffer.faceId[i] >= 0 && d <= m_gbuffer.depth[i] + tol) return true;
            }
        return false;
    }

private:
    const GBuffer &m_gbuffer;
    const Camera &m_camera;
    double m_diagonal;
    double m_footprintPerDepth = 0, m_footprintConst = 0;
};

/// Draws the visible parts of a world polyline: each segment is cut into pieces of
/// at most ~1.5 px on screen and each piece kept or dropped by the visibility of its
/// midpoint.
void drawPolyline(Coverage &layer, const std::vector<field::Vec3> &points, const Camera &camera,
                  const Visibility &vis, double halfWidthPx) {
    for (size_t i = 0; i + 1 < points.size(); ++i) {
        const Vec3 &p0 = points[i], &p1 = points[i + 1];
        if (!(camera.depth(p0) > 0) || !(camera.depth(p1) > 0)) continue;
        const Vec2 r0 = camera.project(p0), r1 = camera.project(p1);
        if (!r0.allFinite() || !r1.allFinite()) continue;
        const int n = std::clamp(int(std::ceil((r1 - r0).norm() / 1.5)), 1, 4096);
        for (int k = 0; k < n; ++k) {
            const double t0 = double(k) / n, t1 = double(k + 1) / n;
            if (!vis.visible(p0 + (0.5 * (t0 + t1)) * (p1 - p0))) continue;
            layer.segment(r0 + t0 * (r1 - r0), r0 + t1 * (r1 - r0), halfWidthPx);
        }
    }
}

/// One seed face per cell of a 3D grid (cell size `spacing`), the lowest visible
/// face id whose centroid falls in the cell: evenly spread seeds in a fixed order,
/// independent of threads and of the mesh's triangle sizes.
std::vector<int> gridSeeds(const field::Mesh &mesh, const std::vector<char> &faceVisible, const Vec3 &lo,
                           double spacing) {
    std::map<std::tuple<long, long, long>, int> cells;
    for (int f = 0; f < mesh.nFaces(); ++f) {
        if (!faceVisible[size_t(f)]) continue;
        const field::Face &t = mesh.face(f);
        const Vec3 c = (mesh.position(t[0]) + mesh.position(t[1]) + mesh.position(t[2])) / 3.0;
        const Vec3 g = (c - lo) / spacing;
        cells.emplace(std::make_tuple(long(std::floor(g.x())), long(std::floor(g.y())), long(std::floor(g.z()))), f);
    }
    std::vector<int> seeds;
    seeds.reserve(cells.size());
    for (const auto &[key, f] : cells) seeds.push_back(f);
    std::sort(seeds.begin(), seeds.end());
    return seeds;
}

} // namespace

Image renderFieldPicture(const field::Mesh &mesh, const field::TangentFrames &frames,
                         const field::RosyField &field, const field::SingularityReport &report,
                         const std::vector<field::Separatrix> &separatrices, const Camera &camera,
                         const FieldPictureOptions &options) {
    const int width = camera.width(), height = camera.height();
    Image image(width, height, {"R", "G", "B"});
    std::fill(image.data.begin(), image.data.end(), 1.0f);
    if (mesh.nFaces() == 0) return image;

    Vec3 lo = mesh.position(0), hi = lo;
    for (int v = 0; v < mesh.nVertices(); ++v) {
        lo = lo.cwiseMin(mesh.position(v));
        hi = hi.cwiseMax(mesh.position(v));
    }
    const double diagonal = std::max((hi - lo).norm(), 1e-12);

    const RayScene scene(mesh);
    const GBuffer gbuffer = renderGBuffer(scene, mesh, camera);
    std::vector<Light> lights = options.lights;
    if (lights.empty()) {
        // A headlight a little above and left of the eye: every visible part is lit
        // and the form still reads.
        Light head;
        head.direction = -camera.forward() + 0.35 * camera.up() - 0.25 * camera.right();
        lights.push_back(head);
    }
    ShadingOptions shading;
    shading.shadows = false;
    shading.ambient = 0.2;
    const std::vector<double> tone = shadeLambert(gbuffer, scene, mesh, camera, lights, shading);

    // Light grey mesh: the lines carry the information, the tone only the form.
    std::vector<float> rgb(size_t(width) * size_t(height) * 3, 1.0f);
    for (size_t i = 0; i < gbuffer.nPixels(); ++i) {
        if (gbuffer.faceId[i] < 0) continue;
        const float g = float(0.3 + 0.6 * tone[i]);
        rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = g;
    }

    const double sizeScale = std::min(width, height) / 1024.0;
    const Visibility vis(gbuffer, camera, diagonal);

    Coverage streamLayer(width, height);
    if (options.streamlines && field.nSym >= 1 && field.u.size() == mesh.nVertices()) {
        std::vector<char> faceVisible(size_t(mesh.nFaces()), 0);
        for (int f : gbuffer.faceId)
            if (f >= 0) faceVisible[size_t(f)] = 1;
        const double spacing = std::max(options.seedSpacingRelative, 1e-4) * diagonal;
        const std::vector<int> seeds = gridSeeds(mesh, faceVisible, lo, spacing);
        const std::vector<int> faceIndex = field::faceIndexNumerators(frames, field);
        // Members that give distinct lines: for even N, member k and k + N/2 trace the
        // same unoriented line.
        const int nMembers = field.nSym % 2 == 0 ? field.nSym / 2 : field.nSym;
        field::StreamlineOptions so;
        so.maxLength = std::max(options.streamlineLengthRelative, 1e-4) * diagonal;
        so.bothDirections = true;
        so.maxSteps = 2000;
        // Long steps (edge crossings still cut them): these short lines only need to
        // look right, and the tracer's default half-edge step dominates the cost.
        so.stepLength = std::max(mesh.meanEdgeLength(), 0.125 * so.maxLength);
        std::vector<std::vector<field::Vec3>> lines(seeds.size() * size_t(nMembers));
        parallelFor(0, int64_t(seeds.size()), [&](int64_t s) {
            const int f = seeds[size_t(s)];
            if (faceIndex[size_t(f)] != 0) return;
            const auto values = frames.faceValues(f, field);
            const field::Complex u = (values[0] + values[1] + values[2]) / 3.0;
            if (std::abs(u) == 0) return;
            const double base = field::memberAngle(u, field.nSym);
            for (int k = 0; k < nMembers; ++k) {
                const Vec3 dir = frames.faceDirection(f, base + 2.0 * M_PI * k / field.nSym);
                field::Streamline line = field::traceStreamline(frames, field, f, Vec3::Constant(1.0 / 3.0), dir, so,
                                                                &faceIndex);
                lines[size_t(s) * size_t(nMembers) + size_t(k)] = std::move(line.points);
            }
        }, 16);
        // Below ~0.8 px a line fades into the shading at small resolutions.
        const double half = std::max(0.5 * options.streamlineWidthPx * sizeScale, 0.4);
        for (const auto &pts : lines) drawPolyline(streamLayer, pts, camera, vis, half);
    }

    Coverage outgoing(width, height), incoming(width, height);
    for (const field::Separatrix &s : separatrices)
        drawPolyline(s.incoming ? incoming : outgoing, s.line.points, camera, vis,
                     0.5 * options.separatrixWidthPx * sizeScale);

    // Dots: a black rim under four colour groups (sign × first/higher order).
    Coverage rim(width, height);
    std::array<Coverage, 4> dots{Coverage(width, height), Coverage(width, height), Coverage(width, height),
                                 Coverage(width, height)};
    for (const field::Singularity &s : report.singularities) {
        if (s.indexNumerator == 0 || !vis.visible(s.position, 1.5)) continue;
        const bool higher = std::abs(s.indexNumerator) > 1;
        const double r = options.dotRadiusPx * sizeScale * (higher ? 1.4 : 1.0);
        const Vec2 c = camera.project(s.position);
        rim.disk(c, r + std::max(1.0, 1.2 * sizeScale));
        dots[size_t((s.indexNumerator > 0 ? 0 : 1) + (higher ? 2 : 0))].disk(c, r);
    }

    auto darker = [](const Rgb &c) { return Rgb{0.45f * c[0], 0.45f * c[1], 0.45f * c[2]}; };
    composite(rgb, streamLayer, options.streamlineColor, 0.9f);
    composite(rgb, outgoing, options.outgoingColor, 1.0f);
    composite(rgb, incoming, options.incomingColor, 1.0f);
    composite(rgb, rim, Rgb{0, 0, 0}, 1.0f);
    composite(rgb, dots[0], options.positiveColor, 1.0f);
    composite(rgb, dots[1], options.negativeColor, 1.0f);
    composite(rgb, dots[2], darker(options.positiveColor), 1.0f);
    composite(rgb, dots[3], darker(options.negativeColor), 1.0f);
    image.data = std::move(rgb);
    return image;
}

} // namespace rosy::renderer
