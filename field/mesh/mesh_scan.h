#pragma once
/// \file mesh_scan.h
/// Checked scanning of mesh files, shared by the four readers (internal to the
/// mesh layer): text split into numbered lines and columns, numbers parsed with
/// every failure named at `file:line:col`, and a bounds-checked cursor over
/// binary data, so that no count in a file can make a reader allocate or read
/// past the data it actually holds.

#include "field/mesh/mesh.h"
#include "field/mesh/mesh_io.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rosy::field::detail {

/// Coordinates beyond this are rejected: products of a few of them (areas,
/// squared areas) must stay far from overflow. Documented in docs/meshes.md.
constexpr double kMaxCoordinate = 1e15;

/// What every reader produces: positions (#V, file units, rounded to float) and
/// polygons as lists of 0-based vertex indices (every index already checked to
/// lie in [0, #V)); repairAndBuild() turns it into a Mesh.
struct PolygonSoup {
    std::vector<Vec3> positions;
    std::vector<std::vector<int>> polygons;
};

/// A text file split into lines on demand, tracking 1-based line numbers.
class LineReader {
public:
    explicit LineReader(std::string_view text, size_t start = 0) : m_text(text), m_pos(start) {}
    /// Next line (without '\n' and a trailing '\r'); false at the end.
    bool next(std::string_view &line);
    int lineNumber() const { return m_line; }
    size_t position() const { return m_pos < m_text.size() ? m_pos : m_text.size(); }
    size_t remainingBytes() const { return m_pos >= m_text.size() ? 0 : m_text.size() - m_pos; }

private:
    std::string_view m_text;
    size_t m_pos = 0;
    int m_line = 0;
};

struct Token {
    std::string_view text;
    int col = 0; ///< 1-based
};

/// Splits a line at spaces and tabs into `tokens` (reused between calls).
void tokenize(std::string_view line, std::vector<Token> &tokens);

/// A whole number (optional '+'), the entire token; false otherwise.
bool parseInt64(std::string_view s, int64_t &value);

/// Only white space, or a '#' comment after it.
bool isBlankOrComment(std::string_view line);

/// One coordinate token of vertex `vertex`: a finite number within
/// kMaxCoordinate, rounded to float. \throws InputError at the token.
double coordinate(const std::string &path, int line, const Token &token, int64_t vertex);

/// tokens[first..first+3) as a vertex position. \throws InputError.
Vec3 vertexAt(const std::string &path, int line, const std::vector<Token> &tokens, size_t first,
              int64_t vertex);

/// The checks of coordinate() for a value read in binary; `element` names it
/// ("vertex 12") since there is no column. \throws InputError.
double binaryCoordinate(const std::string &path, double x, const std::string &element);

/// \throws InputError at `line` if nFaces exceeds options.maxFaces.
void checkFaceCount(const std::string &path, int line, int64_t nFaces, const LoadOptions &options);

/// A face corner index token of face `face`, checked against [0, nV); `hint` says
/// where the format's indices start. \throws InputError at the token.
int cornerIndex(const std::string &path, int line, const Token &token, int64_t face, int64_t nV,
                const char *hint);

/// Bytes of a PLY scalar type (char, uchar, ..., float64), 0 for an unknown name.
int plyTypeSize(std::string_view type);

/// Bounds-checked reading of binary mesh data: every read names the element it
/// belongs to when the data ends early, so no count in a file can make us read
/// past its end or loop on garbage.
class BinaryCursor {
public:
    BinaryCursor(const std::string &path, std::string_view data, bool bigEndian)
        : m_path(path), m_data(data), m_swap(bigEndian) {}
    /// The value of PLY/OFF scalar type `type` as a double. \throws InputError
    /// naming `element` if the data ends first.
    double read(std::string_view type, const std::string &element);
    /// A list length or index: must be a whole number in [0, limit].
    /// \throws InputError naming `element` and `what` otherwise.
    int64_t readCount(std::string_view type, int64_t limit, const std::string &element, const char *what);
    /// A whole number in [lo, hi] (signed: the -1 of a triangle strip's restart).
    /// \throws InputError naming `element` and `what` otherwise.
    int64_t readInteger(std::string_view type, int64_t lo, int64_t hi, const std::string &element,
                        const char *what);
    size_t remaining() const { return m_data.size() - m_pos; }

private:
    std::string m_path;
    std::string_view m_data;
    size_t m_pos = 0;
    bool m_swap;
};

/// The four readers (one file each: read_off.cpp, read_obj.cpp, read_ply.cpp,
/// read_stl.cpp). Each parses `text` (the whole file, byte order mark removed)
/// into `soup`, checking counts against the data before allocating.
/// \throws InputError naming `path` with line and column where there are lines.
void readOff(const std::string &path, std::string_view text, const LoadOptions &options, PolygonSoup &soup);
void readObj(const std::string &path, std::string_view text, const LoadOptions &options, PolygonSoup &soup);
void readPly(const std::string &path, std::string_view text, const LoadOptions &options, PolygonSoup &soup);
void readStl(const std::string &path, std::string_view text, const LoadOptions &options, PolygonSoup &soup);

} // namespace rosy::field::detail
