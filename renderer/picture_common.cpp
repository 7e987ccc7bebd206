/// \file picture_common.cpp
/// The shaded fill, visibility test, visible polylines and dots of the diagnostic
/// pictures (picture_common.h).

#include "renderer/picture_common.h"

#include "core/error.h"
#include "renderer/view/embree_scene.h"

#include <algorithm>
#include <cmath>

namespace rosy::renderer {

Visibility::Visibility(const GBuffer &gbuffer, const Camera &camera, double diagonal)
    : m_gbuffer(gbuffer), m_camera(camera), m_diagonal(diagonal) {
    const double scale = camera.projection() == Projection::Perspective
                             ? 2.0 * std::tan(0.5 * camera.fovYDeg() * M_PI / 180.0) / camera.height()
                             : camera.viewHeight() / camera.height();
    m_footprintPerDepth = camera.projection() == Projection::Perspective ? scale : 0.0;
    m_footprintConst = camera.projection() == Projection::Perspective ? 0.0 : scale;
}

bool Visibility::visible(const Vec3 &p, double slack) const { return visible(p, Vec3::Zero(), slack); }

bool Visibility::visible(const Vec3 &p, const Vec3 &normal, double slack) const {
    const double d = m_camera.depth(p);
    if (!(d > 0)) return false;
    const Vec2 r = m_camera.project(p);
    if (!r.allFinite()) return false;
    const int px = int(std::floor(r.x())), py = int(std::floor(r.y()));
    if (px < -1 || py < -1 || px > m_gbuffer.width || py > m_gbuffer.height) return false;
    const double footprint = m_footprintConst + m_footprintPerDepth * d;
    const double tol = slack * (0.004 * m_diagonal + 3.0 * footprint);
    const bool anyFacing = normal.isZero(0.0); // the overload without a normal
    for (int y = py - 1; y <= py + 1; ++y)
        for (int x = px - 1; x <= px + 1; ++x) {
            if (x < 0 || y < 0 || x >= m_gbuffer.width || y >= m_gbuffer.height) continue;
            const size_t i = size_t(m_gbuffer.index(x, y));
            const int face = m_gbuffer.faceId[i];
            if (face < 0 || d > m_gbuffer.depth[i] + tol) continue;
            if (anyFacing || !(m_gbuffer.mesh->faceNormal(face).dot(normal) < 0)) return true;
        }
    return false;
}

void addVisibleStrokes(std::vector<Stroke> &out, const std::vector<Vec3> &points, const Camera &camera,
                       const Visibility &vis, double widthPx, const std::vector<Vec3> *normals) {
    ROSY_CHECK(!normals || normals->size() == points.size());
    Stroke run;
    auto finish = [&] {
        if (run.points.size() >= 2) {
            run.widths.assign(run.points.size(), float(widthPx));
            run.id = uint32_t(out.size());
            out.push_back(std::move(run));
        }
        run = Stroke{};
    };
    for (size_t i = 0; i + 1 < points.size(); ++i) {
        const Vec3 &p0 = points[i], &p1 = points[i + 1];
        const Vec2 r0 = camera.project(p0), r1 = camera.project(p1);
        if (!(camera.depth(p0) > 0) || !(camera.depth(p1) > 0) || !r0.allFinite() || !r1.allFinite()) {
            finish();
            continue;
        }
        const int n = std::clamp(int(std::ceil((r1 - r0).norm() / 1.5)), 1, 4096);
        const Vec3 normal = normals ? Vec3((*normals)[i] + (*normals)[i + 1]) : Vec3::Zero();
        for (int k = 0; k < n; ++k) {
            const double t0 = double(k) / n, t1 = double(k + 1) / n;
            if (!vis.visible(p0 + (0.5 * (t0 + t1)) * (p1 - p0), normal)) {
                finish();
                continue;
            }
            if (run.points.empty()) run.points.push_back(r0 + t0 * (r1 - r0));
            run.points.push_back(r0 + t1 * (r1 - r0));
        }
    }
    finish();
}

Stroke dot(const Vec2 &centre, double r, uint32_t id) {
    Stroke s;
    s.points = {centre, centre};
    s.widths = {float(2 * r), float(2 * r)};
    s.id = id;
    return s;
}

ShadedFill shadedFill(const field::Mesh &mesh, const Camera &camera, const std::vector<Light> &lights) {
    ShadedFill out;
    out.drawing.width = camera.width();
    out.drawing.height = camera.height();
    out.drawing.fill = Image(camera.width(), camera.height(), {"R", "G", "B"});
    std::fill(out.drawing.fill.data.begin(), out.drawing.fill.data.end(), 1.0f);
    if (mesh.nFaces() == 0) return out;
    Vec3 lo = mesh.position(0), hi = lo;
    for (int v = 0; v < mesh.nVertices(); ++v) {
        lo = lo.cwiseMin(mesh.position(v));
        hi = hi.cwiseMax(mesh.position(v));
    }
    out.diagonal = std::max((hi - lo).norm(), 1e-12);

    const RayScene scene(mesh);
    out.gbuffer = renderGBuffer(scene, mesh, camera);
    std::vector<Light> used = lights;
    if (used.empty()) {
        // A headlight a little above and left of the eye: every visible part is lit
        // and the form still reads.
        Light head;
        head.direction = -camera.forward() + 0.35 * camera.up() - 0.25 * camera.right();
        used.push_back(head);
    }
    ShadingOptions shading;
    shading.shadows = false;
    shading.ambient = 0.2;
    const std::vector<double> tone = shadeLambert(out.gbuffer, scene, mesh, camera, used, shading);

    // Light grey surface: the lines carry the information, the tone only the form.
    std::vector<float> &rgb = out.drawing.fill.data;
    for (size_t i = 0; i < out.gbuffer.nPixels(); ++i) {
        if (out.gbuffer.faceId[i] < 0) continue;
        const float g = float(0.3 + 0.6 * tone[i]);
        rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = g;
    }
    return out;
}

} // namespace rosy::renderer
