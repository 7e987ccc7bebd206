#include "field/mesh_io.h"

#include "core/diagnostics.h"
#include "core/error.h"
#include "core/input_file.h"

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

std::string lower(std::string s) {
    for (char &c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// ---------------------------------------------------------------------------
// Readers. Text formats (OFF, OBJ, ASCII PLY, ASCII STL) and binary STL are
// parsed here in one pass, so every problem is named at its line and column
// (or triangle number) and nothing is allocated from an unchecked count.
// Binary OFF and PLY too: OpenMesh's readers reserve and loop from header
// counts, hang or crash on lying records (tests/fuzz/*/crashers), turn "nan"
// into a failed stream and drop bad faces with a message on omerr only.
// Coordinates are rounded to 32-bit floats, as OpenMesh stores them, so every
// format gives the same positions whichever reader parsed it.
// ---------------------------------------------------------------------------

/// Coordinates beyond this are rejected: products of a few of them (areas,
/// squared areas) must stay far from overflow. Documented in docs/meshes.md.
constexpr double kMaxCoordinate = 1e15;

/// A text file split into lines on demand, tracking 1-based line numbers.
class LineReader {
public:
    explicit LineReader(std::string_view text, size_t start = 0) : m_text(text), m_pos(start) {}
    /// Next line (without '\n' and a trailing '\r'); false at the end.
    bool next(std::string_view &line) {
        if (m_pos >= m_text.size()) return false;
        size_t end = m_text.find('\n', m_pos);
        if (end == std::string::npos) end = m_text.size();
        line = m_text.substr(m_pos, end - m_pos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        m_pos = end + 1;
        ++m_line;
        return true;
    }
    int lineNumber() const { return m_line; }
    size_t position() const { return std::min(m_pos, m_text.size()); }
    size_t remainingBytes() const { return m_pos >= m_text.size() ? 0 : m_text.size() - m_pos; }

private:
    std::string_view m_text;
    size_t m_pos = 0;
    int m_line = 0;
};

struct Token {
    std::string_view text;
    int col = 0; // 1-based
};

inline bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// Splits a line at spaces and tabs into `tokens` (reused between calls).
void tokenize(std::string_view line, std::vector<Token> &tokens) {
    tokens.clear();
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && isSpace(line[i])) ++i;
        if (i >= line.size()) break;
        size_t j = i;
        while (j < line.size() && !isSpace(line[j])) ++j;
        tokens.push_back({line.substr(i, j - i), int(i) + 1});
        i = j;
    }
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
        if (!isSpace(c)) return false;
    }
    return true;
}

/// One coordinate token: a finite number within kMaxCoordinate, rounded to float.
double coordinate(const std::string &path, int line, const Token &token, int64_t vertex) {
    const char *begin = token.text.data(), *end = begin + token.text.size();
    if (begin != end && *begin == '+') ++begin;
    double x = 0;
    auto [ptr, ec] = std::from_chars(begin, end, x);
    if (token.text.empty() || ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range))
        throw InputError(FileLoc{path, line, token.col},
                         "expected a coordinate, found '" + std::string(token.text) + "'",
                         "vertex lines hold numbers");
    if (!std::isfinite(x) || ec == std::errc::result_out_of_range)
        throw InputError(FileLoc{path, line, token.col},
                         "vertex " + std::to_string(vertex) + " has a non-finite coordinate '" +
                             std::string(token.text) + "'",
                         "every coordinate must be a finite number");
    if (std::abs(x) > kMaxCoordinate)
        throw InputError(FileLoc{path, line, token.col},
                         "vertex " + std::to_string(vertex) + " has an absurd coordinate '" +
                             std::string(token.text) + "' (limit 1e15)",
                         "rescale the mesh; rendering does not depend on its scale");
    return double(float(x));
}

