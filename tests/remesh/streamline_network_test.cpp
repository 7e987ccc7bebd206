/// \file streamline_network_test.cpp
/// The paper's streamline network remesher (remesh/streamline_network.h) on
/// procedural surfaces, judged by the independent checks of remesh/quality.h and by
/// what the surfaces are known to be.

#include "field/field_builder.h"
#include "field/primitives.h"
#include "field/mesh/closest_point.h"
#include "field/singularities.h"
#include "remesh/quality.h"
#include "remesh/streamline_network.h"
#include "remesh_helpers.h"
#include "core/error.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

namespace rosy::remesh {
namespace {

using field::Mesh;

struct Network {
    RemeshResult result;
    QualityReport quality;
    field::SingularityReport singularities;
    double edgeLength = 0;
};

Network run(const Mesh &mesh, double relativeEdge, bool separatrices, int nSym = 4,
            double separatrixLength = StreamlineNetworkOptions{}.separatrixLength) {
    const field::TangentFrames frames(mesh);
    field::FieldSpec spec;
    spec.nSym = nSym;
    spec.source = field::FieldSource::Curvature;
    const field::FieldResult fr = field::buildField(frames, spec);
    Network out;
    out.singularities = field::findSingularities(frames, fr.field);
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    StreamlineNetworkOptions opt;
    opt.edgeLength = out.edgeLength = relativeEdge * (hi - lo).norm();
    opt.separatrices = separatrices;
    opt.separatrixLength = separatrixLength;
    out.result = remeshStreamlines(frames, fr.field, out.singularities, opt);
    out.quality = measureQuality(out.result.positions, out.result.polygons, frames, fr.field, out.singularities,
                                 opt.edgeLength);
    return out;
}

void expectClosedValid(const QualityReport &q, int chi) {
    EXPECT_TRUE(q.closed) << q.boundaryEdges << " boundary edges";
    helpers::expectValid(q, chi);
}

// A torus's principal directions run along its two circles and it has no
// singularity: the lines are its meridians and parallels, every crossing a right
// angle. Lines that stop where their neighbours crowd (the inner equator is shorter)
// leave T-junctions (valence 3) and a few pentagons, no other irregularity.
TEST(StreamlineNetwork, TorusIsMeridiansAndParallels) {
    const Network n = run(field::makeTorus(1.0, 0.45, 96, 40), 0.03, false);
    const QualityReport &q = n.quality;
    expectClosedValid(q, 0);
    EXPECT_EQ(q.singularities, 0);
    EXPECT_GE(q.regularFaceFraction, 0.9);
    EXPECT_LT(q.angleDevP90Deg, 5.0);
    EXPECT_LT(q.alignmentP90Deg, 3.0);
    // Irregular vertices are T-junctions, where a line ends on a crossing one.
    for (const auto &[valence, count] : q.valenceHistogram) {
        if (valence != 4) {
            EXPECT_EQ(valence, 3) << count;
        }
    }
    // Every vertex is a crossing of two traced lines: on the (polygonal) torus.
    const Mesh torus = field::makeTorus(1.0, 0.45, 96, 40);
    for (const Vec3 &p : n.result.positions) {
        double best = INFINITY;
        for (const auto &f : torus.faces())
            best = std::min(best, (p - field::closestPointOnTriangle(p, torus.position(f[0]), torus.position(f[1]),
                                                                      torus.position(f[2])))
                                      .norm());
        ASSERT_LT(best, 1e-9) << p.transpose();
    }
    // The faces are flat between them: both distances within the 0.5 %.
    EXPECT_LT(q.distanceOutToInPct, 0.5);
    EXPECT_LT(q.distanceInToOutPct, 0.5);
    EXPECT_EQ(n.result.repairs.at("faces_refused_by_openmesh"), 0);
}

// The rounded cube pair (Figure 4): closed, genus 0, with and without separatrices.
// With them, every singularity is a vertex of the mesh ("this allows singularities
// to be the vertices in the new mesh"); without, the
// lines stop short of the singular faces and no vertex sits on a singular point.
TEST(StreamlineNetwork, Figure4WithSeparatricesHasItsSingularitiesAsVertices) {
    const Mesh mesh = field::makeRoundedCubePair(32);
    for (bool separatrices : {false, true}) {
        SCOPED_TRACE(separatrices ? "separatrices on" : "separatrices off");
        const Network n = run(mesh, 0.03, separatrices);
        expectClosedValid(n.quality, 2);
        EXPECT_GE(n.quality.regularFaceFraction, 0.9);
        int asVertex = 0;
        for (const field::Singularity &s : n.singularities.singularities) {
            double nearest = INFINITY;
            for (const Vec3 &p : n.result.positions) nearest = std::min(nearest, (p - s.position).norm());
            asVertex += nearest < 1e-9 * n.edgeLength;
        }
        if (separatrices) {
            // All 16 with the separatrices traced for six edge lengths (the default);
            // 14 with full-length ones, where two singularities' separatrices all end
            // on lines placed before them and their points keep fewer than three edges.
            EXPECT_EQ(asVertex, int(n.singularities.singularities.size()));
        } else {
            EXPECT_EQ(asVertex, 0);
        }
        RecordProperty(separatrices ? "singular_rings_p90_on" : "singular_rings_p90_off",
                       std::to_string(n.quality.angleDevSingularRingsP90Deg));
    }
}

// The paper's claim for Figure 4 and issue 20's measure of it: with separatrices the
// mesh is better near the singularities — the corners of the two rings of faces
// around each singular vertex (QualityReport::angleDevSingularRings*, the report's
// `singular_rings_*`) deviate less from 90° (from 360° / valence at the vertex). It
// holds with the separatrices traced "for a certain distance" first (the default six
// edge lengths, then running on as ordinary lines: 9.5–13.7° against 27–36° without,
// at the six lengths of docs/remeshing.md), not with the whole separatrices placed
// first (25–40°: those of a nearby pair run beside each other and the singular points
// are left in large polygons), which this test also holds.
TEST(StreamlineNetwork, Figure4IsBetterNearItsSingularitiesWithSeparatrices) {
    const Mesh mesh = field::makeRoundedCubePair(32);
    for (double edge : {0.02, 0.03, 0.04}) {
        SCOPED_TRACE("edge " + std::to_string(edge));
        const Network off = run(mesh, edge, false);
        const Network on = run(mesh, edge, true);
        const Network full = run(mesh, edge, true, 4, INFINITY); // all of each first
        expectClosedValid(on.quality, 2);
        // Measured 35.6 / 31.6 / 26.8° without, 9.5 / 10.7 / 13.7° with, 27.6 / 30.4 /
        // 25.3° with the whole separatrices first (2, 3, 4 %).
        EXPECT_LT(on.quality.angleDevSingularRingsP90Deg, 0.6 * off.quality.angleDevSingularRingsP90Deg);
        EXPECT_LT(on.quality.angleDevSingularRingsP90Deg, 0.6 * full.quality.angleDevSingularRingsP90Deg);
        // Every singularity with an irregular vertex within 2 L.
        EXPECT_EQ(on.quality.singularitiesWithIrregularVertex, int(on.singularities.singularities.size()));
        RecordProperty("singular_rings_p90_off_" + std::to_string(edge), std::to_string(off.quality.angleDevSingularRingsP90Deg));
        RecordProperty("singular_rings_p90_on_" + std::to_string(edge), std::to_string(on.quality.angleDevSingularRingsP90Deg));
    }
}

TEST(StreamlineNetwork, SameOutputForAnyThreadCount) {
    const Mesh mesh = field::makeRoundedCubePair(24);
    Network one, two;
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
        one = run(mesh, 0.04, true);
    }
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
        two = run(mesh, 0.04, true);
    }
    ASSERT_EQ(one.result.positions.size(), two.result.positions.size());
    for (size_t i = 0; i < one.result.positions.size(); ++i)
        ASSERT_EQ(one.result.positions[i], two.result.positions[i]) << i;
    EXPECT_EQ(one.result.polygons, two.result.polygons);
}

