#include "field/mesh_io.h"

#include "core/diagnostics.h"
#include "core/error.h"

#include <Eigen/Geometry>
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <numeric>
#include <sstream>
#include <unordered_map>

namespace rosy::field {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------
// OpenMesh importer that records the raw polygon soup, bad indices included,
// so that every problem is seen (and counted) by our own repair code instead
// of being dropped by OpenMesh's ImporterT with a message on omerr.
// ---------------------------------------------------------------------------
class SoupImporter final : public OpenMesh::IO::BaseImporter {
public:
    std::vector<Vec3> positions;
    std::vector<std::vector<int>> polygons;

    OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f &p) override {
        positions.emplace_back(p[0], p[1], p[2]);
        return OpenMesh::VertexHandle(int(positions.size()) - 1);
    }
    OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d &p) override {
        positions.emplace_back(p[0], p[1], p[2]);
        return OpenMesh::VertexHandle(int(positions.size()) - 1);
    }
    OpenMesh::VertexHandle add_vertex() override {
        positions.emplace_back(Vec3::Zero());
        return OpenMesh::VertexHandle(int(positions.size()) - 1);
    }
    OpenMesh::HalfedgeHandle add_edge(OpenMesh::VertexHandle, OpenMesh::VertexHandle) override {
        return OpenMesh::HalfedgeHandle();
    }
    OpenMesh::FaceHandle add_face(const VHandles &indices) override {
        std::vector<int> poly(indices.size());
        for (size_t i = 0; i < indices.size(); ++i) poly[i] = indices[i].idx();
        polygons.push_back(std::move(poly));
        return OpenMesh::FaceHandle(int(polygons.size()) - 1);
    }
    OpenMesh::FaceHandle add_face(OpenMesh::HalfedgeHandle) override {
        return OpenMesh::FaceHandle();
    }
    void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                            const std::vector<OpenMesh::Vec2f> &) override {}
    void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                            const std::vector<OpenMesh::Vec3f> &) override {}
    void set_face_texindex(OpenMesh::FaceHandle, int) override {}
    void set_point(OpenMesh::VertexHandle vh, const OpenMesh::Vec3f &p) override {
        if (vh.idx() >= 0 && vh.idx() < int(positions.size()))
            positions[vh.idx()] = Vec3(p[0], p[1], p[2]);
    }
    void set_halfedge(OpenMesh::VertexHandle, OpenMesh::HalfedgeHandle) override {}
    void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3f &) override {}
    void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3d &) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3uc &) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4uc &) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3f &) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4f &) override {}
    void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec2f &) override {}
    void set_status(OpenMesh::VertexHandle, const OpenMesh::Attributes::StatusInfo &) override {}
    void set_next(OpenMesh::HalfedgeHandle, OpenMesh::HalfedgeHandle) override {}
    void set_face(OpenMesh::HalfedgeHandle, OpenMesh::FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec2f &) override {}
    void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec3f &) override {}
    void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec3f &) override {}
    void set_status(OpenMesh::HalfedgeHandle, const OpenMesh::Attributes::StatusInfo &) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3uc &) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4uc &) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3f &) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4f &) override {}
    void set_status(OpenMesh::EdgeHandle, const OpenMesh::Attributes::StatusInfo &) override {}
    void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3f &) override {}
    void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3d &) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3uc &) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4uc &) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3f &) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4f &) override {}
    void set_status(OpenMesh::FaceHandle, const OpenMesh::Attributes::StatusInfo &) override {}
    void add_texture_information(int, std::string) override {}

    // Readers reserve straight from header counts; the header was validated by
    // our pre-scan, and the cap keeps a lying header from costing memory anyway.
    void reserve(unsigned int nV, unsigned int, unsigned int nF) override {
        constexpr unsigned int cap = 1u << 20;
        positions.reserve(std::min(nV, cap));
        polygons.reserve(std::min(nF, cap));
    }
    size_t n_vertices() const override { return positions.size(); }
    size_t n_faces() const override { return polygons.size(); }
    size_t n_edges() const override { return 0; }
};

// OpenMesh's streams are process-global; they are switched off once, before
// the first read, and every problem is reported through rosy::warn instead.
void silenceOpenMesh() {
    static std::once_flag once;
    std::call_once(once, [] {
        omerr().disable();
        omlog().disable();
        omout().disable();
    });
}