/// Reads tokens[first..first+3) as a vertex position.
Vec3 vertexAt(const std::string &path, int line, const std::vector<Token> &tokens, size_t first,
              int64_t vertex) {
    if (tokens.size() < first + 3)
        throw InputError(FileLoc{path, line, 1},
                         "vertex " + std::to_string(vertex) + " has fewer than 3 coordinates",
                         "write x y z on each vertex line");
    return Vec3(coordinate(path, line, tokens[first], vertex),
                coordinate(path, line, tokens[first + 1], vertex),
                coordinate(path, line, tokens[first + 2], vertex));
}

/// The same checks for a coordinate that arrives in binary (no column to name).
double binaryCoordinate(const std::string &path, double x, const std::string &element) {
    if (!std::isfinite(x))
        throw InputError(FileLoc{path}, element + " has a non-finite coordinate",
                         "every coordinate must be a finite number");
    if (std::abs(x) > kMaxCoordinate)
        throw InputError(FileLoc{path}, element + " has an absurd coordinate (limit 1e15)",
                         "rescale the mesh; rendering does not depend on its scale");
    return double(float(x));
}

void checkFaceCount(const std::string &path, int line, int64_t nFaces, const LoadOptions &options) {
    if (nFaces > options.maxFaces)
        throw InputError(FileLoc{path, line, 1},
                         "the file has " + std::to_string(nFaces) + " faces, more than the limit of " +
                             std::to_string(options.maxFaces),
                         "simplify the mesh or raise the face limit (--max-faces)");
}

/// Comments after the OFF header are not part of the format (OpenMesh misreads
/// them), so a '#' line is named rather than guessed at.
bool isBlankOffLine(const std::string &path, int lineNumber, std::string_view line) {
    if (!isBlankOrComment(line)) return false;
    if (line.find('#') != std::string_view::npos)
        throw InputError(FileLoc{path, lineNumber, int(line.find('#')) + 1},
                         "comments after the OFF header are not supported",
                         "remove the '#' lines");
    return true;
}

/// A face corner index token, checked against [0, nV).
int cornerIndex(const std::string &path, int line, const Token &token, int64_t face, int64_t nV,
                const char *hint) {
    int64_t idx;
    if (!parseInt64(token.text, idx) || idx < 0 || idx >= nV)
        throw InputError(FileLoc{path, line, token.col},
                         "face " + std::to_string(face) + " uses vertex index '" + std::string(token.text) +
                             "' outside [0, " + std::to_string(nV) + ")",
                         hint);
    return int(idx);
}

/// Bounds-checked reading of binary mesh data: every read names the element it
/// belongs to when the data ends early, so no count in a file can make us read
/// past its end or loop on garbage.
class BinaryCursor {
public:
    BinaryCursor(const std::string &path, std::string_view data, bool bigEndian)
        : m_path(path), m_data(data), m_swap(bigEndian) {}

    /// The value of PLY/OFF scalar type `type` (sizes from plyTypeSize) as a double.
    double read(std::string_view type, const std::string &element) {
        const int size = typeSize(type);
        if (m_data.size() - m_pos < size_t(size))
            throw InputError(FileLoc{m_path}, "the file ends inside " + element + " (byte " +
                                                  std::to_string(m_pos) + " of the binary data)",
                             "the file is truncated or its header is wrong");
        unsigned char b[8];
        std::memcpy(b, m_data.data() + m_pos, size_t(size));
        m_pos += size_t(size);
        if (m_swap) std::reverse(b, b + size);
        auto as = [&](auto v) {
            std::memcpy(&v, b, sizeof v);
            return double(v);
        };
        if (type == "char" || type == "int8") return as(int8_t());
        if (type == "uchar" || type == "uint8") return as(uint8_t());
        if (type == "short" || type == "int16") return as(int16_t());
        if (type == "ushort" || type == "uint16") return as(uint16_t());
        if (type == "int" || type == "int32") return as(int32_t());
        if (type == "uint" || type == "uint32") return as(uint32_t());
        if (type == "float" || type == "float32") return as(float());
        return as(double());
    }
    /// A list length or index: must be a whole number in [0, limit].
    int64_t readCount(std::string_view type, int64_t limit, const std::string &element, const char *what) {
        const double v = read(type, element);
        if (!(v >= 0) || v > double(limit) || v != std::floor(v))
            throw InputError(FileLoc{m_path}, element + ": " + what + " " + number(v) + " is out of range [0, " +
                                                  std::to_string(limit) + "]",
                             "the file is damaged or its header is wrong");
        return int64_t(v);
    }
    size_t remaining() const { return m_data.size() - m_pos; }

private:
    static std::string number(double v) {
        if (v == std::floor(v) && std::abs(v) < 9e18) return std::to_string(int64_t(v));
        std::ostringstream os;
        os << v;
        return os.str();
    }
    static int typeSize(std::string_view t);
    std::string m_path;
    std::string_view m_data;
    size_t m_pos = 0;
    bool m_swap;
};

