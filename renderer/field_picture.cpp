/// \file field_picture.cpp
/// Field pictures (Palacios & Zhang 2007, Figures 3–6): a light Lambert fill, dense
/// surface streamlines, separatrices and singularity dots. Everything drawn is a
/// stroke: each colour is one stroke list, rasterized by rasterizeStrokes() and
/// painted over the fill in its colour, or written as SVG paths.

#include "renderer/field_picture.h"

#include "core/parallel.h"
#include "field/streamlines.h"
#include "renderer/output/raster.h"
#include "renderer/view/embree_scene.h"
#include "renderer/view/gbuffer.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace rosy::renderer {
namespace {

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

/// Appends the visible parts of a world polyline to `out` as strokes of full width
/// `widthPx`: each segment is cut into pieces of at most ~1.5 px on screen and each
/// piece kept or dropped by the visibility of its midpoint; a run of kept pieces is
/// one stroke.
void addVisibleStrokes(std::vector<Stroke> &out, const std::vector<field::Vec3> &points, const Camera &camera,
                       const Visibility &vis, double widthPx) {
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
        for (int k = 0; k < n; ++k) {
            const double t0 = double(k) / n, t1 = double(k + 1) / n;
            if (!vis.visible(p0 + (0.5 * (t0 + t1)) * (p1 - p0))) {
                finish();
                continue;
            }
            if (run.points.empty()) run.points.push_back(r0 + t0 * (r1 - r0));
            run.points.push_back(r0 + t1 * (r1 - r0));
        }
    }
    finish();
}

/// A filled dot of radius r: a stroke of two equal points (a round cap), width 2r.
Stroke dot(const Vec2 &centre, double r, uint32_t id) {
    Stroke s;
    s.points = {centre, centre};
    s.widths = {float(2 * r), float(2 * r)};
    s.id = id;
    return s;
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

FieldDrawing drawFieldPicture(const field::Mesh &mesh, const field::TangentFrames &frames,
                              const field::RosyField &field, const field::SingularityReport &report,
                              const std::vector<field::Separatrix> &separatrices, const Camera &camera,
                              const FieldPictureOptions &options) {
    const int width = camera.width(), height = camera.height();
    FieldDrawing drawing;
    drawing.width = width;
    drawing.height = height;
    drawing.fill = Image(width, height, {"R", "G", "B"});
    std::fill(drawing.fill.data.begin(), drawing.fill.data.end(), 1.0f);
    if (mesh.nFaces() == 0) return drawing;

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
    std::vector<float> &rgb = drawing.fill.data;
    for (size_t i = 0; i < gbuffer.nPixels(); ++i) {
        if (gbuffer.faceId[i] < 0) continue;
        const float g = float(0.3 + 0.6 * tone[i]);
        rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = g;
    }

    const double sizeScale = std::min(width, height) / 1024.0;
    const Visibility vis(gbuffer, camera, diagonal);
    // Each ink's kind and family choose its pen layer in the SVG (fieldPictureStrokes()).
    auto ink = [&](std::string name, const styles::Rgb &colour, double opacity, StrokeKind kind, int family,
                   std::vector<Stroke> strokes, bool vector = true) {
        for (Stroke &s : strokes) {
            s.kind = kind;
            s.family = family;
        }
        FieldInk in{std::move(name), colour, opacity, vector, StrokeList{width, height, std::move(strokes)}};
        drawing.inks.push_back(std::move(in));
    };

    std::vector<Stroke> streamStrokes;
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
        for (const auto &pts : lines)
            addVisibleStrokes(streamStrokes, pts, camera, vis, options.streamlineWidthPx * sizeScale);
    }
    ink("streamlines", options.streamlineColor, 0.9, StrokeKind::Hatch, 0, std::move(streamStrokes));
    drawing.inks.back().minRasterWidthPx = 0.8;

    std::vector<Stroke> outgoing, incoming;
    for (const field::Separatrix &s : separatrices)
        addVisibleStrokes(s.incoming ? incoming : outgoing, s.line.points, camera, vis,
                          options.separatrixWidthPx * sizeScale);
    ink("outgoing separatrices", options.outgoingColor, 1.0, StrokeKind::Hatch, 1, std::move(outgoing));
    ink("incoming separatrices", options.incomingColor, 1.0, StrokeKind::Hatch, 1, std::move(incoming));

    // Dots: a black rim under four colour groups (sign × first/higher order).
    std::vector<Stroke> rims, dots[4];
    for (const field::Singularity &s : report.singularities) {
        if (s.indexNumerator == 0 || !vis.visible(s.position, 1.5)) continue;
        const bool higher = std::abs(s.indexNumerator) > 1;
        const double r = options.dotRadiusPx * sizeScale * (higher ? 1.4 : 1.0);
        const Vec2 c = camera.project(s.position);
        rims.push_back(dot(c, r + std::max(1.0, 1.2 * sizeScale), uint32_t(rims.size())));
        std::vector<Stroke> &group = dots[(s.indexNumerator > 0 ? 0 : 1) + (higher ? 2 : 0)];
        group.push_back(dot(c, r, uint32_t(group.size())));
    }
    auto darker = [](const styles::Rgb &c) { return styles::Rgb{0.45 * c[0], 0.45 * c[1], 0.45 * c[2]}; };
    ink("singularity rims", styles::Rgb{0, 0, 0}, 1.0, StrokeKind::Contour, -1, std::move(rims), false);
    ink("positive singularities", options.positiveColor, 1.0, StrokeKind::Contour, -1, std::move(dots[0]));
    ink("negative singularities", options.negativeColor, 1.0, StrokeKind::Contour, -1, std::move(dots[1]));
    ink("positive higher-order singularities", darker(options.positiveColor), 1.0, StrokeKind::Contour, -1,
        std::move(dots[2]));
    ink("negative higher-order singularities", darker(options.negativeColor), 1.0, StrokeKind::Contour, -1,
        std::move(dots[3]));
    return drawing;
}

