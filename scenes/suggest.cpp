#include "scenes/suggest.h"

#include <algorithm>

namespace rosy::scenes {

int editDistance(const std::string &a, const std::string &b) {
    std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) prev[j] = int(j);
    for (size_t i = 1; i <= a.size(); ++i) {
        cur[0] = int(i);
        for (size_t j = 1; j <= b.size(); ++j)
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

std::string joinNames(const std::vector<std::string> &names) {
    std::string s;
    for (size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + names[i];
    return s;
}

/// "did you mean 'x'?" for the closest candidate within a small edit distance,
/// else the list of allowed names.
std::string suggest(const std::string &word, const std::vector<std::string> &candidates) {
    std::string best;
    int bestDist = 1 << 30;
    for (const std::string &c : candidates) {
        int d = editDistance(word, c);
        if (d < bestDist) {
            bestDist = d;
            best = c;
        }
    }
    int limit = std::max(2, int(word.size()) / 3);
    if (!best.empty() && bestDist <= limit) return "did you mean '" + best + "'?";
    return "expected one of: " + joinNames(candidates);
}

} // namespace rosy::scenes