/// Parses OFF, ASCII or binary (Geomview's OFF BINARY: 32-bit little-endian
/// counts, float coordinates, per-face vertex count, indices and colour count).
bool readOff(const std::string &path, std::string_view text, const LoadOptions &options, SoupImporter &soup) {
    LineReader reader(text);
    std::string_view line;
    std::vector<Token> tok;
    if (!reader.next(line)) throw InputError(FileLoc{path, 1, 1}, "expected an OFF header line ('OFF')");
    tokenize(line, tok);
    const std::string_view magic = tok.empty() ? std::string_view() : tok[0].text;
    // ST, C, N, 4 and n prefixes: per-vertex extras after x y z. "4OFF"/"nOFF"
    // change the dimension, which a surface renderer cannot use.
    if (magic.size() < 3 || magic.substr(magic.size() - 3) != "OFF" ||
        magic.substr(0, magic.size() - 3).find_first_not_of("STCN") != std::string_view::npos)
        throw InputError(FileLoc{path, 1, 1},
                         "expected an OFF header line ('OFF'), found '" +
                             std::string(line.substr(0, std::min<size_t>(line.size(), 20))) + "'",
                         "the first line of an .off file is 'OFF' (or COFF, NOFF, STOFF)");
    if (tok.size() >= 2 && tok[1].text == "BINARY") {
        // Binary OFF: three 32-bit counts follow the header line.
        const size_t start = reader.position();
        if (text.size() < start + 12)
            throw InputError(FileLoc{path, 2, 1}, "binary OFF header is truncated",
                             "the file is truncated");
        uint32_t counts[3];
        std::memcpy(counts, text.data() + start, 12);
        checkFaceCount(path, 2, counts[1], options);
        const uint64_t need = uint64_t(counts[0]) * 12 + uint64_t(counts[1]) * 16;
        if (need > text.size() - start - 12)
            throw InputError(FileLoc{path, 2, 1},
                             "header says " + std::to_string(counts[0]) + " vertices and " +
                                 std::to_string(counts[1]) + " faces but the file is only " +
                                 std::to_string(text.size()) + " bytes",
                             "the file is truncated or its header is wrong");
        // Per-vertex extras of the prefixes, in Geomview's order: normal, colour, texture.
        const std::string_view prefix = magic.substr(0, magic.size() - 3);
        const int extras = (prefix.find('N') != std::string_view::npos ? 3 : 0) +
                           (prefix.find('C') != std::string_view::npos ? 4 : 0) +
                           (prefix.find("ST") != std::string_view::npos ? 2 : 0);
        BinaryCursor in(path, text.substr(start + 12), false);
        const int64_t nV = counts[0], nF = counts[1];
        soup.positions.reserve(size_t(nV));
        for (int64_t v = 0; v < nV; ++v) {
            const std::string what = "vertex " + std::to_string(v);
            Vec3 p;
            for (int k = 0; k < 3; ++k) p[k] = binaryCoordinate(path, in.read("float", what), what);
            for (int k = 0; k < extras; ++k) in.read("float", what);
            soup.positions.push_back(p);
        }
        soup.polygons.reserve(size_t(nF));
        for (int64_t f = 0; f < nF; ++f) {
            const std::string what = "face " + std::to_string(f);
            const int64_t n = in.readCount("int", int64_t(in.remaining() / 4), what, "vertex count");
            std::vector<int> poly(static_cast<size_t>(n));
            for (int64_t c = 0; c < n; ++c)
                poly[size_t(c)] = int(in.readCount("int", std::max<int64_t>(nV - 1, 0), what, "vertex index"));
            const int64_t colours = in.readCount("int", 4, what, "colour component count");
            for (int64_t c = 0; c < colours; ++c) in.read("float", what);
            soup.polygons.push_back(std::move(poly));
        }
        return true;
    }
    // Counts: on the header line after OFF, or on the first non-blank line after it.
    int countsLine = 1;
    tok.erase(tok.begin());
    if (tok.empty()) {
        countsLine = 0;
        while (reader.next(line)) {
            if (isBlankOffLine(path, reader.lineNumber(), line)) continue;
            tokenize(line, tok);
            countsLine = reader.lineNumber();
            break;
        }
    }
    int64_t nV = -1, nF = -1;
    if (countsLine == 0 || tok.size() < 2 || !parseInt64(tok[0].text, nV) || !parseInt64(tok[1].text, nF) ||
        nV < 0 || nF < 0)
        throw InputError(FileLoc{path, std::max(countsLine, 2), 1},
                         "expected the vertex, face and edge counts (whole numbers >= 0)",
                         "the line after 'OFF' reads e.g. '8 6 0'");
    checkFaceCount(path, countsLine, nF, options);
    // Reject before allocating: the shortest vertex line is "0 0 0\n", the
    // shortest face line "3 0 1 2\n".
    const uint64_t minBytes = uint64_t(nV) * 6 + uint64_t(nF) * 8;
    if (nV > std::numeric_limits<int>::max() || minBytes > reader.remainingBytes() + 1)
        throw InputError(FileLoc{path, countsLine, 1},
                         "header says " + std::to_string(nV) + " vertices and " + std::to_string(nF) +
                             " faces but the rest of the file is only " +
                             std::to_string(reader.remainingBytes()) + " bytes",
                         "the file is truncated or its header is wrong");
    soup.positions.reserve(size_t(nV));
    soup.polygons.reserve(size_t(nF));
    int64_t v = 0;
    while (v < nV && reader.next(line)) {
        if (isBlankOffLine(path, reader.lineNumber(), line)) continue;
        tokenize(line, tok);
        soup.positions.push_back(vertexAt(path, reader.lineNumber(), tok, 0, v));
        ++v;
    }
    int64_t f = 0;
    while (f < nF && reader.next(line)) {
        if (isBlankOffLine(path, reader.lineNumber(), line)) continue;
        tokenize(line, tok);
        int64_t n = 0;
        if (!parseInt64(tok[0].text, n) || n < 1 || int64_t(tok.size()) < n + 1)
            throw InputError(FileLoc{path, reader.lineNumber(), tok[0].col},
                             "face " + std::to_string(f) + " could not be parsed",
                             "a face line reads 'n i1 ... in'");
        std::vector<int> poly(static_cast<size_t>(n));
        for (int64_t k = 1; k <= n; ++k)
            poly[size_t(k - 1)] = cornerIndex(path, reader.lineNumber(), tok[size_t(k)], f, nV,
                                              "indices in OFF files start at 0");
        soup.polygons.push_back(std::move(poly));
        ++f;
    }
    if (v < nV || f < nF)
        throw InputError(FileLoc{path, countsLine, 1},
                         "header says " + std::to_string(nV) + " vertices and " + std::to_string(nF) +
                             " faces but the file holds only " + std::to_string(v) + " and " +
                             std::to_string(f),
                         "the file is truncated or its header is wrong");
    return true;
}

