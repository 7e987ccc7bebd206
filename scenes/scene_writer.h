#pragma once
/// \file scene_writer.h
/// Writing a scene's `field:` block back into its YAML text (for `rosyhatch
/// studio`'s save). Only the `field:` block is replaced; every other line of the
/// file, comments included, stays as it was. Numbers are written in their
/// shortest form that reads back to the same double, so parsing the text gives
/// exactly the values that were written (the saved scene renders the same picture).

#include "field/edits.h"
#include "field/field_builder.h"

#include <string>
#include <vector>

namespace rosy::scenes {

/// A `field:` block as the scene file spells it (phase in degrees, as written).
struct FieldBlock {
    struct Element {
        field::Vec3 position = field::Vec3::Zero();
        int order = 0;                              ///< −1, 0, 1
        field::Vec3 direction = field::Vec3::UnitX(); ///< order 0
        double phaseDeg = 0;                        ///< order ±1
        double strength = 1;
    };
    int symmetry = 4;
    field::FieldSource source = field::FieldSource::Curvature;
    double smoothingLength = 0.08;
    field::LaplaceWeights weights = field::LaplaceWeights::MeanValue;
    int globalSmoothingIterations = 0;
    double globalSmoothingStrength = 0.5;
    double featureAngleDeg = 0;  ///< `features: {angle: D, min_length: m}`, written when D > 0
    double featureMinLength = 0; ///< written when > 0
    std::vector<Element> elements;
    std::vector<field::FieldEdit> edits;
};

/// The block of a parsed spec and its edits (phases converted back to degrees).
FieldBlock fieldBlockOf(const field::FieldSpec &spec, const std::vector<field::FieldEdit> &edits);

/// The block as YAML text, starting with the line "field:" and ending with a newline.
std::string fieldBlockYaml(const FieldBlock &block);

/// `sceneText` with its top-level `field:` entry replaced by `block` (appended when
/// the scene has none). `path` names the text in messages.
/// \throws InputError if the text is no YAML map, or its top-level map is written in
///   flow style (`{mesh: ..., field: ...}` on one line), where no block can be spliced.
std::string replaceFieldBlock(const std::string &sceneText, const std::string &path, const FieldBlock &block);

} // namespace rosy::scenes
