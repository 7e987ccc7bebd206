#pragma once
/// \file remesh_helpers.h
/// What the remesher's tests share: one run from a mesh to its measured remesh, and
/// the guarantees every remesh keeps, checked with the independent measures of
/// remesh/quality.h.

#include "field/field_builder.h"
#include "field/singularities.h"
#include "remesh/quality.h"
#include "remesh/remesh.h"

#include <gtest/gtest.h>

namespace rosy::remesh::helpers {

struct Remeshed {
    RemeshResult result;
    QualityReport quality;
    field::SingularityReport singularities;
    double edgeLength = 0; ///< in world units
};

/// The field of `spec` on `mesh`, its singularities, the remesh with `options` at
/// edge length relativeEdge × the bounding-box diagonal, and its quality.
inline Remeshed remeshAndMeasure(const field::Mesh &mesh, const field::FieldSpec &spec, RemeshOptions options,
                                 double relativeEdge) {
    const field::TangentFrames frames(mesh);
    const field::FieldResult fr = field::buildField(frames, spec);
    Remeshed out;
    out.singularities = field::findSingularities(frames, fr.field);
    field::Vec3 lo, hi;
    mesh.bounds(lo, hi);
    options.edgeLength = relativeEdge * (hi - lo).norm();
    out.edgeLength = options.edgeLength;
    out.result = remesh(frames, fr.field, out.singularities, options);
    out.quality = measureQuality(out.result.positions, out.result.polygons, frames, fr.field, out.singularities,
                                 options.edgeLength);
    return out;
}

/// Manifold, consistently oriented, Euler characteristic `chi`, no degenerate or
/// flipped face and no valence-2 vertex (closed or not).
inline void expectValid(const QualityReport &q, int chi) {
    EXPECT_TRUE(q.manifold) << q.nonManifoldEdges << " edges, " << q.nonManifoldVertices << " vertices";
    EXPECT_TRUE(q.oriented) << q.inconsistentEdges;
    EXPECT_EQ(q.eulerCharacteristic, chi);
    EXPECT_EQ(q.degenerateFaces, 0);
    EXPECT_EQ(q.flippedFaces, 0);
    EXPECT_EQ(q.valence2Vertices, 0);
}

} // namespace rosy::remesh::helpers
