#include "field/mesh/mesh_scan.h"

#include "core/error.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

namespace rosy::field::detail {

bool LineReader::next(std::string_view &line) {
    if (m_pos >= m_text.size()) return false;
    size_t end = m_text.find('\n', m_pos);
    if (end == std::string::npos) end = m_text.size();
    line = m_text.substr(m_pos, end - m_pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    m_pos = end + 1;
    ++m_line;
    return true;
}

namespace {
inline bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
} // namespace

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

int plyTypeSize(std::string_view t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32")
        return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

double BinaryCursor::read(std::string_view type, const std::string &element) {
    const int size = plyTypeSize(type);
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

int64_t BinaryCursor::readCount(std::string_view type, int64_t limit, const std::string &element, const char *what) {
    return readInteger(type, 0, limit, element, what);
}

int64_t BinaryCursor::readInteger(std::string_view type, int64_t lo, int64_t hi, const std::string &element,
                                  const char *what) {
    const double v = read(type, element);
    // fmt's shortest round-trip form: 1e+20 or 2.5 as they are, not 100000000000000000000.000000.
    if (!(v >= double(lo)) || v > double(hi) || v != std::floor(v))
        throw InputError(FileLoc{m_path}, fmt::format("{}: {} {} is out of range [{}, {}]", element, what, v, lo, hi),
                         "the file is damaged or its header is wrong");
    return int64_t(v);
}

} // namespace rosy::field::detail