void readObj(const std::string &path, std::string_view text, const LoadOptions &options, SoupImporter &soup) {
    LineReader reader(text);
    std::string_view line;
    std::vector<Token> tok;
    int64_t nF = 0;
    while (reader.next(line)) {
        tokenize(line, tok);
        if (tok.empty()) continue;
        if (tok[0].text == "v") {
            soup.positions.push_back(vertexAt(path, reader.lineNumber(), tok, 1, int64_t(soup.positions.size())));
        } else if (tok[0].text == "f") {
            const int64_t nV = int64_t(soup.positions.size());
            if (tok.size() < 2)
                throw InputError(FileLoc{path, reader.lineNumber(), 1}, "face without vertices",
                                 "a face line reads 'f i1 i2 i3 ...'");
            std::vector<int> poly(tok.size() - 1);
            for (size_t k = 1; k < tok.size(); ++k) {
                std::string_view s = tok[k].text.substr(0, tok[k].text.find('/'));
                int64_t idx;
                // 1-based; negative indices count back from the last vertex read (OBJ spec).
                if (!parseInt64(s, idx) || idx == 0 || idx > nV || idx < -nV)
                    throw InputError(FileLoc{path, reader.lineNumber(), tok[k].col},
                                     "face uses vertex index '" + std::string(s) + "' but only " +
                                         std::to_string(nV) + " vertices are defined before it",
                                     "OBJ indices start at 1 (negative ones count back)");
                poly[k - 1] = int(idx > 0 ? idx - 1 : nV + idx);
            }
            soup.polygons.push_back(std::move(poly));
            if (++nF > options.maxFaces) checkFaceCount(path, reader.lineNumber(), nF, options);
        }
    }
}

