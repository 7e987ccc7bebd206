#include "field/mesh/mesh_scan.h"

#include "core/error.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace rosy::field::detail {
namespace {

struct PlyProperty {
    std::string name;
    bool list = false;
    int countSize = 0, itemSize = 0; // binary sizes (list: count and item type)
    std::string countType, itemType; // type names (a scalar has only itemType)
};

struct PlyElement {
    std::string name;
    int64_t count = 0;
    int64_t minBytes = 0; // per element, as ASCII or binary
    std::vector<PlyProperty> properties;
};

/// Appends the triangles of one PLY triangle strip (the `tristrips` element of
/// Stanford's range scans): -1 restarts the strip; within a strip triangle k is
/// (s_k, s_k+1, s_k+2), with the first two swapped for odd k so that every
/// triangle keeps the strip's winding (OpenGL's GL_TRIANGLE_STRIP rule).
/// Triangles with a repeated vertex are the strip's way of turning or joining
/// and are skipped without a repair warning, but still count for the parity.
void appendStripTriangles(const std::vector<int> &strip, std::vector<std::vector<int>> &polygons) {
    size_t begin = 0;
    while (begin < strip.size()) {
        size_t end = begin;
        while (end < strip.size() && strip[end] >= 0) ++end;
        for (size_t k = begin; k + 2 < end; ++k) {
            int a = strip[k], b = strip[k + 1];
            const int c = strip[k + 2];
            if ((k - begin) % 2 == 1) std::swap(a, b);
            if (a != b && b != c && a != c) polygons.push_back({a, b, c});
        }
        begin = end + 1;
    }
}

} // namespace

