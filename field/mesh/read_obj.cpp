#include "field/mesh/mesh_scan.h"

#include "core/error.h"


namespace rosy::field::detail {

void readObj(const std::string &path, std::string_view text, const LoadOptions &options, PolygonSoup &soup) {
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

} // namespace rosy::field::detail