/// Appends corner `p` of an STL triangle, welding bit-identical corners (STL
/// repeats every corner per triangle; welding them is reading, not repair).
struct StlWelder {
    std::unordered_map<uint64_t, std::vector<int>> buckets;
    int add(SoupImporter &soup, const Vec3 &p) {
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

void readStl(const std::string &path, std::string_view text, const LoadOptions &options, SoupImporter &soup) {
    StlWelder welder;
    // Binary exactly when the size is 84 + 50 n (as OpenMesh decides).
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

int plyTypeSize(std::string_view t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32")
        return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

int BinaryCursor::typeSize(std::string_view t) { return plyTypeSize(t); }

/// Parses a PLY header, checks its counts against the file size, and reads
/// its ASCII or binary (either byte order) data.
bool readPly(const std::string &path, std::string_view text, const LoadOptions &options, SoupImporter &soup) {
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
        if (e.properties.empty() && e.name != "vertex" && e.name != "face") continue;
        const auto at = [&](const char *n) {
            for (size_t i = 0; i < e.properties.size(); ++i)
                if (e.properties[i].name == n) return i;
            return e.properties.size();
        };
        const bool isVertex = e.name == "vertex", isFace = e.name == "face";
        const size_t ix = at("x"), iy = at("y"), iz = at("z");
        size_t iFace = at("vertex_indices");
        if (iFace == e.properties.size()) iFace = at("vertex_index");
        if (isVertex && (ix == e.properties.size() || iy == e.properties.size() || iz == e.properties.size()))
            throw InputError(FileLoc{path}, "the vertex element has no x, y and z properties",
                             "add 'property float x' etc.");
        if (isFace && (iFace == e.properties.size() || !e.properties[iFace].list))
            throw InputError(FileLoc{path}, "the face element has no vertex_indices list",
                             "add 'property list uchar int vertex_indices'");
        if (isVertex) soup.positions.reserve(size_t(e.count));
        if (isFace) soup.polygons.reserve(size_t(e.count));
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
                }
                t += 1 + size_t(n);
            }
            if (isVertex) soup.positions.push_back(p);
        }
    }
    return true;
}

