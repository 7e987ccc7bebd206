#include "field/mesh/mesh_scan.h"

#include "core/error.h"
#include "core/parallel.h"

#include <algorithm>
#include <cstring>
#include <exception>
#include <limits>

namespace rosy::field::detail {
namespace {

/// The line without its comment: Geomview's OFF lets a '#' begin a comment that
/// runs to the end of the line, on a line of its own or after the values (a face's
/// colour "ends with the end of the line (or the next # comment)"). The CGAL data
/// has both, and comment lines before the header.
std::string_view withoutComment(std::string_view line) {
    const size_t hash = line.find('#');
    return hash == std::string_view::npos ? line : line.substr(0, hash);
}

/// A numbered line of the file.
struct NumberedLine {
    std::string_view text;
    int number = 0;
};

/// Calls parse(i, tokens) for every i in [0, n) in parallel chunks; the first
/// InputError in index order (that is, in file order) is rethrown afterwards, as a
/// loop in order would have thrown it. `parse` writes only its own index.
template <typename Parse>
void parseLinesInParallel(size_t n, Parse &&parse) {
    constexpr int64_t kGrain = 4096;
    const int64_t nChunks = (int64_t(n) + kGrain - 1) / kGrain;
    std::vector<std::exception_ptr> errors(static_cast<size_t>(nChunks));
    parallelFor(0, nChunks, [&](int64_t c) {
        std::vector<Token> tok;
        const size_t end = std::min(n, size_t(c + 1) * size_t(kGrain));
        try {
            for (size_t i = size_t(c) * size_t(kGrain); i < end; ++i) parse(i, tok);
        } catch (const InputError &) {
            errors[size_t(c)] = std::current_exception(); // the chunk's first; later chunks' come after it
        }
    }, 1);
    for (const std::exception_ptr &e : errors)
        if (e) std::rethrow_exception(e);
}

} // namespace

/// Parses OFF, ASCII or binary (Geomview's OFF BINARY: 32-bit little-endian
/// counts, float coordinates, per-face vertex count, indices and colour count).
void readOff(const std::string &path, std::string_view text, const LoadOptions &options, PolygonSoup &soup) {
    LineReader reader(text);
    std::string_view line;
    std::vector<Token> tok;
    // Blank and comment lines may come before the header.
    bool found = false;
    while (!found && reader.next(line)) found = !isBlankOrComment(line);
    if (!found)
        throw InputError(FileLoc{path, 1, 1}, "expected an OFF header line ('OFF'), found only blank or comment lines",
                         "an .off file holds 'OFF', the counts, the vertices and the faces");
    const int headerLine = reader.lineNumber();
    line = withoutComment(line);
    tokenize(line, tok);
    const std::string_view magic = tok.empty() ? std::string_view() : tok[0].text;
    // ST, C, N, 4 and n prefixes: per-vertex extras after x y z. "4OFF"/"nOFF"
    // change the dimension, which a surface renderer cannot use.
    if (magic.size() < 3 || magic.substr(magic.size() - 3) != "OFF" ||
        magic.substr(0, magic.size() - 3).find_first_not_of("STCN") != std::string_view::npos)
        throw InputError(FileLoc{path, headerLine, 1},
                         "expected an OFF header line ('OFF'), found '" +
                             std::string(line.substr(0, std::min<size_t>(line.size(), 20))) + "'",
                         "the first line of an .off file is 'OFF' (or COFF, NOFF, STOFF)");
    if (tok.size() >= 2 && tok[1].text == "BINARY") {
        // Binary OFF: three 32-bit counts follow the header line.
        const size_t start = reader.position();
        if (text.size() < start + 12)
            throw InputError(FileLoc{path, headerLine + 1, 1}, "binary OFF header is truncated",
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
        return;
    }
    // Counts: on the header line after OFF, or on the first non-blank line after it.
    int countsLine = headerLine;
    tok.erase(tok.begin());
    if (tok.empty()) {
        countsLine = 0;
        while (reader.next(line)) {
            if (isBlankOrComment(line)) continue;
            tokenize(withoutComment(line), tok);
            countsLine = reader.lineNumber();
            break;
        }
    }
    int64_t nV = -1, nF = -1;
    if (countsLine == 0 || tok.size() < 2 || !parseInt64(tok[0].text, nV) || !parseInt64(tok[1].text, nF) ||
        nV < 0 || nF < 0)
        throw InputError(FileLoc{path, std::max(countsLine, headerLine + 1), 1},
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
    // The vertex and face lines, in order, up to the counts (blank and comment lines
    // skipped, trailing comments cut); then parsed in parallel.
    std::vector<NumberedLine> lines;
    lines.reserve(size_t(std::min<int64_t>(nV + nF, int64_t(reader.remainingBytes() / 6 + 1))));
    while (int64_t(lines.size()) < nV + nF && reader.next(line)) {
        if (isBlankOrComment(line)) continue;
        lines.push_back({withoutComment(line), reader.lineNumber()});
    }
    const int64_t v = std::min<int64_t>(nV, int64_t(lines.size()));
    const int64_t f = int64_t(lines.size()) - v;
    soup.positions.resize(size_t(v));
    parseLinesInParallel(size_t(v), [&](size_t i, std::vector<Token> &tok) {
        tokenize(lines[i].text, tok);
        soup.positions[i] = vertexAt(path, lines[i].number, tok, 0, int64_t(i));
    });
    soup.polygons.resize(size_t(f));
    parseLinesInParallel(size_t(f), [&](size_t i, std::vector<Token> &tok) {
        const NumberedLine &l = lines[size_t(v) + i];
        tokenize(l.text, tok);
        int64_t n = 0;
        if (!parseInt64(tok[0].text, n) || n < 1 || int64_t(tok.size()) < n + 1)
            throw InputError(FileLoc{path, l.number, tok[0].col},
                             "face " + std::to_string(i) + " could not be parsed",
                             "a face line reads 'n i1 ... in'");
        std::vector<int> &poly = soup.polygons[i];
        poly.resize(static_cast<size_t>(n));
        for (int64_t k = 1; k <= n; ++k)
            poly[size_t(k - 1)] = cornerIndex(path, l.number, tok[size_t(k)], int64_t(i), nV,
                                              "indices in OFF files start at 0");
    });
    if (v < nV || f < nF)
        throw InputError(FileLoc{path, countsLine, 1},
                         "header says " + std::to_string(nV) + " vertices and " + std::to_string(nF) +
                             " faces but the file holds only " + std::to_string(v) + " and " +
                             std::to_string(f),
                         "the file is truncated or its header is wrong");
}

} // namespace rosy::field::detail
