#include "field/mesh/mesh_scan.h"

#include "core/error.h"

#include <cctype>
#include <cstring>
#include <unordered_map>

namespace rosy::field::detail {
namespace {

/// Appends corner `p` of an STL triangle, welding bit-identical corners (STL
/// repeats every corner per triangle; welding them is reading, not repair).
struct StlWelder {
    std::unordered_map<uint64_t, std::vector<int>> buckets;
    int add(PolygonSoup &soup, const Vec3 &p) {
        float c[3] = {float(p.x()), float(p.y()), float(p.z())};
        // -0 and +0 are the same point.
        for (float &x : c)
            if (x == 0.0f) x = 0.0f;
        uint32_t b[3];
        std::memcpy(b, c, 12);
        const uint64_t h = (uint64_t(b[0]) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(b[1]) * 0xC2B2AE3D27D4EB4Full) ^
                           (uint64_t(b[2]) * 0x165667B19E3779F9ull);
        std::vector<int> &bucket = buckets[h];
        for (int v : bucket)
            if (soup.positions[v] == Vec3(c[0], c[1], c[2])) return v;
        soup.positions.emplace_back(c[0], c[1], c[2]);
        bucket.push_back(int(soup.positions.size()) - 1);
        return bucket.back();
    }
};

} // namespace

void readStl(const std::string &path, std::string_view text, const LoadOptions &options, PolygonSoup &soup) {
    StlWelder welder;
    // Binary exactly when the size is 84 + 50 n (the only test the format allows: binary files may begin with "solid" too).
    if (text.size() >= 84) {
        uint32_t n;
        std::memcpy(&n, text.data() + 80, 4);
        if (text.size() == 84 + 50 * uint64_t(n)) {
            checkFaceCount(path, 0, n, options);
            soup.polygons.reserve(n);
            for (uint32_t t = 0; t < n; ++t) {
                std::vector<int> tri(3);
                for (int k = 0; k < 3; ++k) {
                    float c[3];
                    std::memcpy(c, text.data() + 84 + 50 * size_t(t) + 12 + 12 * k, 12);
                    const std::string what = "triangle " + std::to_string(t);
                    Vec3 p(binaryCoordinate(path, c[0], what), binaryCoordinate(path, c[1], what),
                           binaryCoordinate(path, c[2], what));
                    tri[k] = welder.add(soup, p);
                }
                soup.polygons.push_back(std::move(tri));
            }
            return;
        }
    }
    LineReader reader(text);
    std::string_view line;
    std::vector<Token> tok;
    bool first = true;
    int64_t nF = 0, nCorner = 0;
    std::vector<int> tri;
    int facetLine = 0;
    auto lowerIs = [](std::string_view s, const char *word) {
        const size_t n = std::strlen(word);
        if (s.size() != n) return false;
        for (size_t i = 0; i < n; ++i)
            if (std::tolower(static_cast<unsigned char>(s[i])) != word[i]) return false;
        return true;
    };
    while (reader.next(line)) {
        tokenize(line, tok);
        if (tok.empty()) continue;
        if (first) {
            if (!lowerIs(tok[0].text, "solid"))
                throw InputError(FileLoc{path, reader.lineNumber(), 1},
                                 "neither ASCII STL (no 'solid' keyword) nor binary STL (size " +
                                     std::to_string(text.size()) + " is not 84 + 50 n bytes)",
                                 "the file is damaged or not an STL file");
            first = false;
            continue;
        }
        if (lowerIs(tok[0].text, "facet")) {
            if (!tri.empty())
                throw InputError(FileLoc{path, facetLine, 1},
                                 "facet " + std::to_string(nF - 1) + " has " + std::to_string(tri.size()) +
                                     " vertices", "each facet has exactly 3 vertex lines");
            facetLine = reader.lineNumber();
            if (++nF > options.maxFaces) checkFaceCount(path, reader.lineNumber(), nF, options);
        } else if (lowerIs(tok[0].text, "vertex")) {
            tri.push_back(welder.add(soup, vertexAt(path, reader.lineNumber(), tok, 1, nCorner++)));
            if (tri.size() > 3)
                throw InputError(FileLoc{path, reader.lineNumber(), 1},
                                 "facet " + std::to_string(nF - 1) + " has more than 3 vertices",
                                 "each facet has exactly 3 vertex lines");
        } else if (lowerIs(tok[0].text, "endfacet")) {
            if (tri.size() != 3)
                throw InputError(FileLoc{path, reader.lineNumber(), 1},
                                 "facet " + std::to_string(nF - 1) + " has " + std::to_string(tri.size()) +
                                     " vertices", "each facet has exactly 3 vertex lines");
            soup.polygons.push_back(tri);
            tri.clear();
        }
    }
    if (first) throw InputError(FileLoc{path}, "the file is empty", "export the mesh again");
    if (!tri.empty())
        throw InputError(FileLoc{path, reader.lineNumber(), 1},
                         "the file ends inside facet " + std::to_string(nF - 1),
                         "the file is truncated");
}

} // namespace rosy::field::detail