/// Meshes are read only from regular files: the readers check header counts against
/// the file's size, which a pipe or a device (a link to /dev/zero) does not have.
std::string readWholeFile(const std::string &path) {
    return readInputFile(path, InputFileRules{"mesh file", std::numeric_limits<size_t>::max(), false});
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
    // Bucket the edges by their smaller vertex (a counting sort), then sort each
    // small bucket by (larger vertex, face): the same order as one global sort of
    // (key, face) pairs, without its cost.
    int nV = 0;
    for (const Face &t : tris) nV = std::max({nV, t[0] + 1, t[1] + 1, t[2] + 1});
    std::vector<int> start(size_t(nV) + 1, 0);
    for (const Face &t : tris)
        for (int k = 0; k < 3; ++k) ++start[size_t(std::min(t[k], t[(k + 1) % 3])) + 1];
    for (int v = 0; v < nV; ++v) start[v + 1] += start[v];
    std::vector<std::pair<int, int>> bucket(3 * tris.size()); // (larger vertex, face)
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int f = 0; f < int(tris.size()); ++f)
        for (int k = 0; k < 3; ++k) {
            const int a = tris[f][k], b = tris[f][(k + 1) % 3];
            bucket[fill[std::min(a, b)]++] = {std::max(a, b), f};
        }
    EdgeFaces ef;
    ef.keys.reserve(bucket.size() / 2 + 1);
    ef.offset.reserve(bucket.size() / 2 + 2);
    ef.faces.reserve(bucket.size());
    for (int v = 0; v < nV; ++v) {
        const auto first = bucket.begin() + start[v], last = bucket.begin() + start[v + 1];
        std::sort(first, last);
        for (auto it = first; it != last; ++it) {
            const uint64_t key = edgeKey(v, it->first);
            if (ef.keys.empty() || ef.keys.back() != key) {
                ef.keys.push_back(key);
                ef.offset.push_back(int(ef.faces.size()));
            }
            ef.faces.push_back(it->second);
        }
    }
    ef.offset.push_back(int(ef.faces.size()));
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
    for (int v = 0; v < nV0; ++v) {
        if (!positions[v].allFinite())
            throw InputError(loc, "vertex " + std::to_string(v) + " has a non-finite coordinate",
                             "every coordinate must be a finite number");
        if (positions[v].cwiseAbs().maxCoeff() > kMaxCoordinate)
            throw InputError(loc, "vertex " + std::to_string(v) + " has an absurd coordinate (limit 1e15)",
                             "rescale the mesh; rendering does not depend on its scale");
    }
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
    const std::string ext = lower(fs::path(path).extension().string());
    if (ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".stl")
        throw InputError(FileLoc{path},
                         "unknown mesh format '" + (ext.empty() ? std::string("(none)") : ext) + "'",
                         "use a .obj, .ply, .off or .stl file");
    const std::string file = readWholeFile(path);
    std::string_view text = file;
    // A UTF-8 byte order mark (some Windows editors write one) is not content.
    const bool bom = text.substr(0, 3) == "\xEF\xBB\xBF";
    if (bom) text.remove_prefix(3);
    if (text.find_first_not_of(" \t\r\n") == std::string::npos)
        throw InputError(FileLoc{path}, "the file is empty", "export the mesh again");

    SoupImporter soup;
    if (ext == ".off") readOff(path, text, options, soup);
    else if (ext == ".obj") readObj(path, text, options, soup);
    else if (ext == ".stl") readStl(path, text, options, soup);
    else readPly(path, text, options, soup);
    return repairAndBuild(std::move(soup.positions), soup.polygons, path, options, report);
}

} // namespace rosy::field
