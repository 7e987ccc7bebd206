/// \file mesh_picture.cpp
/// Pictures of polygon meshes (mesh_picture.h): shaded fill, edges, tinted faces of
/// the other kind, irregular vertices and singularity rings, as a FieldDrawing.

#include "renderer/mesh_picture.h"

#include "core/error.h"
#include "field/mesh/mesh_io.h"
#include "renderer/picture_common.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

namespace rosy::renderer {
namespace {

/// The second ring of a singularity that did not end up as one irregular element,
/// as a share of the ring's radius.
constexpr double kInnerRingRatio = 0.55;

/// A closed circle of radius r around `centre` as one stroke (48 segments).
Stroke ring(const Vec2 &centre, double r, double widthPx, uint32_t id) {
    Stroke s;
    const int n = 48;
    for (int k = 0; k <= n; ++k) {
        const double a = 2.0 * M_PI * k / n;
        s.points.push_back(centre + r * Vec2(std::cos(a), std::sin(a)));
    }
    s.widths.assign(s.points.size(), float(widthPx));
    s.id = id;
    return s;
}

} // namespace

FieldDrawing drawMeshPicture(const std::vector<Vec3> &positions, const std::vector<std::vector<int>> &polygons,
                             const std::vector<Vec3> &singularityPositions, const Camera &camera,
                             const MeshPictureOptions &options) {
    const int nV = int(positions.size());
    if (!options.singularityAsOne.empty() && options.singularityAsOne.size() != singularityPositions.size())
        throw std::invalid_argument("drawMeshPicture: " + std::to_string(options.singularityAsOne.size()) +
                                    " singularity flags for " + std::to_string(singularityPositions.size()) +
                                    " singularities");
    for (size_t p = 0; p < polygons.size(); ++p) {
        if (polygons[p].size() < 3)
            throw std::invalid_argument("drawMeshPicture: polygon " + std::to_string(p) + " has fewer than 3 vertices");
        for (int v : polygons[p])
            if (v < 0 || v >= nV)
                throw std::invalid_argument("drawMeshPicture: polygon " + std::to_string(p) + " names vertex " +
                                            std::to_string(v) + " of " + std::to_string(nV));
    }

    // The used vertices, renumbered (the triangle mesh may not have isolated ones),
    // then a fan around each polygon's centroid: new edges only towards the new
    // centre, so a manifold polygon mesh gives a manifold triangle mesh, and every
    // polygon edge is a triangle edge (lines lie exactly on the shaded surface).
    std::vector<int> newIndex(size_t(nV), -1);
    std::vector<Vec3> points;
    for (const std::vector<int> &poly : polygons)
        for (int v : poly)
            if (newIndex[size_t(v)] < 0) {
                newIndex[size_t(v)] = int(points.size());
                points.push_back(positions[size_t(v)]);
            }
    std::vector<field::Face> tris;
    std::vector<int> polygonOf;
    for (size_t p = 0; p < polygons.size(); ++p) {
        const std::vector<int> &poly = polygons[p];
        Vec3 c = Vec3::Zero();
        for (int v : poly) c += positions[size_t(v)];
        const int centre = int(points.size());
        points.push_back(c / double(poly.size()));
        for (size_t i = 0; i < poly.size(); ++i) {
            tris.push_back({centre, newIndex[size_t(poly[i])], newIndex[size_t(poly[(i + 1) % poly.size()])]});
            polygonOf.push_back(int(p));
        }
    }
    field::Mesh surface;
    bool faceMapValid = true;
    try {
        surface = field::Mesh::fromTriangles(points, tris, "remeshed surface");
    } catch (const InputError &) {
        // Not clean (e.g. a vertex with two fans): the loaders' repairs, which may
        // reorder faces, so faces of the other kind are not tinted.
        std::vector<std::vector<int>> soup(tris.size());
        for (size_t t = 0; t < tris.size(); ++t) soup[t] = {tris[t][0], tris[t][1], tris[t][2]};
        surface = field::repairAndBuild(points, soup, "remeshed surface");
        faceMapValid = false;
    }

    const int width = camera.width(), height = camera.height();
    ShadedFill shaded = shadedFill(surface, camera, options.lights);
    FieldDrawing drawing = std::move(shaded.drawing);
    if (surface.nFaces() == 0) return drawing;
    const GBuffer &gbuffer = shaded.gbuffer;

    // Faces of the other kind, tinted (multiplied, so the shading still reads).
    if (faceMapValid)
        for (size_t i = 0; i < gbuffer.nPixels(); ++i) {
            const int f = gbuffer.faceId[i];
            if (f < 0 || int(polygons[size_t(polygonOf[size_t(f)])].size()) == options.regularSides) continue;
            for (int c = 0; c < 3; ++c) drawing.fill.data[3 * i + size_t(c)] *= float(options.otherFaceTint[c]);
        }

    // Polygon normals (Newell's, area-weighted), summed per vertex and per edge: what
    // each side of a wall thinner than the visibility's depth tolerance faces, so its
    // far side's lines and dots are not drawn through the near side.
    std::vector<Vec3> vertexNormal(size_t(nV), Vec3::Zero());
    std::vector<Vec3> polygonNormal(polygons.size(), Vec3::Zero());
    for (size_t p = 0; p < polygons.size(); ++p) {
        const std::vector<int> &poly = polygons[p];
        for (size_t i = 0; i < poly.size(); ++i)
            polygonNormal[p] += positions[size_t(poly[i])].cross(positions[size_t(poly[(i + 1) % poly.size()])]);
        for (int v : poly) vertexNormal[size_t(v)] += polygonNormal[p];
    }

    // Undirected edges with the number of polygons on each; valence and boundary per vertex.
    struct HalfEdge {
        int a, b, polygon;
    };
    std::vector<HalfEdge> halfEdges;
    for (size_t p = 0; p < polygons.size(); ++p) {
        const std::vector<int> &poly = polygons[p];
        for (size_t i = 0; i < poly.size(); ++i) {
            const int a = poly[i], b = poly[(i + 1) % poly.size()];
            halfEdges.push_back({std::min(a, b), std::max(a, b), int(p)});
        }
    }
    std::sort(halfEdges.begin(), halfEdges.end(), [](const HalfEdge &x, const HalfEdge &y) {
        return std::tie(x.a, x.b, x.polygon) < std::tie(y.a, y.b, y.polygon);
    });
    std::vector<int> valence(size_t(nV), 0);
    std::vector<char> onBoundary(size_t(nV), 0);
    std::vector<std::pair<int, int>> edges;
    std::vector<Vec3> edgeNormal;
    for (size_t i = 0; i < halfEdges.size();) {
        const int a = halfEdges[i].a, b = halfEdges[i].b;
        Vec3 normal = Vec3::Zero();
        size_t j = i;
        for (; j < halfEdges.size() && halfEdges[j].a == a && halfEdges[j].b == b; ++j)
            normal += polygonNormal[size_t(halfEdges[j].polygon)];
        edges.emplace_back(a, b);
        edgeNormal.push_back(normal);
        ++valence[size_t(a)];
        ++valence[size_t(b)];
        if (j - i == 1) onBoundary[size_t(a)] = onBoundary[size_t(b)] = 1;
        i = j;
    }

    const double sizeScale = std::min(width, height) / 1024.0;
    const Visibility vis(gbuffer, camera, shaded.diagonal);
    auto ink = [&](std::string name, const styles::Rgb &colour, StrokeKind kind, int family,
                   std::vector<Stroke> strokes) {
        for (Stroke &s : strokes) {
            s.kind = kind;
            s.family = family;
        }
        drawing.inks.push_back(FieldInk{std::move(name), colour, 1.0, true, StrokeList{width, height, std::move(strokes)}});
    };

    std::vector<Stroke> edgeStrokes;
    for (size_t e = 0; e < edges.size(); ++e) {
        const auto [a, b] = edges[e];
        const std::vector<Vec3> normals(2, edgeNormal[e]);
        addVisibleStrokes(edgeStrokes, {positions[size_t(a)], positions[size_t(b)]}, camera, vis,
                          options.edgeWidthPx * sizeScale, &normals);
    }
    ink("edges", options.edgeColor, StrokeKind::Hatch, 0, std::move(edgeStrokes));
    drawing.inks.back().minRasterWidthPx = 0.8;

    std::vector<Stroke> rings;
    for (size_t k = 0; k < singularityPositions.size(); ++k) {
        const Vec3 &p = singularityPositions[k];
        if (!vis.visible(p, 1.5)) continue;
        const Vec2 c = camera.project(p);
        rings.push_back(ring(c, options.ringRadiusPx * sizeScale, options.ringWidthPx * sizeScale, uint32_t(rings.size())));
        if (!options.singularityAsOne.empty() && !options.singularityAsOne[k])
            rings.push_back(ring(c, kInnerRingRatio * options.ringRadiusPx * sizeScale, options.ringWidthPx * sizeScale,
                                 uint32_t(rings.size())));
    }
    ink("field singularities", options.ringColor, StrokeKind::Hatch, 1, std::move(rings));

    const int regularValence = options.regularSides == 3 ? 6 : 4;
    std::vector<Stroke> low, high, degenerate;
    for (int v = 0; v < nV; ++v) {
        if (valence[size_t(v)] == 0 || onBoundary[size_t(v)] || valence[size_t(v)] == regularValence) continue;
        if (!vis.visible(positions[size_t(v)], vertexNormal[size_t(v)], 1.5)) continue;
        std::vector<Stroke> &group =
            valence[size_t(v)] <= 2 ? degenerate : (valence[size_t(v)] < regularValence ? low : high);
        group.push_back(dot(camera.project(positions[size_t(v)]), options.dotRadiusPx * sizeScale,
                            uint32_t(group.size())));
    }
    ink("low-valence vertices", options.lowValenceColor, StrokeKind::Contour, -1, std::move(low));
    ink("high-valence vertices", options.highValenceColor, StrokeKind::Contour, -1, std::move(high));
    ink("valence-2 vertices", styles::Rgb{0, 0, 0}, StrokeKind::Contour, -1, std::move(degenerate));
    return drawing;
}

} // namespace rosy::renderer
