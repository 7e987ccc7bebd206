/// \file fig8_test.cpp
/// Palacios & Zhang 2007, Figure 8 (docs/remeshing.md, "Figure 8"): the default
/// curvature 4-RoSy field of a CGAL mesh (elephant) made simpler two ways — the
/// paper's global smoothing (60 steps of strength 0.5, as `rosyhatch compare`'s
/// smoothed variant), and topological editing (the closest opposite singularity
/// pairs cancelled down to as many singularities as smoothing leaves, its edited
/// variant) — and each remeshed at L = 2 %. The paper: smoothing "no longer
/// follows the principle curvature directions", editing "maintain[s] sharp
/// features". Measured here as the alignment of the output edges to the raw
/// principal directions (the curvature field without its smoothing length).

#include "field/edits.h"
#include "field/field_builder.h"
#include "field/mesh_io.h"
#include "field/singularities.h"
#include "field/smoothing.h"
#include "remesh/quality.h"
#include "remesh/remesh.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace rosy::remesh {
namespace {

TEST(Fig8Remesh, EditedFieldFollowsCurvatureBetterThanSmoothed) {
    const field::Mesh mesh = field::loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/elephant.off");
    const field::TangentFrames frames(mesh);
    field::FieldSpec spec; // the default curvature 4-RoSy field
    const field::RosyField base = field::buildField(frames, spec).field;
    field::FieldSpec rawSpec = spec;
    rawSpec.smoothingLength = 0; // the principal directions themselves
    const field::RosyField curvature = field::buildField(frames, rawSpec).field;

    field::RosyField smoothed = base;
    field::relaxationSmooth(frames, smoothed, 60, 0.5);
    const field::SingularityReport smoothedSing = field::findSingularities(frames, smoothed);
    const field::SingularityReport baseSing = field::findSingularities(frames, base);
    ASSERT_LT(smoothedSing.singularities.size(), baseSing.singularities.size());
    field::RosyField edited = base;
    const int pairs = field::cancelClosestPairs(frames, edited, smoothedSing.singularities.size(),
                                                int(baseSing.singularities.size()));
    EXPECT_GT(pairs, 0);
    const field::SingularityReport editedSing = field::findSingularities(frames, edited);
    // A fair comparison: both simplified to about the same number of singularities.
    EXPECT_LE(std::abs(int(editedSing.singularities.size()) - int(smoothedSing.singularities.size())), 4);

    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    RemeshOptions opt;
    opt.edgeLength = 0.02 * (hi - lo).norm();
    auto remeshAlong = [&](const field::RosyField &f, const field::SingularityReport &s) {
        const RemeshResult r = remesh(frames, f, s, opt);
        return measureQuality(r.positions, r.polygons, frames, curvature, s, opt.edgeLength);
    };
    const QualityReport fromSmoothed = remeshAlong(smoothed, smoothedSing);
    const QualityReport fromEdited = remeshAlong(edited, editedSing);
    for (const QualityReport *q : {&fromSmoothed, &fromEdited}) {
        EXPECT_TRUE(q->closed && q->manifold && q->oriented);
        EXPECT_EQ(q->eulerCharacteristic, q->inputEulerCharacteristic);
    }
    EXPECT_LT(fromEdited.alignmentMedianDeg, fromSmoothed.alignmentMedianDeg);
    EXPECT_LT(fromEdited.alignmentP90Deg, fromSmoothed.alignmentP90Deg);
    RecordProperty("alignment_median_smoothed", std::to_string(fromSmoothed.alignmentMedianDeg));
    RecordProperty("alignment_median_edited", std::to_string(fromEdited.alignmentMedianDeg));
}

} // namespace
} // namespace rosy::remesh
