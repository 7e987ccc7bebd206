#include "field/edits.h"

#include <algorithm>
#include <set>
#include <tuple>
#include <utility>

namespace rosy::field {

const char *toString(FieldEdit::Op op) {
    switch (op) {
    case FieldEdit::Op::Cancel: return "cancel";
    case FieldEdit::Op::Move: return "move";
    case FieldEdit::Op::CancelNear: return "cancel_near";
    }
    return "?";
}

std::vector<AppliedEdit> applyFieldEdits(const TangentFrames &frames, RosyField &rosyField,
                                         const std::vector<FieldEdit> &edits) {
    std::vector<AppliedEdit> applied;
    if (edits.empty()) return applied;
    std::vector<Singularity> current = findSingularities(frames, rosyField).singularities;
    for (const FieldEdit &e : edits) {
        AppliedEdit rec;
        rec.edit = e;
        rec.before = current;
        EditOptions options;
        options.where = e.loc;
        rec.a = e.a;
        rec.b = e.b;
        if (e.op == FieldEdit::Op::Move) {
            rec.result = moveSingularity(frames, rosyField, e.a, e.p, options);
        } else {
            if (e.op == FieldEdit::Op::CancelNear) std::tie(rec.a, rec.b) = nearestOppositePair(current, e.p, e.q, e.loc);
            rec.result = cancelPair(frames, rosyField, rec.a, rec.b, options);
        }
        current = findSingularities(frames, rosyField).singularities;
        rec.after = current;
        applied.push_back(std::move(rec));
    }
    return applied;
}

int cancelClosestPairs(const TangentFrames &frames, RosyField &rosyField, std::size_t target, int maxPairs) {
    int cancelled = 0;
    std::set<std::pair<int, int>> failed; // face pairs that could not be cancelled
    for (;;) {
        const std::vector<Singularity> list = findSingularities(frames, rosyField).singularities;
        if (list.size() <= target || cancelled >= maxPairs) break;
        struct Candidate {
            double distance;
            int a, b;
        };
        std::vector<Candidate> candidates;
        for (std::size_t i = 0; i < list.size(); ++i) {
            if (list[i].indexNumerator != 1) continue;
            for (std::size_t j = 0; j < list.size(); ++j) {
                if (list[j].indexNumerator != -1) continue;
                if (failed.count({list[i].face, list[j].face})) continue;
                candidates.push_back({(list[i].position - list[j].position).norm(), int(i), int(j)});
            }
        }
        if (candidates.empty()) break;
        // Nearest first; ids break ties so the order never depends on the sort.
        std::sort(candidates.begin(), candidates.end(), [](const Candidate &x, const Candidate &y) {
            return std::tie(x.distance, x.a, x.b) < std::tie(y.distance, y.a, y.b);
        });
        bool done = false;
        for (const Candidate &c : candidates) {
            try {
                cancelPair(frames, rosyField, c.a, c.b);
                ++cancelled;
                done = true;
                break;
            } catch (const InputError &) {
                // An expected outcome of the search (the editor's refusals are input
                // errors for a user's explicit pair): remember the pair, try the next.
                failed.insert({list[std::size_t(c.a)].face, list[std::size_t(c.b)].face});
                if (failed.size() > 64) break; // the rest of the field is crowded; stop trying
            }
        }
        if (!done) break;
    }
    return cancelled;
}

} // namespace rosy::field
