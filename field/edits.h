#pragma once
/// \file edits.h
/// Sequences of topological edits (Palacios & Zhang 2007, Sec. 5.2) on top of the
/// single edits of field/editing.h: a scene's or command line's list of cancels and
/// moves applied in order, and the search that cancels the closest opposite pairs
/// until a field has few enough singularities (`rosyhatch compare`'s edited panel).
/// Both re-find the singularities after every edit, so ids always refer to the
/// list as it is just before the edit (sorted by face id).

#include "core/error.h"
#include "field/editing.h"
#include "field/frames.h"
#include "field/rosy.h"
#include "field/singularities.h"

#include <cstddef>
#include <vector>

namespace rosy::field {

/// One topological edit of the field, as asked for by a scene or a flag.
struct FieldEdit {
    enum class Op {
        Cancel,     ///< cancel singularities `a` and `b`
        Move,       ///< move singularity `a` to point `p`
        CancelNear, ///< cancel the opposite-sign pair nearest to points `p` and `q`
    };
    Op op = Op::Cancel;
    int a = -1, b = -1;                      ///< ids into the singularity list just before this edit
    Vec3 p = Vec3::Zero(), q = Vec3::Zero(); ///< world units
    /// Where it was asked for: the scene entry or the CLI flag ("--cancel #1").
    FileLoc loc;
};

/// "cancel", "move" or "cancel_near".
const char *toString(FieldEdit::Op op);

/// One applied edit, for reports.
struct AppliedEdit {
    FieldEdit edit;
    int a = -1, b = -1;               ///< the ids actually used (CancelNear resolves them)
    EditResult result;
    std::vector<Singularity> before;  ///< singularities just before the edit
    std::vector<Singularity> after;   ///< and just after
};

/// Applies `edits` in order to `rosyField` (on the mesh of `frames`), re-finding the
/// singularities between edits. Empty `edits`: returns at once, the field untouched.
/// \throws InputError at the edit's location (bad id, impossible edit); edits
///   before the failing one stay applied, the failing one changes nothing.
std::vector<AppliedEdit> applyFieldEdits(const TangentFrames &frames, RosyField &rosyField,
                                         const std::vector<FieldEdit> &edits);

/// Cancels first-order opposite-sign pairs (+1/N with −1/N), the closest
/// (Euclidean, world units) first, until the field has at most `target`
/// singularities or `maxPairs` pairs are gone. A pair the editor cannot cancel
/// (another singularity in the way, both on the boundary) is skipped; the search
/// stops when no candidate is left or more than 64 pairs have failed. Ties in
/// distance go to the lower ids, so the result never depends on the sort.
/// \returns the number of pairs cancelled (0 on a field without such pairs).
int cancelClosestPairs(const TangentFrames &frames, RosyField &rosyField, std::size_t target, int maxPairs);

} // namespace rosy::field