Image rasterizeFieldDrawing(const FieldDrawing &drawing) {
    Image image = drawing.fill;
    // One ink is one flat colour: where its strokes overlap they do not darken.
    RasterOptions raster;
    raster.combine = RasterOptions::Combine::Max;
    for (const FieldInk &in : drawing.inks) {
        if (in.strokes.strokes.empty()) continue;
        const float minWidth = float(in.minRasterWidthPx);
        bool widen = false;
        for (const Stroke &s : in.strokes.strokes)
            for (float w : s.widths) widen = widen || w < minWidth;
        if (!widen) {
            paintOver(image, combinedCoverage(rasterizeStrokes(in.strokes, raster)), in.colour, in.opacity);
            continue;
        }
        StrokeList wide = in.strokes;
        for (Stroke &s : wide.strokes)
            for (float &w : s.widths) w = std::max(w, minWidth);
        paintOver(image, combinedCoverage(rasterizeStrokes(wide, raster)), in.colour, in.opacity);
    }
    return image;
}

StrokeList fieldPictureStrokes(const FieldDrawing &drawing) {
    StrokeList list{drawing.width, drawing.height, {}};
    for (const FieldInk &in : drawing.inks) {
        if (!in.vector) continue;
        for (const Stroke &s : in.strokes.strokes) {
            list.strokes.push_back(s);
            list.strokes.back().id = uint32_t(list.strokes.size() - 1);
        }
    }
    return list;
}

Image renderFieldPicture(const field::Mesh &mesh, const field::TangentFrames &frames,
                         const field::RosyField &field, const field::SingularityReport &report,
                         const std::vector<field::Separatrix> &separatrices, const Camera &camera,
                         const FieldPictureOptions &options) {
    return rasterizeFieldDrawing(drawFieldPicture(mesh, frames, field, report, separatrices, camera, options));
}

} // namespace rosy::renderer
