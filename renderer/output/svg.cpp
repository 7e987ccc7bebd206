/// \file svg.cpp
/// Layered SVG writer (see svg.h).

#include "renderer/output/svg.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <tuple>

namespace rosy::renderer {

namespace {

/// A plotter and Inkscape read at most this many vertices per path comfortably.
constexpr size_t kMaxPathVertices = 32000;

/// Fixed 3 decimals (µm on the page) with trailing zeros trimmed: byte-identical
/// across runs and platforms, and "210" rather than "210.000" for page sizes.
void appendNumber(std::string &out, double x) {
    // Every number written is a page coordinate or width in mm, at most
    // kMaxPaperSideMm plus a margin; anything else is a bug, not a truncated number.
    if (std::isfinite(x) && !(std::abs(x) < 1e12)) ROSY_CHECK(!"SVG number out of range");
    char buf[64];
    const int n = std::snprintf(buf, sizeof buf, "%.3f", x);
    ROSY_CHECK(n > 0 && n < int(sizeof buf));
    std::string s(buf);
    if (s.find('.') != std::string::npos) {
        while (s.back() == '0') s.pop_back();
        if (s.back() == '.') s.pop_back();
    }
    if (s == "-0") s = "0";
    out += s;
}

std::string number(double x) {
    std::string s;
    appendNumber(s, x);
    return s;
}

int layerOf(const Stroke &s) {
    switch (s.kind) {
    case StrokeKind::Hatch: return s.family == 1 ? 1 : 0;
    case StrokeKind::Contour: return 2;
    case StrokeKind::HiddenContour: return 3;
    }
    return 2;
}

} // namespace

std::optional<std::pair<double, double>> parsePaperSize(const std::string &name) {
    std::string lower = name;
    for (char &c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (lower == "a4") return std::pair{210.0, 297.0};
    if (lower == "a3") return std::pair{297.0, 420.0};
    if (lower == "letter") return std::pair{215.9, 279.4};
    const size_t x = lower.find('x');
    if (x == std::string::npos || x == 0 || x + 1 >= lower.size()) return std::nullopt;
    try {
        size_t usedW = 0, usedH = 0;
        const std::string ws = lower.substr(0, x), hs = lower.substr(x + 1);
        const double w = std::stod(ws, &usedW), h = std::stod(hs, &usedH);
        if (usedW != ws.size() || usedH != hs.size()) return std::nullopt;
        if (!(w >= kMinPaperSideMm && w <= kMaxPaperSideMm) || !(h >= kMinPaperSideMm && h <= kMaxPaperSideMm))
            return std::nullopt;
        return std::pair{w, h};
    } catch (const std::exception &) {
        return std::nullopt;
    }
}

std::pair<double, double> paperSize(const std::string &name, const FileLoc &where) {
    if (const auto size = parsePaperSize(name)) return *size;
    // Tell a malformed name from a well-formed size out of range.
    std::string lower = name;
    for (char &c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    const size_t x = lower.find('x');
    if (x != std::string::npos && x > 0 && x + 1 < lower.size()) {
        size_t usedW = 0, usedH = 0;
        double w = 0, h = 0;
        try {
            w = std::stod(lower.substr(0, x), &usedW);
            h = std::stod(lower.substr(x + 1), &usedH);
        } catch (const std::exception &) {
            usedW = 0; // out of double's range, or not numbers: handled below
        }
        const bool numbers = usedW == x && usedH == lower.size() - x - 1;
        if (numbers || lower.find_first_not_of("0123456789.e+-x") == std::string::npos)
            throw InputError(where,
                             "paper size '" + name + "' is out of range: each side must be in [" +
                                 number(kMinPaperSideMm) + ", " + number(kMaxPaperSideMm) + "] mm" +
                                 (numbers ? " (got " + (std::ostringstream() << w << " x " << h).str() + ")" : ""),
                             "use a4, a3, letter or WIDTHxHEIGHT in mm such as 300x200");
    }
    throw InputError(where, "unknown paper size '" + name + "'",
                     "use a4, a3, letter or WIDTHxHEIGHT in mm such as 300x200");
}

SvgOptions svgOptionsFor(const styles::PageStyle &page) {
    SvgOptions o;
    o.pageWidthMm = page.widthMm;
    o.pageHeightMm = page.heightMm;
    o.marginMm = page.marginMm;
    o.orientation = page.orientation;
    o.penWidthMm = page.penWidthMm;
    return o;
}

std::pair<double, double> orientedPage(double widthMm, double heightMm, styles::PageStyle::Orientation orientation,
                                       double marginMm, int pictureW, int pictureH) {
    using O = styles::PageStyle::Orientation;
    const double shortSide = std::min(widthMm, heightMm), longSide = std::max(widthMm, heightMm);
    switch (orientation) {
    case O::Portrait: return {shortSide, longSide};
    case O::Landscape: return {longSide, shortSide};
    case O::Auto: break;
    }
    const auto fit = [&](double w, double h) {
        return std::min((w - 2 * marginMm) / std::max(pictureW, 1), (h - 2 * marginMm) / std::max(pictureH, 1));
    };
    if (fit(heightMm, widthMm) > fit(widthMm, heightMm) * (1 + 1e-12)) return {heightMm, widthMm};
    return {widthMm, heightMm};
}

double pictureMmPerPx(const SvgOptions &o, int w, int h) {
    if (w <= 0 || h <= 0) throw InputError(FileLoc{}, "SVG: picture has no size", "render at a positive resolution");
    const auto [pw, ph] = orientedPage(o.pageWidthMm, o.pageHeightMm, o.orientation, o.marginMm, w, h);
    const double availW = pw - 2 * o.marginMm, availH = ph - 2 * o.marginMm;
    if (!(availW > 0) || !(availH > 0))
        throw InputError(FileLoc{}, "SVG: margin of " + number(o.marginMm) + " mm leaves no room on a " + number(pw) +
                                        "x" + number(ph) + " mm page",
                         "use a smaller margin or a larger paper size");
    return std::min(availW / w, availH / h);
}

std::pair<int, int> printResolution(const SvgOptions &o, int w, int h, double pxMm, int maxSide, bool *capped) {
    const double scale = pictureMmPerPx(o, w, h); // mm per px of the w×h picture
    double f = scale / pxMm;                      // px of the print grid per px of w×h
    const double longSide = std::max(w, h) * f;
    const bool cap = longSide > maxSide;
    if (cap) f = maxSide / double(std::max(w, h));
    if (capped) *capped = cap;
    const auto side = [&](int v) { return std::clamp(int(std::lround(v * f)), 16, std::max(maxSide, 16)); };
    return {side(w), side(h)};
}

namespace {

/// svgDocument(); `progress` (when given) moves to its stage 1 after the plotter pass.
std::string svgText(const StrokeList &list, const SvgOptions &optionsIn, SvgReport *report, Progress *progress) {
    if (list.width <= 0 || list.height <= 0)
        throw InputError(FileLoc{}, "SVG: stroke list has no size (" + std::to_string(list.width) + "x" +
                                        std::to_string(list.height) + " px)",
                         "render at a positive resolution");
    SvgOptions options = optionsIn;
    for (const double side : {options.pageWidthMm, options.pageHeightMm})
        if (!(side >= kMinPaperSideMm && side <= kMaxPaperSideMm))
            throw InputError(FileLoc{}, "SVG: a page side of " + (std::ostringstream() << side).str() +
                                            " mm is outside [" + number(kMinPaperSideMm) + ", " +
                                            number(kMaxPaperSideMm) + "] mm",
                             "use a paper size within that range");
    std::tie(options.pageWidthMm, options.pageHeightMm) = orientedPage(
        options.pageWidthMm, options.pageHeightMm, options.orientation, options.marginMm, list.width, list.height);
    const double availW = options.pageWidthMm - 2 * options.marginMm;
    const double availH = options.pageHeightMm - 2 * options.marginMm;
    if (!(availW > 0) || !(availH > 0) || !std::isfinite(availW) || !std::isfinite(availH))
        throw InputError(FileLoc{}, "SVG: margin of " + number(options.marginMm) + " mm leaves no room on a " +
                                        number(options.pageWidthMm) + "x" + number(options.pageHeightMm) + " mm page",
                         "use a smaller margin or a larger paper size");
    const double scale = std::min(availW / list.width, availH / list.height); // mm per px
    const double offX = options.marginMm + 0.5 * (availW - scale * list.width);
    const double offY = options.marginMm + 0.5 * (availH - scale * list.height);

    std::array<std::vector<Stroke>, 4> layers;
    for (const Stroke &s : list.strokes) layers[size_t(layerOf(s))].push_back(s);
    if (!options.hiddenContours) layers[3].clear();

    // The pen starts every layer at the page origin (the plotter's home, top left):
    // in raster px that is (−offX, −offY) / scale. Order and pen-up figure both use it.
    options.plotter.homePx = Eigen::Vector2d(-offX / scale, -offY / scale);
    PlotterReport plot;
    for (auto &layer : layers) {
        if (options.plotterPass) {
            layer = optimizeForPlotter(std::move(layer), options.plotter, &plot);
        } else {
            std::vector<Stroke> clean;
            for (Stroke &s : layer)
                if (removeDuplicatePoints(s)) clean.push_back(std::move(s));
            layer = std::move(clean);
            plot.penUpPx += penUpLength(layer, options.plotter.homePx);
            plot.penUpUnsortedPx += penUpLength(layer, options.plotter.homePx);
            plot.penDownPx += penDownLength(layer);
        }
    }

    if (progress) progress->beginStage(1);
    std::string out;
    out.reserve(1 << 20);
    out += "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n";
    out += "<svg xmlns=\"http://www.w3.org/2000/svg\" "
           "xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" version=\"1.1\" width=\"";
    out += number(options.pageWidthMm) + "mm\" height=\"" + number(options.pageHeightMm) + "mm\" viewBox=\"0 0 ";
    out += number(options.pageWidthMm) + " " + number(options.pageHeightMm) + "\">\n";

    int paths = 0;
    for (size_t l = 0; l < layers.size(); ++l) {
        if (l == 3 && layers[3].empty()) continue;
        // The label starts with the layer's number, its only digits: vpype takes the
        // (first group of) digits of inkscape:label as the layer id, AxiDraw the
        // leading number; id="layerN" is vpype's own fallback and writing convention.
        out += "  <g inkscape:groupmode=\"layer\" id=\"layer" + std::to_string(l + 1) + "\" inkscape:label=\"";
        out += options.layerLabels[l];
        out += "\" fill=\"none\" stroke=\"";
        out += l == 3 ? "#808080" : "#000000";
        out += "\" stroke-linecap=\"round\" stroke-linejoin=\"round\"";
        if (l == 3) out += " stroke-dasharray=\"1 1\"";
        out += ">\n";
        for (const Stroke &s : layers[l]) {
            const size_t n = s.points.size();
            if (n == 0) continue;
            // One width per path (SVG strokes have no width profile): the stroke's
            // length-weighted mean, so tapers and pressure keep their share of ink.
            double widthLen = 0, len = 0, widthSum = 0;
            for (size_t i = 0; i < s.widths.size(); ++i) {
                widthSum += s.widths[i];
                if (i == 0 || s.widths.size() != n) continue;
                const double l = (s.points[i] - s.points[i - 1]).norm();
                widthLen += 0.5 * (s.widths[i] + s.widths[i - 1]) * l;
                len += l;
            }
            const double meanWidth = len > 0 ? widthLen / len
                                     : s.widths.empty() ? 1.0
                                                        : widthSum / double(s.widths.size());
            const double widthMm = options.penWidthMm > 0 ? options.penWidthMm : meanWidth * scale;
            // Long paths are split into pieces sharing their joining vertex, so the line stays continuous.
            for (size_t begin = 0; begin + 1 < n || begin == 0; begin += kMaxPathVertices - 1) {
                const size_t end = std::min(n, begin + kMaxPathVertices);
                out += "    <path d=\"M";
                for (size_t i = begin; i < end; ++i) {
                    if (i == begin + 1) out += " L";
                    out += ' ';
                    appendNumber(out, offX + scale * s.points[i].x());
                    out += ' ';
                    appendNumber(out, offY + scale * s.points[i].y());
                }
                if (end - begin == 1) { // a lone vertex still needs a segment to show its round cap
                    out += " L ";
                    appendNumber(out, offX + scale * s.points[begin].x());
                    out += ' ';
                    appendNumber(out, offY + scale * s.points[begin].y());
                }
                out += "\" stroke-width=\"";
                appendNumber(out, std::max(widthMm, 0.001));
                out += "\"/>\n";
                ++paths;
                if (end == n) break;
            }
        }
        out += "  </g>\n";
    }
    out += "</svg>\n";

    if (report) {
        report->penUpMm = plot.penUpPx * scale;
        report->penUpUnsortedMm = plot.penUpUnsortedPx * scale;
        report->penDownMm = plot.penDownPx * scale;
        report->penUpRatioVsUnsorted = plot.penUpUnsortedPx > 0 ? plot.penUpPx / plot.penUpUnsortedPx : 1.0;
        report->paths = paths;
        report->mmPerPx = scale;
        report->pageWidthMm = options.pageWidthMm;
        report->pageHeightMm = options.pageHeightMm;
        report->overlapRemovedMm = plot.overlapRemovedPx * scale;
    }
    return out;
}

} // namespace

std::string svgDocument(const StrokeList &list, const SvgOptions &options, SvgReport *report) {
    return svgText(list, options, report, nullptr);
}

void writeSvg(const StrokeList &strokes, const SvgOptions &options, const std::string &path, SvgReport *report) {
    // The plotter pass is most of a large drawing's write (about 1 s at 4096²): the
    // display names it, then the file (terminal only, after a second).
    const std::string name = std::filesystem::path(path).filename().string();
    Progress progress("writing", {{name + " (plotter pass)", options.plotterPass ? 4.0 : 0.0}, {name, 1.0}});
    writeTextAtomically(path, svgText(strokes, options, report, &progress));
}

} // namespace rosy::renderer