TEST(StreamlineNetwork, RefusesSixRosyOpenSurfacesAndTooShortEdges) {
    EXPECT_THROW(run(field::makeIcosphere(3), 0.05, false, 6), InputError);
    EXPECT_THROW(run(field::makeGrid(16), 0.05, false), InputError); // a boundary
    const Mesh sphere = field::makeIcosphere(3);
    const field::TangentFrames frames(sphere);
    field::FieldSpec spec;
    const field::FieldResult fr = field::buildField(frames, spec);
    StreamlineNetworkOptions opt;
    opt.edgeLength = 0.01; // 4π / 1e-4 ≈ 1.3e5 crossings
    opt.maxVertices = 100000;
    try {
        remeshStreamlines(frames, fr.field, field::findSingularities(frames, fr.field), opt);
        ADD_FAILURE() << "no error";
    } catch (const InputError &e) {
        EXPECT_NE(std::string(e.what()).find("--edge"), std::string::npos) << e.what();
    }
    opt.edgeLength = std::nan("");
    EXPECT_THROW(remeshStreamlines(frames, fr.field, field::findSingularities(frames, fr.field), opt), InputError);
    opt.edgeLength = 0.2;
    for (double length : {0.0, -1.0, std::nan("")}) {
        opt.separatrixLength = length;
        EXPECT_THROW(remeshStreamlines(frames, fr.field, field::findSingularities(frames, fr.field), opt), InputError)
            << length;
    }
}

} // namespace
} // namespace rosy::remesh
