/// \file field_picture.cpp
/// Field pictures (Palacios & Zhang 2007, Figures 3–6): a light Lambert fill, dense
/// surface streamlines, separatrices and singularity dots. Everything drawn is a
/// stroke: each colour is one stroke list, rasterized by rasterizeStrokes() and
/// painted over the fill in its colour, or written as SVG paths.

#include "renderer/field_picture.h"

#include "core/parallel.h"
#include "field/streamlines.h"
#include "renderer/output/raster.h"
#include "renderer/picture_common.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace rosy::renderer {
namespace {

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
    ShadedFill shaded = shadedFill(mesh, camera, options.lights);
    FieldDrawing drawing = std::move(shaded.drawing);
    if (mesh.nFaces() == 0) return drawing;
    const GBuffer &gbuffer = shaded.gbuffer;
    const double diagonal = shaded.diagonal;
    Vec3 lo = mesh.position(0);
    for (int v = 0; v < mesh.nVertices(); ++v) lo = lo.cwiseMin(mesh.position(v));

    const double sizeScale = std::min(width, height) / 1024.0;
    const Visibility vis(gbuffer, camera, diagonal);
    // The normal of the face holding each point of a traced line (empty if the line
    // does not name them), so a wall's far side is not drawn through it.
    auto facingOf = [&](const field::Streamline &line) {
        std::vector<Vec3> normals;
        if (line.faces.size() != line.points.size()) return normals;
        normals.reserve(line.faces.size());
        for (int f : line.faces) normals.push_back(f >= 0 && f < mesh.nFaces() ? mesh.faceNormal(f) : Vec3::Zero());
        return normals;
    };
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
        std::vector<field::Streamline> lines(seeds.size() * size_t(nMembers));
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
                lines[size_t(s) * size_t(nMembers) + size_t(k)] = std::move(line);
            }
        }, 16);
        for (const field::Streamline &line : lines) {
            const std::vector<Vec3> normals = facingOf(line);
            addVisibleStrokes(streamStrokes, line.points, camera, vis, options.streamlineWidthPx * sizeScale,
                              normals.empty() ? nullptr : &normals);
        }
    }
    ink("streamlines", options.streamlineColor, 0.9, StrokeKind::Hatch, 0, std::move(streamStrokes));
    drawing.inks.back().minRasterWidthPx = 0.8;

    std::vector<Stroke> outgoing, incoming;
    for (const field::Separatrix &s : separatrices) {
        const std::vector<Vec3> normals = facingOf(s.line);
        addVisibleStrokes(s.incoming ? incoming : outgoing, s.line.points, camera, vis,
                          options.separatrixWidthPx * sizeScale, normals.empty() ? nullptr : &normals);
    }
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