std::string lower(std::string s) {
    for (char &c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// ---------------------------------------------------------------------------
// Pre-scan. OpenMesh's readers trust header counts (they reserve and loop
// from them), silently turn "nan" into a failed stream, and drop bad faces
// with a message on omerr only. We therefore check headers, coordinates and
// indices of text formats ourselves first, where a line and column can be named.
// ---------------------------------------------------------------------------

/// A text file split into lines on demand, tracking 1-based line numbers.
class LineReader {
public:
    explicit LineReader(const std::string &text) : m_text(text) {}
    /// Next line (without '\n'); false at the end.
    bool next(std::string_view &line) {
        if (m_pos >= m_text.size()) return false;
        size_t end = m_text.find('\n', m_pos);
        if (end == std::string::npos) end = m_text.size();
        line = std::string_view(m_text).substr(m_pos, end - m_pos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        m_pos = end + 1;
        ++m_line;
        return true;
    }
    int lineNumber() const { return m_line; }
    size_t remainingBytes() const { return m_pos >= m_text.size() ? 0 : m_text.size() - m_pos; }

private:
    const std::string &m_text;
    size_t m_pos = 0;
    int m_line = 0;
};

struct Token {
    std::string_view text;
    int col = 0; // 1-based
};

std::vector<Token> tokenize(std::string_view line) {
    std::vector<Token> tokens;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        if (i >= line.size()) break;
        size_t j = i;
        while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
        tokens.push_back({line.substr(i, j - i), int(i) + 1});
        i = j;
    }
    return tokens;
}

bool parseDouble(std::string_view s, double &value) {
    // from_chars accepts "nan" and "inf" too, which we want to see (and reject).
    const char *begin = s.data(), *end = s.data() + s.size();
    if (begin != end && *begin == '+') ++begin;
    auto [ptr, ec] = std::from_chars(begin, end, value);
    return !s.empty() && ptr == end && (ec == std::errc() || ec == std::errc::result_out_of_range);
}

bool parseInt64(std::string_view s, int64_t &value) {
    const char *begin = s.data(), *end = s.data() + s.size();
    if (begin != end && *begin == '+') ++begin;
    auto [ptr, ec] = std::from_chars(begin, end, value);
    return !s.empty() && ptr == end && ec == std::errc();
}

bool isBlankOrComment(std::string_view line) {
    for (char c : line) {
        if (c == '#') return true;
        if (!std::isspace(static_cast<unsigned char>(c))) return false;
    }
    return true;
}

/// Checks that tokens[first..first+3) are finite numbers; throws at the offending column.
void checkCoordinates(const std::string &path, int line, const std::vector<Token> &tokens,
                      size_t first, int64_t vertex) {
    if (tokens.size() < first + 3)
        throw InputError(FileLoc{path, line, 1},
                         "vertex " + std::to_string(vertex) + " has fewer than 3 coordinates",
                         "write x y z on each vertex line");
    for (size_t k = first; k < first + 3; ++k) {
        double x;
        if (!parseDouble(tokens[k].text, x))
            throw InputError(FileLoc{path, line, tokens[k].col},
                             "expected a coordinate, found '" + std::string(tokens[k].text) + "'",
                             "vertex lines hold numbers");
        if (!std::isfinite(x))
            throw InputError(FileLoc{path, line, tokens[k].col},
                             "vertex " + std::to_string(vertex) + " has a non-finite coordinate '" +
                                 std::string(tokens[k].text) + "'",
                             "every coordinate must be a finite number");
    }
}

void checkFaceCount(const std::string &path, int line, int64_t nFaces, const LoadOptions &options) {
    if (nFaces > options.maxFaces)
        throw InputError(FileLoc{path, line, 1},
                         "the file has " + std::to_string(nFaces) + " faces, more than the limit of " +
                             std::to_string(options.maxFaces),
                         "simplify the mesh or raise the face limit");
}

/// OpenMesh's OFF reader parses numbers straight off the stream, so a comment
/// after the header line would be misread as data: name it instead.
bool isBlankOffLine(const std::string &path, int lineNumber, std::string_view line) {
    if (!isBlankOrComment(line)) return false;
    if (line.find('#') != std::string_view::npos)
        throw InputError(FileLoc{path, lineNumber, int(line.find('#')) + 1},
                         "comments after the OFF header are not supported",
                         "remove the '#' lines");
    return true;
}

void prescanOff(const std::string &path, const std::string &text, const LoadOptions &options) {
    LineReader reader(text);
    std::string_view line;
    if (!reader.next(line) || line.find("OFF") == std::string_view::npos)
        throw InputError(FileLoc{path, 1, 1}, "expected an OFF header line ('OFF')",
                         "the first line of an .off file is 'OFF'");
    if (line.find("BINARY") != std::string_view::npos) {
        // Binary OFF: three 32-bit counts follow the header line.
        size_t start = size_t(line.data() + line.size() - text.data()) + 1;
        if (text.size() < start + 12)
            throw InputError(FileLoc{path, 2, 1}, "binary OFF header is truncated");
        uint32_t counts[3];
        std::memcpy(counts, text.data() + start, 12);
        checkFaceCount(path, 2, counts[1], options);
        uint64_t need = uint64_t(counts[0]) * 12 + uint64_t(counts[1]) * 16;
        if (need > text.size() - start - 12)
            throw InputError(FileLoc{path, 2, 1},
                             "header says " + std::to_string(counts[0]) + " vertices and " +
                                 std::to_string(counts[1]) + " faces but the file is only " +
                                 std::to_string(text.size()) + " bytes",
                             "the file is truncated or its header is wrong");
        return;
    }
    // Counts line (the first non-comment line after the header).
    std::vector<Token> tok;
    int countsLine = 0;
    while (reader.next(line)) {
        if (isBlankOffLine(path, reader.lineNumber(), line)) continue;
        tok = tokenize(line);
        countsLine = reader.lineNumber();
        break;
    }
    int64_t nV = -1, nF = -1;
    if (countsLine == 0 || tok.size() < 2 || !parseInt64(tok[0].text, nV) ||
        !parseInt64(tok[1].text, nF) || nV < 0 || nF < 0)
        throw InputError(FileLoc{path, std::max(countsLine, 2), 1},
                         "expected the vertex, face and edge counts",
                         "the line after 'OFF' reads e.g. '8 6 0'");
    checkFaceCount(path, countsLine, nF, options);
    // The shortest possible vertex line is "0 0 0\n" and face line "3 0 1 2\n".
    const uint64_t minBytes = uint64_t(nV) * 6 + uint64_t(nF) * 8;
    if (nV > std::numeric_limits<int>::max() || minBytes > reader.remainingBytes() + 1)
        throw InputError(FileLoc{path, countsLine, 1},
                         "header says " + std::to_string(nV) + " vertices and " +
                             std::to_string(nF) + " faces but the rest of the file is only " +
                             std::to_string(reader.remainingBytes()) + " bytes",
                         "the file is truncated or its header is wrong");
    int64_t v = 0;
    while (v < nV && reader.next(line)) {
        if (isBlankOffLine(path, reader.lineNumber(), line)) continue;
        checkCoordinates(path, reader.lineNumber(), tokenize(line), 0, v);
        ++v;
    }
    int64_t f = 0;
    while (f < nF && reader.next(line)) {
        if (isBlankOffLine(path, reader.lineNumber(), line)) continue;
        tok = tokenize(line);
        int64_t n = 0;
        if (!parseInt64(tok[0].text, n) || n < 0 || int64_t(tok.size()) < n + 1)
            throw InputError(FileLoc{path, reader.lineNumber(), tok[0].col},
                             "face " + std::to_string(f) + " could not be parsed",
                             "a face line reads 'n i1 ... in'");
        for (int64_t k = 1; k <= n; ++k) {
            int64_t idx;
            if (!parseInt64(tok[k].text, idx) || idx < 0 || idx >= nV)
                throw InputError(FileLoc{path, reader.lineNumber(), tok[k].col},
                                 "face " + std::to_string(f) + " uses vertex index '" +
                                     std::string(tok[k].text) + "' outside [0, " +
                                     std::to_string(nV) + ")",
                                 "indices in OFF files start at 0");
        }
        ++f;
    }
    if (v < nV || f < nF)
        throw InputError(FileLoc{path, countsLine, 1},
                         "header says " + std::to_string(nV) + " vertices and " +
                             std::to_string(nF) + " faces but the file holds only " +
                             std::to_string(v) + " and " + std::to_string(f),
                         "the file is truncated or its header is wrong");
}

void prescanObj(const std::string &path, const std::string &text, const LoadOptions &options) {
    LineReader reader(text);
    std::string_view line;
    int64_t nV = 0, nF = 0;
    while (reader.next(line)) {
        std::vector<Token> tok = tokenize(line);
        if (tok.empty()) continue;
        if (tok[0].text == "v") {
            checkCoordinates(path, reader.lineNumber(), tok, 1, nV);
            ++nV;
        } else if (tok[0].text == "f") {
            for (size_t k = 1; k < tok.size(); ++k) {
                std::string_view s = tok[k].text.substr(0, tok[k].text.find('/'));
                int64_t idx;
                if (!parseInt64(s, idx) || idx == 0 || idx > nV || idx < -nV)
                    throw InputError(FileLoc{path, reader.lineNumber(), tok[k].col},
                                     "face uses vertex index '" + std::string(s) +
                                         "' but only " + std::to_string(nV) +
                                         " vertices are defined before it",
                                     "OBJ indices start at 1 (negative ones count back)");
            }
            if (++nF > options.maxFaces) checkFaceCount(path, reader.lineNumber(), nF, options);
        }
    }
}

void prescanStl(const std::string &path, const std::string &text, const LoadOptions &options) {
    // OpenMesh decides "binary" purely from the size, so we do the same.
    if (text.size() >= 84) {
        uint32_t n;
        std::memcpy(&n, text.data() + 80, 4);
        if (text.size() == 84 + 50 * uint64_t(n)) {
            checkFaceCount(path, 0, n, options);
            // Its vertex welding compares floats in a std::map: a NaN breaks the
            // ordering (undefined behaviour), so non-finite values never get there.
            for (uint32_t t = 0; t < n; ++t)
                for (int k = 0; k < 9; ++k) {
                    float x;
                    std::memcpy(&x, text.data() + 84 + 50 * size_t(t) + 12 + 4 * k, 4);
                    if (!std::isfinite(x))
                        throw InputError(FileLoc{path},
                                         "triangle " + std::to_string(t) +
                                             " has a non-finite vertex coordinate",
                                         "every coordinate must be a finite number");
                }
            return;
        }
    }
    LineReader reader(text);
    std::string_view line;
    bool first = true;
    int64_t nF = 0, nVertex = 0;
    while (reader.next(line)) {
        std::vector<Token> tok = tokenize(line);
        if (tok.empty()) continue;
        if (first) {
            if (lower(std::string(tok[0].text)) != "solid")
                throw InputError(FileLoc{path, reader.lineNumber(), 1},
                                 "neither ASCII STL (no 'solid' keyword) nor binary STL (size " +
                                     std::to_string(text.size()) + " is not 84 + 50 n bytes)",
                                 "the file is damaged or not an STL file");
            first = false;
            continue;
        }
        std::string key = lower(std::string(tok[0].text));
        if (key == "facet") {
            if (++nF > options.maxFaces) checkFaceCount(path, reader.lineNumber(), nF, options);
        } else if (key == "vertex") {
            checkCoordinates(path, reader.lineNumber(), tok, 1, nVertex++);
        }
    }
    if (first) throw InputError(FileLoc{path}, "the file is empty", "export the mesh again");
}

struct PlyElement {
    std::string name;
    int64_t count = 0;
    int64_t minBytes = 0; // per element, as ASCII or binary
    std::vector<std::string> properties;
};

int plyTypeSize(const std::string &t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" ||
        t == "float32")
        return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

void prescanPly(const std::string &path, const std::string &text, const LoadOptions &options) {
    LineReader reader(text);
    std::string_view line;
    if (!reader.next(line) || tokenize(line).empty() || tokenize(line)[0].text != "ply")
        throw InputError(FileLoc{path, 1, 1}, "expected a PLY header ('ply')",
                         "the first line of a .ply file is 'ply'");
    bool ascii = true, ended = false;
    std::vector<PlyElement> elements;
    while (reader.next(line)) {
        std::vector<Token> tok = tokenize(line);
        if (tok.empty()) continue;
        const int ln = reader.lineNumber();
        if (tok[0].text == "format" && tok.size() >= 2) {
            ascii = tok[1].text == "ascii";
        } else if (tok[0].text == "element") {
            PlyElement e;
            if (tok.size() < 3 || !parseInt64(tok[2].text, e.count) || e.count < 0)
                throw InputError(FileLoc{path, ln, 1}, "expected 'element NAME COUNT'");
            e.name = std::string(tok[1].text);
            if (e.name == "face") checkFaceCount(path, ln, e.count, options);
            elements.push_back(e);
        } else if (tok[0].text == "property" && !elements.empty()) {
            PlyElement &e = elements.back();
            if (tok.size() >= 5 && tok[1].text == "list") {
                // The smallest list is a triangle.
                e.minBytes += ascii ? 8 : plyTypeSize(std::string(tok[2].text)) +
                                              3 * plyTypeSize(std::string(tok[3].text));
                e.properties.emplace_back(tok[4].text);
            } else if (tok.size() >= 3) {
                e.minBytes += ascii ? 2 : plyTypeSize(std::string(tok[1].text));
                e.properties.emplace_back(tok[2].text);
            }
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
    // ASCII vertices come first in every file we know of; check x, y, z there.
    if (!ascii || elements.empty() || elements[0].name != "vertex") return;
    const std::vector<std::string> &props = elements[0].properties;
    const auto at = [&](const char *n) {
        return size_t(std::find(props.begin(), props.end(), n) - props.begin());
    };
    const size_t ix = at("x"), iy = at("y"), iz = at("z");
    if (ix >= props.size() || iy >= props.size() || iz >= props.size()) return;
    int64_t v = 0;
    while (v < elements[0].count && reader.next(line)) {
        std::vector<Token> tok = tokenize(line);
        if (tok.empty()) continue;
        for (size_t k : {ix, iy, iz}) {
            double x;
            if (k >= tok.size() || !parseDouble(tok[k].text, x) || !std::isfinite(x))
                throw InputError(FileLoc{path, reader.lineNumber(),
                                         k < tok.size() ? tok[k].col : 1},
                                 "vertex " + std::to_string(v) +
                                     " has a missing or non-finite coordinate",
                                 "every coordinate must be a finite number");
        }
        ++v;
    }
}

std::string readWholeFile(const std::string &path) {
    std::error_code ec;
    fs::file_status st = fs::status(path, ec);
    if (ec || !fs::exists(st)) throw IoError(path, "no such file");
    if (fs::is_directory(st)) throw IoError(path, "is a folder, expected a mesh file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(path, "cannot open the file for reading");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw IoError(path, "reading failed");
    return text;
}

// ---------------------------------------------------------------------------
// Repair helpers.
// ---------------------------------------------------------------------------

struct UnionFind {
    std::vector<int> parent;
    explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    // The smaller id becomes the root so results do not depend on call order.
    void unite(int a, int b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

uint64_t edgeKey(int a, int b) {
    if (a > b) std::swap(a, b);
    return (uint64_t(uint32_t(a)) << 32) | uint32_t(b);
}

/// Incident faces of every undirected edge, in face order.
struct EdgeFaces {
    std::vector<uint64_t> keys;      // sorted unique edge keys
    std::vector<int> offset, faces;  // CSR: faces of keys[i] at offset[i]..offset[i+1]
};

EdgeFaces buildEdgeFaces(const std::vector<Face> &tris) {
    std::vector<std::pair<uint64_t, int>> all;
    all.reserve(3 * tris.size());
    for (int f = 0; f < int(tris.size()); ++f)
        for (int k = 0; k < 3; ++k) all.push_back({edgeKey(tris[f][k], tris[f][(k + 1) % 3]), f});
    std::sort(all.begin(), all.end());
    EdgeFaces ef;
    for (size_t i = 0; i < all.size(); ++i) {
        if (i == 0 || all[i].first != all[i - 1].first) {
            ef.keys.push_back(all[i].first);
            ef.offset.push_back(int(i));
        }
        ef.faces.push_back(all[i].second);
    }
    ef.offset.push_back(int(all.size()));
    return ef;
}

int cornerOf(const Face &t, int v) { return t[0] == v ? 0 : t[1] == v ? 1 : 2; }

/// True if face t runs a -> b (rather than b -> a).
bool runs(const Face &t, int a, int b) {
    for (int k = 0; k < 3; ++k)
        if (t[k] == a && t[(k + 1) % 3] == b) return true;
    return false;
}

/// Splits vertices so that around each vertex the faces form a single fan
/// connected through manifold edges. Edges with more than two faces join only
/// one pair of faces (the first consistently oriented pair, else the first two);
/// the others are cut loose along that edge. Returns the number of vertices
/// whose corners fell into more than one group under the given joining rule.
int splitVertices(std::vector<Vec3> &positions, std::vector<Face> &tris, bool cutEdges,
                  int *nNonManifoldEdges) {
    const int nF = int(tris.size());
    EdgeFaces ef = buildEdgeFaces(tris);
    UnionFind uf(3 * nF);
    int nBad = 0;
    for (size_t e = 0; e < ef.keys.size(); ++e) {
        const int *fs = ef.faces.data() + ef.offset[e];
        const int n = ef.offset[e + 1] - ef.offset[e];
        const int a = int(ef.keys[e] >> 32), b = int(ef.keys[e] & 0xffffffffu);
        auto join = [&](int f, int g) {
            uf.unite(3 * f + cornerOf(tris[f], a), 3 * g + cornerOf(tris[g], a));
            uf.unite(3 * f + cornerOf(tris[f], b), 3 * g + cornerOf(tris[g], b));
        };
        if (n == 2) join(fs[0], fs[1]);
        if (n > 2) {
            ++nBad;
            if (!cutEdges) {
                for (int i = 1; i < n; ++i) join(fs[0], fs[i]);
            } else {
                int partner = 1;
                const bool dir0 = runs(tris[fs[0]], a, b);
                for (int i = 1; i < n; ++i)
                    if (runs(tris[fs[i]], a, b) != dir0) {
                        partner = i;
                        break;
                    }
                join(fs[0], fs[partner]);
            }
        }
    }
    if (nNonManifoldEdges) *nNonManifoldEdges = nBad;
    // One vertex per (vertex, corner group); the first group keeps the old index.
    std::vector<int> groupVertex(3 * nF, -1);
    std::vector<int> firstRoot(positions.size(), -1);
    std::vector<uint8_t> counted(positions.size(), 0);
    int nSplit = 0;
    for (int c = 0; c < 3 * nF; ++c) {
        int r = uf.find(c);
        int v = tris[c / 3][c % 3];
        if (groupVertex[r] < 0) {
            if (firstRoot[v] < 0) {
                firstRoot[v] = r;
                groupVertex[r] = v;
            } else {
                groupVertex[r] = int(positions.size());
                positions.push_back(positions[v]);
                if (!counted[v]) {
                    counted[v] = 1;
                    ++nSplit;
                }
            }
        }
        tris[c / 3][c % 3] = groupVertex[r];
    }
    return nSplit;
}

void report(const std::string &name, const LoadOptions &options, const char *kind, int count,
            const std::string &what, const std::string &treatment) {
    if (count == 0) return;
    if (!options.repair)
        throw InputError(FileLoc{name}, std::to_string(count) + " " + what,
                         "fix the file or load it with repair enabled");
    rosy::warn(name, kind, std::to_string(count) + " " + what + ": " + treatment);
}

} // namespace

Mesh repairAndBuild(std::vector<Vec3> positions, const std::vector<std::vector<int>> &polygons,
                    const std::string &name, const LoadOptions &options, LoadReport *reportOut) {
    LoadReport rep;
    const FileLoc loc{name};
    const int nV0 = int(positions.size());
    for (int v = 0; v < nV0; ++v)
        if (!positions[v].allFinite())
            throw InputError(loc, "vertex " + std::to_string(v) + " has a non-finite coordinate",
                             "every coordinate must be a finite number");
    if (int64_t(polygons.size()) > options.maxFaces)
        throw InputError(loc,
                         "the mesh has " + std::to_string(polygons.size()) +
                             " faces, more than the limit of " + std::to_string(options.maxFaces),
                         "simplify the mesh or raise the face limit");

    // 1. Fan triangulation after removing consecutive repeats.
    std::vector<Face> tris;
    tris.reserve(polygons.size());
    std::vector<int> poly;
    for (size_t p = 0; p < polygons.size(); ++p) {
        for (int idx : polygons[p])
            if (idx < 0 || idx >= nV0)
                throw InputError(loc,
                                 "face " + std::to_string(p) + " uses vertex index " +
                                     std::to_string(idx) + " outside [0, " + std::to_string(nV0) +
                                     ")",
                                 "fix the face's indices");
        poly.clear();
        for (int idx : polygons[p])
            if (poly.empty() || poly.back() != idx) poly.push_back(idx);
        while (poly.size() > 1 && poly.back() == poly.front()) poly.pop_back();
        if (poly.size() < 3) {
            ++rep.degenerateFacesDropped;
            continue;
        }
        if (poly.size() > 3) ++rep.polygonsTriangulated;
        for (size_t k = 1; k + 1 < poly.size(); ++k) tris.push_back({poly[0], poly[k], poly[k + 1]});
    }

    // 2. Merge vertices with identical coordinates (smallest index wins).
    std::vector<int> order(nV0);
    std::iota(order.begin(), order.end(), 0);
    auto less = [&](int a, int b) {
        const Vec3 &p = positions[a], &q = positions[b];
        if (p.x() != q.x()) return p.x() < q.x();
        if (p.y() != q.y()) return p.y() < q.y();
        if (p.z() != q.z()) return p.z() < q.z();
        return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<int> rep0(nV0);
    for (int i = 0; i < nV0; ++i) {
        if (i > 0 && positions[order[i]] == positions[order[i - 1]]) {
            rep0[order[i]] = rep0[order[i - 1]];
            ++rep.duplicateVerticesMerged;
        } else {
            rep0[order[i]] = order[i];
        }
    }
    for (Face &t : tris)
        for (int &v : t) v = rep0[v];

    // 3. Drop faces with a repeated vertex or (numerically) zero area. The area
    // test is relative to the longest edge so that it does not depend on scale.
    std::vector<Face> kept;
    kept.reserve(tris.size());
    for (const Face &t : tris) {
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            ++rep.degenerateFacesDropped;
            continue;
        }
        const Vec3 &a = positions[t[0]], &b = positions[t[1]], &c = positions[t[2]];
        double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
        if ((b - a).cross(c - a).norm() <= 1e-12 * longest) {
            ++rep.degenerateFacesDropped;
            continue;
        }
        kept.push_back(t);
    }
    tris.swap(kept);

    // 4. Duplicate faces (same vertex set, either orientation): keep the first.
    {
        std::vector<std::pair<std::array<int, 3>, int>> sorted(tris.size());
        for (int f = 0; f < int(tris.size()); ++f) {
            std::array<int, 3> s = tris[f];
            std::sort(s.begin(), s.end());
            sorted[f] = {s, f};
        }
        std::sort(sorted.begin(), sorted.end());
        std::vector<uint8_t> drop(tris.size(), 0);
        for (size_t i = 1; i < sorted.size(); ++i)
            if (sorted[i].first == sorted[i - 1].first) {
                drop[sorted[i].second] = 1;
                ++rep.duplicateFacesDropped;
            }
        kept.clear();
        for (int f = 0; f < int(tris.size()); ++f)
            if (!drop[f]) kept.push_back(tris[f]);
        tris.swap(kept);
    }

    // Report the simple repairs before the topological ones, so that with
    // repair disabled the first problem found in the file is the one named.
    report(name, options, "degenerate-faces", rep.degenerateFacesDropped,
           "faces with a repeated vertex or zero area", "dropped");
    report(name, options, "duplicate-vertices", rep.duplicateVerticesMerged,
           "vertices with identical coordinates", "merged");
    report(name, options, "duplicate-faces", rep.duplicateFacesDropped,
           "duplicate faces (same vertices)", "dropped");

    // 5. Isolated vertices: those no face uses (merged duplicates do not count).
    std::vector<uint8_t> used(nV0, 0);
    for (const Face &t : tris)
        for (int v : t) used[v] = 1;
    for (int v = 0; v < nV0; ++v)
        if (!used[v] && rep0[v] == v) ++rep.isolatedVerticesDropped;
    report(name, options, "isolated-vertices", rep.isolatedVerticesDropped,
           "vertices not used by any face", "dropped");

    if (tris.empty())
        throw InputError(loc, "the mesh has no faces" +
                                  std::string(polygons.empty() ? "" : " left after dropping degenerate ones"),
                         "a surface mesh needs at least one triangle");

    // 6. Non-manifold edges and vertices. A first pass that joins every face on
    // an edge tells which vertices are genuinely pinched (several fans); the
    // second pass also cuts edges with more than two faces.
    {
        std::vector<Vec3> probePositions = positions;
        std::vector<Face> probe = tris;
        int nBadEdges = 0;
        rep.nonManifoldVerticesSplit = splitVertices(probePositions, probe, false, &nBadEdges);
        rep.nonManifoldEdgesSplit = nBadEdges;
    }
    report(name, options, "nonmanifold-edges", rep.nonManifoldEdgesSplit,
           "edges shared by more than two faces", "extra faces split off onto duplicated vertices");
    report(name, options, "nonmanifold-vertices", rep.nonManifoldVerticesSplit,
           "non-manifold vertices (several fans)", "duplicated once per fan");
    if (rep.nonManifoldEdgesSplit > 0 || rep.nonManifoldVerticesSplit > 0) {
        int remaining = 0;
        splitVertices(positions, tris, true, &remaining);
        if (remaining > 0) {
            // A cut face can still meet its edge through other faces around both
            // ends; detach such faces completely, then split fans again.
            EdgeFaces ef = buildEdgeFaces(tris);
            std::vector<uint8_t> detach(tris.size(), 0);
            for (size_t e = 0; e < ef.keys.size(); ++e)
                for (int i = ef.offset[e] + 2; i < ef.offset[e + 1]; ++i) detach[ef.faces[i]] = 1;
            for (int f = 0; f < int(tris.size()); ++f)
                if (detach[f])
                    for (int &v : tris[f]) {
                        positions.push_back(positions[v]);
                        v = int(positions.size()) - 1;
                    }
            splitVertices(positions, tris, true, &remaining);
        }
    }

    // 7. Compact: drop unused vertices and re-index in order of first use by index.
    {
        std::vector<int> newIndex(positions.size(), -1);
        for (const Face &t : tris)
            for (int v : t) newIndex[v] = 0;
        std::vector<Vec3> compact;
        compact.reserve(positions.size());
        for (size_t v = 0; v < positions.size(); ++v)
            if (newIndex[v] == 0) {
                newIndex[v] = int(compact.size());
                compact.push_back(positions[v]);
            }
        for (Face &t : tris)
            for (int &v : t) v = newIndex[v];
        positions.swap(compact);
    }

    // 8. Consistent orientation by BFS over manifold edges, per component. The
    // orientation that flips fewer faces wins (ties keep the first face's).
    {
        const int nF = int(tris.size());
        EdgeFaces ef = buildEdgeFaces(tris);
        // Neighbour across each corner's edge (k -> k+1), or -1.
        std::vector<int> nbr(3 * nF, -1);
        for (size_t e = 0; e < ef.keys.size(); ++e) {
            if (ef.offset[e + 1] - ef.offset[e] != 2) continue;
            const int f = ef.faces[ef.offset[e]], g = ef.faces[ef.offset[e] + 1];
            const int a = int(ef.keys[e] >> 32), b = int(ef.keys[e] & 0xffffffffu);
            for (int k = 0; k < 3; ++k) {
                const int x = tris[f][k], y = tris[f][(k + 1) % 3];
                if ((x == a && y == b) || (x == b && y == a)) nbr[3 * f + k] = g;
                const int u = tris[g][k], w = tris[g][(k + 1) % 3];
                if ((u == a && w == b) || (u == b && w == a)) nbr[3 * g + k] = f;
            }
        }
        std::vector<int8_t> flip(nF, -1);
        std::vector<int> queue, comp;
        for (int seed = 0; seed < nF; ++seed) {
            if (flip[seed] >= 0) continue;
            flip[seed] = 0;
            queue.assign(1, seed);
            comp.clear();
            for (size_t qi = 0; qi < queue.size(); ++qi) {
                const int f = queue[qi];
                comp.push_back(f);
                for (int k = 0; k < 3; ++k) {
                    const int g = nbr[3 * f + k];
                    if (g < 0) continue;
                    const int a = tris[f][k], b = tris[f][(k + 1) % 3];
                    // g must run b -> a once both carry their flips.
                    const bool sameDir = runs(tris[g], a, b);
                    const int8_t want = int8_t(sameDir ? !flip[f] : flip[f]);
                    if (flip[g] < 0) {
                        flip[g] = want;
                        queue.push_back(g);
                    } else if (flip[g] != want) {
                        throw InputError(loc,
                                         "the surface is not orientable (a Moebius-like band "
                                         "around face " + std::to_string(f) + ")",
                                         "N-RoSy frames need an orientation; cut the band open "
                                         "or use an orientable surface");
                    }
                }
            }
            int nFlipped = 0;
            for (int f : comp) nFlipped += flip[f];
            if (2 * nFlipped > int(comp.size()))
                for (int f : comp) flip[f] = int8_t(!flip[f]);
            for (int f : comp)
                if (flip[f]) {
                    std::swap(tris[f][1], tris[f][2]);
                    ++rep.facesReoriented;
                }
        }
    }
    report(name, options, "reoriented-faces", rep.facesReoriented,
           "faces with inconsistent orientation", "flipped to agree with their neighbours");

    if (reportOut) *reportOut = rep;
    return Mesh::fromTriangles(std::move(positions), std::move(tris), name);
}

Mesh loadMesh(const std::string &path, const LoadOptions &options, LoadReport *report) {
    const std::string text = readWholeFile(path);
    const std::string ext = lower(fs::path(path).extension().string());
    if (ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".stl")
        throw InputError(FileLoc{path},
                         "unknown mesh format '" + (ext.empty() ? std::string("(none)") : ext) + "'",
                         "use a .obj, .ply, .off or .stl file");
    if (text.find_first_not_of(" \t\r\n") == std::string::npos)
        throw InputError(FileLoc{path}, "the file is empty", "export the mesh again");

    if (ext == ".off") prescanOff(path, text, options);
    else if (ext == ".obj") prescanObj(path, text, options);
    else if (ext == ".stl") prescanStl(path, text, options);
    else prescanPly(path, text, options);

    silenceOpenMesh();
    SoupImporter importer;
    OpenMesh::IO::Options omOptions;
    bool ok;
    {
        // The IOManager singleton and its readers keep per-read state.
        static std::mutex readMutex;
        std::lock_guard<std::mutex> lock(readMutex);
        ok = OpenMesh::IO::IOManager().read(path, importer, omOptions);
    }
    if (!ok)
        throw InputError(FileLoc{path}, "could not be parsed as " + ext.substr(1) + " mesh",
                         "the file is damaged or in another format");
    for (size_t p = 0; p < importer.polygons.size(); ++p)
        if (importer.polygons[p].empty())
            throw InputError(FileLoc{path}, "face " + std::to_string(p) + " could not be parsed",
                             "the file is damaged");
    return repairAndBuild(std::move(importer.positions), importer.polygons, path, options, report);
}

} // namespace rosy::field