/// Parses a PLY header, checks its counts against the file size, and reads
/// its ASCII or binary (either byte order) data: faces from a `face` element,
/// a `tristrips` element, or both.
void readPly(const std::string &path, std::string_view text, const LoadOptions &options, PolygonSoup &soup) {
    LineReader reader(text);
    std::string_view line;
    std::vector<Token> tok;
    if (!reader.next(line) || (tokenize(line, tok), tok.empty()) || tok[0].text != "ply")
        throw InputError(FileLoc{path, 1, 1}, "expected a PLY header ('ply')",
                         "the first line of a .ply file is 'ply'");
    bool ascii = true, ended = false, bigEndian = false;
    std::vector<PlyElement> elements;
    while (reader.next(line)) {
        tokenize(line, tok);
        if (tok.empty()) continue;
        const int ln = reader.lineNumber();
        if (tok[0].text == "format" && tok.size() >= 2) {
            ascii = tok[1].text == "ascii";
            bigEndian = tok[1].text == "binary_big_endian";
            if (!ascii && tok[1].text != "binary_little_endian" && tok[1].text != "binary_big_endian")
                throw InputError(FileLoc{path, ln, tok[1].col}, "unknown PLY format '" + std::string(tok[1].text) + "'",
                                 "use ascii, binary_little_endian or binary_big_endian");
            if (tok.size() != 3 || tok[2].text != "1.0")
                throw InputError(FileLoc{path, ln, tok.size() >= 3 ? tok[2].col : 1},
                                 "expected 'format " + std::string(tok[1].text) + " 1.0'",
                                 "PLY 1.0 is the only version");
        } else if (tok[0].text == "element") {
            PlyElement e;
            if (tok.size() < 3 || !parseInt64(tok[2].text, e.count) || e.count < 0)
                throw InputError(FileLoc{path, ln, tok.size() >= 3 ? tok[2].col : 1},
                                 "expected 'element NAME COUNT' with a whole COUNT >= 0",
                                 "e.g. 'element vertex 8'");
            e.name = std::string(tok[1].text);
            if (e.name == "face") checkFaceCount(path, ln, e.count, options);
            elements.push_back(e);
        } else if (tok[0].text == "property") {
            if (elements.empty())
                throw InputError(FileLoc{path, ln, 1}, "property before any element", "declare the element first");
            PlyElement &e = elements.back();
            PlyProperty prop;
            if (tok.size() >= 5 && tok[1].text == "list") {
                prop = {std::string(tok[4].text), true, plyTypeSize(tok[2].text), plyTypeSize(tok[3].text),
                        std::string(tok[2].text), std::string(tok[3].text)};
                if (prop.countSize == 0 || prop.itemSize == 0)
                    throw InputError(FileLoc{path, ln, tok[2].col}, "unknown PLY property type",
                                     "use char, uchar, short, ushort, int, uint, float or double");
                // The smallest face is a triangle; other lists may be empty.
                const bool corners = e.name == "face" && (prop.name == "vertex_indices" || prop.name == "vertex_index");
                e.minBytes += ascii ? (corners ? 8 : 2) : prop.countSize + (corners ? 3 * prop.itemSize : 0);
            } else if (tok.size() == 3) {
                prop = {std::string(tok[2].text), false, plyTypeSize(tok[1].text), 0, {}, std::string(tok[1].text)};
                if (prop.countSize == 0)
                    throw InputError(FileLoc{path, ln, tok[1].col}, "unknown PLY property type '" +
                                                                         std::string(tok[1].text) + "'",
                                     "use char, uchar, short, ushort, int, uint, float or double");
                e.minBytes += ascii ? 2 : prop.countSize;
            } else {
                throw InputError(FileLoc{path, ln, 1}, "expected 'property TYPE NAME' or 'property list CTYPE ITYPE NAME'");
            }
            e.properties.push_back(prop);
        } else if (tok[0].text == "end_header") {
            ended = true;
            break;
        }
    }
    if (!ended)
        throw InputError(FileLoc{path, reader.lineNumber(), 1}, "the PLY header has no 'end_header'",
                         "the file is truncated or not a PLY file");
    uint64_t need = 0;
    for (const PlyElement &e : elements) need += uint64_t(e.count) * uint64_t(e.minBytes);
    if (need > reader.remainingBytes() + 1) {
        std::string counts;
        for (const PlyElement &e : elements)
            counts += (counts.empty() ? "" : ", ") + std::to_string(e.count) + " " + e.name;
        throw InputError(FileLoc{path, 1, 1},
                         "header says " + counts + " but the data after it is only " +
                             std::to_string(reader.remainingBytes()) + " bytes",
                         "the file is truncated or its header is wrong");
    }
    int64_t nV = -1;
    for (const PlyElement &e : elements)
        if (e.name == "vertex") nV = e.count;
    BinaryCursor in(path, text.substr(reader.position()), bigEndian);
    for (const PlyElement &e : elements) {
        // Any other element without properties holds no data in either encoding (its
        // ASCII lines would be empty, and blank lines are skipped), so it is skipped,
        // not iterated: the size check above cannot bound its count (0 bytes each), and
        // counting to 10^11 was the fuzzer's PLY hang (tests/fuzz/mesh_ply/crashers).
        // A vertex or face element without properties is rejected just below.
        if (e.properties.empty() && e.name != "vertex" && e.name != "face" && e.name != "tristrips") continue;
        const auto at = [&](const char *n) {
            for (size_t i = 0; i < e.properties.size(); ++i)
                if (e.properties[i].name == n) return i;
            return e.properties.size();
        };
        const bool isVertex = e.name == "vertex", isFace = e.name == "face", isStrips = e.name == "tristrips";
        const size_t ix = at("x"), iy = at("y"), iz = at("z");
        size_t iFace = at("vertex_indices");
        if (iFace == e.properties.size()) iFace = at("vertex_index");
        if (isVertex && (ix == e.properties.size() || iy == e.properties.size() || iz == e.properties.size()))
            throw InputError(FileLoc{path}, "the vertex element has no x, y and z properties",
                             "add 'property float x' etc.");
        if (isFace && (iFace == e.properties.size() || !e.properties[iFace].list))
            throw InputError(FileLoc{path}, "the face element has no vertex_indices list",
                             "add 'property list uchar int vertex_indices'");
        if (isStrips && (iFace == e.properties.size() || !e.properties[iFace].list))
            throw InputError(FileLoc{path}, "the tristrips element has no vertex_indices list",
                             "add 'property list int int vertex_indices'");
        if (isVertex) soup.positions.reserve(size_t(e.count));
        if (isFace) soup.polygons.reserve(soup.polygons.size() + size_t(e.count));
        std::vector<int> strip;
        if (!ascii) {
            for (int64_t i = 0; i < e.count; ++i) {
                const std::string what = e.name + " " + std::to_string(i);
                Vec3 p = Vec3::Zero();
                for (size_t k = 0; k < e.properties.size(); ++k) {
                    const PlyProperty &prop = e.properties[k];
                    if (!prop.list) {
                        const double x = in.read(prop.itemType, what);
                        if (isVertex && (k == ix || k == iy || k == iz))
                            p[k == ix ? 0 : k == iy ? 1 : 2] = binaryCoordinate(path, x, what);
                        continue;
                    }
                    const int64_t n = in.readCount(prop.countType, int64_t(in.remaining() / size_t(prop.itemSize)),
                                                   what, "list length");
                    if (isFace && k == iFace) {
                        std::vector<int> poly(static_cast<size_t>(n));
                        for (int64_t c = 0; c < n; ++c)
                            poly[size_t(c)] = int(in.readCount(prop.itemType, std::max<int64_t>(nV - 1, 0), what,
                                                               "vertex index (indices in PLY files start at 0)"));
                        soup.polygons.push_back(std::move(poly));
                    } else if (isStrips && k == iFace) {
                        strip.resize(size_t(n));
                        for (int64_t c = 0; c < n; ++c)
                            strip[size_t(c)] = int(in.readInteger(prop.itemType, -1, std::max<int64_t>(nV - 1, 0), what,
                                                                  "strip index (-1 restarts the strip)"));
                        appendStripTriangles(strip, soup.polygons);
                        checkFaceCount(path, 0, int64_t(soup.polygons.size()), options);
                    } else {
                        for (int64_t c = 0; c < n; ++c) in.read(prop.itemType, what);
                    }
                }
                if (isVertex) soup.positions.push_back(p);
            }
            continue;
        }
        for (int64_t i = 0; i < e.count; ++i) {
            do {
                if (!reader.next(line))
                    throw InputError(FileLoc{path, reader.lineNumber(), 1},
                                     "the file ends at " + e.name + " " + std::to_string(i) + " of " +
                                         std::to_string(e.count),
                                     "the file is truncated or its header is wrong");
            } while (isBlankOrComment(line));
            tokenize(line, tok);
            const int ln = reader.lineNumber();
            size_t t = 0;
            Vec3 p = Vec3::Zero();
            for (size_t k = 0; k < e.properties.size(); ++k) {
                if (t >= tok.size())
                    throw InputError(FileLoc{path, ln, int(line.size()) + 1},
                                     e.name + " " + std::to_string(i) + " has too few values",
                                     "each line holds one " + e.name + " with every property of the header");
                if (!e.properties[k].list) {
                    if (isVertex && (k == ix || k == iy || k == iz))
                        p[k == ix ? 0 : k == iy ? 1 : 2] = coordinate(path, ln, tok[t], i);
                    ++t;
                    continue;
                }
                int64_t n = 0;
                if (!parseInt64(tok[t].text, n) || n < 0 || t + 1 + size_t(n) > tok.size())
                    throw InputError(FileLoc{path, ln, tok[t].col},
                                     e.name + " " + std::to_string(i) + ": bad list length '" +
                                         std::string(tok[t].text) + "'",
                                     "a list is its length followed by that many values");
                if (isFace && k == iFace) {
                    std::vector<int> poly(static_cast<size_t>(n));
                    for (int64_t c = 0; c < n; ++c)
                        poly[size_t(c)] = cornerIndex(path, ln, tok[t + 1 + size_t(c)], i, std::max<int64_t>(nV, 0),
                                                      "indices in PLY files start at 0");
                    soup.polygons.push_back(std::move(poly));
                } else if (isStrips && k == iFace) {
                    strip.resize(size_t(n));
                    for (int64_t c = 0; c < n; ++c) {
                        const Token &index = tok[t + 1 + size_t(c)];
                        int64_t v = 0;
                        if (!parseInt64(index.text, v) || v < -1 || v >= std::max<int64_t>(nV, 0))
                            throw InputError(FileLoc{path, ln, index.col},
                                             "strip " + std::to_string(i) + " uses vertex index '" +
                                                 std::string(index.text) + "' outside [0, " +
                                                 std::to_string(std::max<int64_t>(nV, 0)) + ")",
                                             "strip indices start at 0; -1 restarts the strip");
                        strip[size_t(c)] = int(v);
                    }
                    appendStripTriangles(strip, soup.polygons);
                    checkFaceCount(path, ln, int64_t(soup.polygons.size()), options);
                }
                t += 1 + size_t(n);
            }
            if (isVertex) soup.positions.push_back(p);
        }
    }
}

} // namespace rosy::field::detail
