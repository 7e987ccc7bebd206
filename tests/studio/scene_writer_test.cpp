// scenes/scene_writer.h: the `field:` block written back into a scene's text.

#include "core/error.h"
#include "scenes/scene.h"
#include "scenes/scene_writer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

using rosy::scenes::FieldBlock;
using rosy::scenes::parseScene;
using rosy::scenes::replaceFieldBlock;

const std::string kMesh = std::string(ROSY_DATA_DIR) + "/meshes/head.off";

FieldBlock sampleBlock() {
    FieldBlock b;
    b.symmetry = 2;
    b.source = rosy::field::FieldSource::Curvature;
    b.smoothingLength = 0.1 / 3.0; // not exact in decimal: must still read back bit for bit
    b.featureAngleDeg = 100.0 / 3.0; // field.features.angle
    b.featureMinLength = 0.1 / 7.0;
    FieldBlock::Element regular;
    regular.position = {0.1 / 7.0, -2.0 / 3.0, 1e-17};
    regular.direction = {0, 1, 0.3};
    FieldBlock::Element singular;
    singular.position = {0.25, 0.5, -0.125};
    singular.order = -1;
    singular.phaseDeg = 1.0 / 3.0;
    b.elements = {regular, singular};
    rosy::field::FieldEdit cancel;
    cancel.op = rosy::field::FieldEdit::Op::CancelNear;
    cancel.p = {1.0 / 3.0, 0, 0};
    cancel.q = {0, 2.0 / 3.0, 0};
    rosy::field::FieldEdit move;
    move.op = rosy::field::FieldEdit::Op::Move;
    move.a = 7;
    move.p = {0.3, 0.2, 0.1};
    b.edits = {cancel, move};
    return b;
}

TEST(SceneWriter, ReplacesOnlyTheFieldBlockKeepingComments) {
    const std::string text = "# head scene\nmesh: " + kMesh +
                             "\nfield:   # the old block\n  symmetry: 4\n  source: smoothest\n"
                             "# style comment stays\nstyle:\n  ambient: 0.08  # inline\noutput: head.png\n";
    const std::string out = replaceFieldBlock(text, "t.yaml", sampleBlock());
    EXPECT_NE(out.find("# head scene\n"), std::string::npos);
    EXPECT_NE(out.find("# style comment stays\nstyle:\n  ambient: 0.08  # inline\n"), std::string::npos);
    EXPECT_EQ(out.find("the old block"), std::string::npos);
    EXPECT_EQ(out.find("smoothest"), std::string::npos);
    const rosy::scenes::SceneDesc d = parseScene(out, "t.yaml");
    EXPECT_EQ(d.output.value, "head.png");
    EXPECT_EQ(d.field.spec.nSym, 2);
    EXPECT_EQ(d.field.spec.source, rosy::field::FieldSource::Curvature);
}

TEST(SceneWriter, NumbersReadBackExactly) {
    const FieldBlock b = sampleBlock();
    const std::string out = replaceFieldBlock("mesh: " + kMesh + "\n", "t.yaml", b);
    const rosy::scenes::SceneDesc d = parseScene(out, "t.yaml");
    EXPECT_EQ(d.field.spec.smoothingLength, b.smoothingLength);
    EXPECT_EQ(d.field.spec.featureAngleDeg, b.featureAngleDeg);
    EXPECT_EQ(d.field.spec.featureMinLength, b.featureMinLength);
    ASSERT_EQ(d.field.spec.elements.size(), 2u);
    EXPECT_EQ(d.field.spec.elements[0].position, b.elements[0].position);
    EXPECT_EQ(d.field.spec.elements[0].direction, b.elements[0].direction);
    EXPECT_EQ(d.field.spec.elements[1].order, -1);
    EXPECT_EQ(d.field.spec.elements[1].phaseRad, b.elements[1].phaseDeg * M_PI / 180.0);
    ASSERT_EQ(d.field.edits.size(), 2u);
    EXPECT_EQ(d.field.edits[0].op, rosy::field::FieldEdit::Op::CancelNear);
    EXPECT_EQ(d.field.edits[0].p, b.edits[0].p);
    EXPECT_EQ(d.field.edits[0].q, b.edits[0].q);
    EXPECT_EQ(d.field.edits[1].op, rosy::field::FieldEdit::Op::Move);
    EXPECT_EQ(d.field.edits[1].a, 7);
    EXPECT_EQ(d.field.edits[1].p, b.edits[1].p);
}

TEST(SceneWriter, AppendsAMissingBlockAndReplacesTheLastKey) {
    const std::string noField = "mesh: " + kMesh + "\noutput: x.png"; // no final newline
    const std::string out = replaceFieldBlock(noField, "t.yaml", sampleBlock());
    EXPECT_EQ(out.rfind("output: x.png\nfield:\n", 0) == std::string::npos, true);
    EXPECT_NE(out.find("output: x.png\nfield:\n"), std::string::npos);
    const std::string last = "mesh: " + kMesh + "\nfield: {symmetry: 6}\n# trailing comment\n";
    const std::string out2 = replaceFieldBlock(last, "t.yaml", sampleBlock());
    EXPECT_EQ(out2.find("symmetry: 6"), std::string::npos);
    EXPECT_NE(out2.find("# trailing comment"), std::string::npos);
    EXPECT_EQ(parseScene(out2, "t.yaml").field.spec.nSym, 2);
}

TEST(SceneWriter, RefusesWhatCannotBeSpliced) {
    EXPECT_THROW(replaceFieldBlock("{mesh: a.off, field: {symmetry: 2}}", "t.yaml", sampleBlock()), rosy::InputError);
    EXPECT_THROW(replaceFieldBlock("- a\n- b\n", "t.yaml", sampleBlock()), rosy::InputError);
    EXPECT_THROW(replaceFieldBlock("mesh: [unclosed\n", "t.yaml", sampleBlock()), rosy::InputError);
}

} // namespace
