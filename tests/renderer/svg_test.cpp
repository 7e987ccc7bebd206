#include "bench/plotter_reference.h"
#include "renderer/output/plotter.h"
#include "renderer/output/svg.h"

#include "core/error.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>

using namespace rosy::renderer;

namespace {

Stroke line(Eigen::Vector2d a, Eigen::Vector2d b, float width = 1.0f, StrokeKind kind = StrokeKind::Hatch,
            int family = 0) {
    Stroke s;
    s.points = {a, b};
    s.widths = {width, width};
    s.kind = kind;
    s.family = kind == StrokeKind::Hatch ? family : -1;
    return s;
}

/// An element of the tiny XML reader below: name, attributes, and the label of the enclosing layer.
struct Element {
    std::string name;
    std::map<std::string, std::string> attrs;
    std::string layer;
};

/// Well-formedness check written for these tests: balanced tags, quoted
/// attributes, no duplicate attribute, one root. Returns false (with a reason) on
/// the first violation; fills `elements` in document order.
bool parseXml(const std::string &text, std::vector<Element> &elements, std::string &why) {
    std::vector<std::string> open;
    std::vector<std::string> layerStack;
    int roots = 0;
    size_t i = 0;
    auto fail = [&](const std::string &msg) {
        why = msg + " at byte " + std::to_string(i);
        return false;
    };
    while (i < text.size()) {
        if (text[i] != '<') {
            if (open.empty() && !std::isspace(static_cast<unsigned char>(text[i]))) return fail("text outside root");
            ++i;
            continue;
        }
        if (text.compare(i, 5, "<?xml") == 0) {
            const size_t e = text.find("?>", i);
            if (e == std::string::npos) return fail("unterminated declaration");
            i = e + 2;
            continue;
        }
        if (text.compare(i, 2, "</") == 0) {
            const size_t e = text.find('>', i);
            if (e == std::string::npos) return fail("unterminated end tag");
            const std::string name = text.substr(i + 2, e - i - 2);
            if (open.empty() || open.back() != name) return fail("mismatched </" + name + ">");
            open.pop_back();
            if (name == "g") layerStack.pop_back();
            i = e + 1;
            continue;
        }
        size_t j = i + 1;
        while (j < text.size() && (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == ':')) ++j;
        Element el;
        el.name = text.substr(i + 1, j - i - 1);
        if (el.name.empty()) return fail("empty tag name");
        bool selfClosing = false;
        for (;;) {
            while (j < text.size() && std::isspace(static_cast<unsigned char>(text[j]))) ++j;
            if (j >= text.size()) return fail("unterminated tag");
            if (text[j] == '>') {
                ++j;
                break;
            }
            if (text.compare(j, 2, "/>") == 0) {
                selfClosing = true;
                j += 2;
                break;
            }
            const size_t eq = text.find('=', j);
            if (eq == std::string::npos || text[eq + 1] != '"') return fail("unquoted attribute");
            const std::string key = text.substr(j, eq - j);
            const size_t close = text.find('"', eq + 2);
            if (close == std::string::npos) return fail("unterminated attribute");
            const std::string value = text.substr(eq + 2, close - eq - 2);
            if (value.find('<') != std::string::npos) return fail("'<' in attribute");
            if (!el.attrs.emplace(key, value).second) return fail("duplicate attribute " + key);
            j = close + 1;
        }
        if (open.empty()) ++roots;
        if (roots > 1) return fail("two roots");
        el.layer = layerStack.empty() ? "" : layerStack.back();
        if (!selfClosing) {
            open.push_back(el.name);
            if (el.name == "g") layerStack.push_back(el.attrs["inkscape:label"]);
        }
        elements.push_back(el);
        i = j;
    }
    if (!open.empty()) return fail("unclosed <" + open.back() + ">");
    if (roots != 1) return fail("no root");
    return true;
}

std::vector<Element> parseOrFail(const std::string &svg) {
    std::vector<Element> els;
    std::string why;
    EXPECT_TRUE(parseXml(svg, els, why)) << why;
    return els;
}

std::map<std::string, int> pathsPerLayer(const std::vector<Element> &els) {
    std::map<std::string, int> counts;
    for (const Element &e : els)
        if (e.name == "g") counts[e.attrs.at("inkscape:label")] += 0;
        else if (e.name == "path") ++counts[e.layer];
    return counts;
}

std::vector<Stroke> randomShortStrokes(int n, double size, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(0, size), ang(0, 6.283185307179586), len(2, 10);
    std::vector<Stroke> out;
    out.reserve(size_t(n));
    for (int i = 0; i < n; ++i) {
        const Eigen::Vector2d a(pos(rng), pos(rng));
        const double t = ang(rng), l = len(rng);
        Stroke s = line(a, a + l * Eigen::Vector2d(std::cos(t), std::sin(t)));
        s.id = uint32_t(i);
        out.push_back(std::move(s));
    }
    return out;
}

} // namespace

TEST(XmlCheck, RejectsMalformedDocuments) {
    std::vector<Element> els;
    std::string why;
    EXPECT_FALSE(parseXml("<svg><g></svg>", els, why));
    EXPECT_FALSE(parseXml("<svg a=1/>", els, why));
    EXPECT_FALSE(parseXml("<svg/><svg/>", els, why));
    EXPECT_TRUE(parseXml("<svg><g a=\"1\"/></svg>", els, why)) << why;
}

TEST(Svg, A4PageHasMillimetreSizeAndLayers) {
    StrokeList list;
    list.width = 200;
    list.height = 100;
    list.strokes.push_back(line({10, 10}, {50, 10}, 1, StrokeKind::Hatch, 0));
    list.strokes.push_back(line({10, 80}, {50, 80}, 1, StrokeKind::Hatch, 0));
    list.strokes.push_back(line({10, 20}, {10, 60}, 1, StrokeKind::Hatch, 1));
    list.strokes.push_back(line({100, 20}, {150, 60}, 2, StrokeKind::Contour));
    SvgReport report;
    const std::string svg = svgDocument(list, SvgOptions{}, &report);
    const auto els = parseOrFail(svg);
    ASSERT_FALSE(els.empty());
    EXPECT_EQ(els[0].name, "svg");
    // A 2:1 picture: turned A4 holds it at 277/200 mm/px, upright A4 only at 190/200.
    EXPECT_EQ(els[0].attrs.at("width"), "297mm");
    EXPECT_EQ(els[0].attrs.at("height"), "210mm");
    EXPECT_EQ(els[0].attrs.at("viewBox"), "0 0 297 210");
    EXPECT_NEAR(report.mmPerPx, 277.0 / 200, 1e-12);
    const auto counts = pathsPerLayer(els);
    EXPECT_EQ(counts.size(), 3u); // no hidden contours, no hidden layer
    EXPECT_EQ(counts.at("1 hatch"), 2);
    EXPECT_EQ(counts.at("2 cross-hatch"), 1);
    EXPECT_EQ(counts.at("3 contours"), 1);
    EXPECT_EQ(report.paths, 4);
    for (const Element &e : els)
        if (e.name == "g") {
            EXPECT_EQ(e.attrs.at("inkscape:groupmode"), "layer");
        }
}

namespace {

/// How a plotter tool numbers the layers of an SVG, as its documentation states
/// (written for this test, not taken from those tools):
///  - vpype `read` (help text and issue abey79/vpype#594): each top-level <g> is a
///    layer; its id is the number made of the digits of `inkscape:label` — all of
///    them up to 1.12 (`VpypeAllDigits`), the first run of digits from 1.13
///    (`VpypeFirstDigits`) —, else of the `id` attribute, else the group's order of
///    appearance; 0 becomes 1.
///  - AxiDraw layer control (EMSL wiki, "Syntax"): the label's leading integer after
///    leading whitespace; a label without one is not a numbered layer (-1 here).
enum class LayerRule { VpypeAllDigits, VpypeFirstDigits, AxiDraw };

std::vector<std::pair<std::string, long>> layerIds(const std::vector<Element> &els, LayerRule rule) {
    const auto digits = [&](const std::string &text) -> long {
        std::string d;
        for (size_t i = 0; i < text.size(); ++i) {
            if (std::isdigit(static_cast<unsigned char>(text[i]))) d += text[i];
            else if (!d.empty() && rule == LayerRule::VpypeFirstDigits) break;
        }
        if (d.empty()) return -1;
        const long v = std::stol(d);
        return v == 0 ? 1 : v;
    };
    std::vector<std::pair<std::string, long>> out;
    long order = 0;
    for (const Element &e : els) {
        if (e.name != "g" || !e.layer.empty()) continue; // top-level groups only
        ++order;
        const std::string label = e.attrs.count("inkscape:label") ? e.attrs.at("inkscape:label") : "";
        long id = -1;
        if (rule == LayerRule::AxiDraw) {
            size_t i = label.find_first_not_of(" \t");
            size_t j = i;
            while (j < label.size() && std::isdigit(static_cast<unsigned char>(label[j]))) ++j;
            if (i != std::string::npos && j > i) id = std::stol(label.substr(i, j - i));
        } else {
            id = digits(label);
            if (id < 0 && e.attrs.count("id")) id = digits(e.attrs.at("id"));
            if (id < 0) id = order;
        }
        out.push_back({label, id});
    }
    return out;
}

} // namespace

TEST(Svg, LayersGetDistinctIdsUnderVpypeAndAxiDrawRules) {
    StrokeList list;
    list.width = list.height = 100;
    list.strokes.push_back(line({10, 10}, {50, 10}, 1, StrokeKind::Hatch, 0));
    list.strokes.push_back(line({10, 20}, {10, 60}, 1, StrokeKind::Hatch, 1));
    list.strokes.push_back(line({60, 20}, {90, 60}, 1, StrokeKind::Contour));
    list.strokes.push_back(line({60, 70}, {90, 90}, 1, StrokeKind::HiddenContour));
    const auto els = parseOrFail(svgDocument(list, SvgOptions{}));
    // One stroke of each family: each layer holds one path.
    for (const auto &[label, n] : pathsPerLayer(els)) EXPECT_EQ(n, 1) << label;
    for (const LayerRule rule : {LayerRule::VpypeAllDigits, LayerRule::VpypeFirstDigits, LayerRule::AxiDraw}) {
        const auto ids = layerIds(els, rule);
        ASSERT_EQ(ids.size(), 4u) << int(rule);
        // Hatch family 0, family 1, contours, hidden contours: pens 1, 2, 3, 4, in that order.
        for (size_t k = 0; k < ids.size(); ++k) EXPECT_EQ(ids[k].second, long(k) + 1) << int(rule) << " " << ids[k].first;
    }
    // The same reader on the old labels ("hatch 0", "hatch 1", "contours") merges
    // the two hatch families into vpype's layer 1 (the bug of issue 18): it can fail.
    std::vector<Element> old;
    for (const char *label : {"hatch 0", "hatch 1", "contours"}) {
        Element g;
        g.name = "g";
        g.attrs["inkscape:label"] = label;
        g.attrs["id"] = "layer";
        old.push_back(g);
    }
    const auto oldIds = layerIds(old, LayerRule::VpypeFirstDigits);
    EXPECT_EQ(oldIds[0].second, oldIds[1].second);
    EXPECT_EQ(layerIds(old, LayerRule::AxiDraw)[0].second, -1);
    // Every group is an Inkscape layer with a unique id.
    std::set<std::string> idAttrs;
    for (const Element &e : els)
        if (e.name == "g") {
            EXPECT_EQ(e.attrs.at("inkscape:groupmode"), "layer");
            EXPECT_TRUE(idAttrs.insert(e.attrs.at("id")).second);
        }
    EXPECT_EQ(idAttrs, (std::set<std::string>{"layer1", "layer2", "layer3", "layer4"}));
}

TEST(Svg, KnownStrokeLandsAtExpectedMillimetres) {
    // 100×100 px into A4 minus 10 mm margins (190×277 mm): 1.9 mm/px, the square
    // centred vertically, so its top is at 10 + (277 − 190)/2 = 53.5 mm.
    StrokeList list;
    list.width = 100;
    list.height = 100;
    list.strokes.push_back(line({0, 0}, {50, 50}, 2));
    SvgOptions opt;
    opt.plotterPass = false;
    SvgReport report;
    const auto els = parseOrFail(svgDocument(list, opt, &report));
    int found = 0;
    for (const Element &e : els)
        if (e.name == "path") {
            ++found;
            EXPECT_EQ(e.attrs.at("d"), "M 10 53.5 L 105 148.5");
            EXPECT_EQ(e.attrs.at("stroke-width"), "3.8");
        }
    EXPECT_EQ(found, 1);
    EXPECT_NEAR(report.mmPerPx, 1.9, 1e-12);
    EXPECT_NEAR(report.penDownMm, std::sqrt(2.0) * 50 * 1.9, 1e-9);
}

TEST(Svg, HiddenContoursGetADashedLayer) {
    StrokeList list;
    list.width = list.height = 64;
    list.strokes.push_back(line({1, 1}, {30, 1}, 1, StrokeKind::Contour));
    list.strokes.push_back(line({1, 10}, {30, 10}, 1, StrokeKind::HiddenContour));
    const auto els = parseOrFail(svgDocument(list, SvgOptions{}));
    bool dashed = false;
    for (const Element &e : els)
        if (e.name == "g" && e.attrs.at("inkscape:label") == "4 hidden contours")
            dashed = e.attrs.count("stroke-dasharray") == 1;
    EXPECT_TRUE(dashed);
    EXPECT_EQ(pathsPerLayer(els).at("4 hidden contours"), 1);
}

TEST(Svg, LongPathsAreSplitBelow32000Vertices) {
    StrokeList list;
    list.width = list.height = 1000;
    Stroke s;
    s.kind = StrokeKind::Contour;
    // A zigzag, so simplification cannot drop vertices: 70000 points need
    // ceil(69999 / 31999) = 3 pieces that share their joining vertices.
    for (int i = 0; i < 70000; ++i) {
        s.points.emplace_back(i * 1.0, (i % 2) * 5.0);
        s.widths.push_back(1);
    }
    list.strokes.push_back(s);
    const auto els = parseOrFail(svgDocument(list, SvgOptions{}));
    int paths = 0;
    for (const Element &e : els)
        if (e.name == "path") {
            ++paths;
            const std::string &d = e.attrs.at("d");
            const size_t numbers = size_t(std::count(d.begin(), d.end(), ' ')) - 1; // "M" and "L" each take one space
            EXPECT_LE(numbers / 2, 32000u);
        }
    EXPECT_EQ(paths, 3);
}

TEST(Svg, RejectsMarginsLargerThanThePage) {
    StrokeList list;
    list.width = list.height = 10;
    SvgOptions opt;
    opt.marginMm = 120;
    EXPECT_THROW(svgDocument(list, opt), rosy::InputError);
}

TEST(Svg, ParsesPaperSizes) {
    EXPECT_EQ(parsePaperSize("A4"), (std::pair{210.0, 297.0}));
    EXPECT_EQ(parsePaperSize("a3"), (std::pair{297.0, 420.0}));
    EXPECT_EQ(parsePaperSize("300x200"), (std::pair{300.0, 200.0}));
    EXPECT_FALSE(parsePaperSize("a5x").has_value());
    EXPECT_FALSE(parsePaperSize("0x10").has_value());
    EXPECT_FALSE(parsePaperSize("b4").has_value());
}

TEST(Svg, IsByteIdenticalForOneTwoAndEightThreads) {
    StrokeList list;
    list.width = list.height = 500;
    list.strokes = randomShortStrokes(5000, 500, 7);
    for (size_t i = 0; i < list.strokes.size(); i += 3) list.strokes[i].family = 1;
    // Some exact and partial repeats, so the overlap removal has work to do.
    for (size_t i = 0; i < 500; i += 5) list.strokes.push_back(list.strokes[i]);
    std::string doc[3];
    const int threads[3] = {1, 2, 8};
    for (int k = 0; k < 3; ++k) {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, size_t(threads[k]));
        doc[k] = svgDocument(list, SvgOptions{});
    }
    EXPECT_GT(doc[0].size(), 100000u);
    EXPECT_EQ(doc[0], doc[1]);
    EXPECT_EQ(doc[0], doc[2]);
}

TEST(Svg, WritesTheFileAtomically) {
    const auto path = std::filesystem::path(ROSY_BINARY_DIR) / "svg_test_out.svg";
    StrokeList list;
    list.width = list.height = 10;
    list.strokes.push_back(line({1, 1}, {9, 9}));
    writeSvg(list, SvgOptions{}, path.string());
    std::ifstream is(path, std::ios::binary);
    std::stringstream ss;
    ss << is.rdbuf();
    EXPECT_EQ(ss.str(), svgDocument(list, SvgOptions{}));
    std::filesystem::remove(path);
}

TEST(Plotter, MergeJoinsStrokesSharingAnEndpoint) {
    // The second stroke runs towards the shared point, so it must be reversed.
    std::vector<Stroke> in{line({0, 0}, {1, 0}), line({2, 0}, {1.2, 0}), line({5, 5}, {6, 5})};
    const auto out = mergeStrokes(in, 0.5);
    ASSERT_EQ(out.size(), 2u);
    ASSERT_EQ(out[0].points.size(), 4u);
    EXPECT_EQ(out[0].points.front(), Eigen::Vector2d(0, 0));
    EXPECT_EQ(out[0].points.back(), Eigen::Vector2d(2, 0));
    EXPECT_EQ(out[0].widths.size(), out[0].points.size());
    EXPECT_EQ(out[1].points.front(), Eigen::Vector2d(5, 5));
}

TEST(Plotter, MergeLeavesDistantEndsApart) {
    std::vector<Stroke> in{line({0, 0}, {1, 0}), line({1.6, 0}, {3, 0})};
    EXPECT_EQ(mergeStrokes(in, 0.5).size(), 2u);
}

TEST(Plotter, SimplifyRemovesCollinearPointsAndKeepsCorners) {
    Stroke s;
    s.points = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {2, 2}, {2.1, 3}, {2, 4}};
    s.widths = {1, 2, 3, 4, 5, 6, 7};
    simplifyStroke(s, 0.25);
    // (2.1, 3) is 0.1 px off the chord (2,2)-(2,4) … and (2,2) itself lies on
    // the chord (2,0)-(2,4): only the corner and the ends remain.
    ASSERT_EQ(s.points.size(), 3u);
    EXPECT_EQ(s.points[0], Eigen::Vector2d(0, 0));
    EXPECT_EQ(s.points[1], Eigen::Vector2d(2, 0));
    EXPECT_EQ(s.points[2], Eigen::Vector2d(2, 4));
    EXPECT_EQ(s.widths, (std::vector<float>{1, 3, 7}));
}

TEST(Plotter, DuplicatePointsAndNaNsAreDropped) {
    Stroke s;
    s.points = {{0, 0}, {0, 0}, {NAN, 1}, {1, 0}, {1, 0}};
    s.widths = {1, 1, 1, 1, 1};
    ASSERT_TRUE(removeDuplicatePoints(s));
    EXPECT_EQ(s.points.size(), 2u);
}

TEST(Plotter, SortingCutsPenUpAndKeepsPenDown) {
    const auto in = randomShortStrokes(3000, 1000, 11);
    PlotterReport report;
    const auto out = optimizeForPlotter(in, PlotterOptions{}, &report);
    EXPECT_NEAR(report.penUpUnsortedPx, penUpLength(in), 1e-6);
    EXPECT_NEAR(report.penDownPx, penDownLength(in), 0.01 * penDownLength(in));
    EXPECT_LT(report.penUpPx, 0.6 * report.penUpUnsortedPx);
    EXPECT_NEAR(report.penUpPx, penUpLength(out), 1e-6);
    // Nothing drawn is lost: every input stroke is still drawn (possibly merged).
    EXPECT_LE(out.size(), in.size());
    EXPECT_EQ(report.paths, int(out.size()));
}

TEST(Plotter, TwoOptFixesACrossedTour) {
    // Four unit strokes on a line; the given order zigzags across it. The optimal
    // tour from the origin draws them left to right with 3 px of travel.
    std::vector<Stroke> in{line({0, 0}, {1, 0}), line({6, 0}, {7, 0}), line({2, 0}, {3, 0}), line({4, 0}, {5, 0})};
    PlotterOptions opt;
    opt.mergeTolerancePx = 0;
    const auto out = sortStrokes(in, opt);
    EXPECT_NEAR(penUpLength(out), 3.0, 1e-12);
}

TEST(Plotter, OrderIsNoWorseThanGreedyPlusExhaustiveTwoOpt) {
    // The yardstick (bench/plotter_reference.h) is the textbook greedy + full
    // 2-opt that vpype's `linesort --two-opt` describes, by brute force. Three
    // kinds of input: random short strokes, shuffled parallel hatch lines with
    // gaps (a hatched region), and clusters far apart (long jumps to place well).
    std::mt19937 rng(17);
    std::vector<std::vector<Stroke>> sets;
    sets.push_back(randomShortStrokes(400, 1000, 23));
    std::vector<Stroke> hatch;
    for (int row = 0; row < 40; ++row)
        for (int piece = 0; piece < 8; ++piece) {
            const double x0 = piece * 30 + (row % 3) * 4, y = 5.0 * row + 0.3 * piece;
            hatch.push_back(line({x0, y}, {x0 + 22, y + 3}));
        }
    std::shuffle(hatch.begin(), hatch.end(), rng);
    sets.push_back(hatch);
    std::vector<Stroke> clusters;
    for (const auto &[cx, cy] : {std::pair{100.0, 900.0}, {900.0, 100.0}, {500.0, 500.0}, {950.0, 950.0}})
        for (Stroke s : randomShortStrokes(80, 60, uint32_t(cx + cy))) {
            for (auto &p : s.points) p += Eigen::Vector2d(cx, cy);
            clusters.push_back(s);
        }
    std::shuffle(clusters.begin(), clusters.end(), rng);
    sets.push_back(clusters);
    PlotterOptions opt;
    for (size_t k = 0; k < sets.size(); ++k) {
        const double ours = penUpLength(sortStrokes(sets[k], opt));
        int passes = 0;
        const double reference = penUpLength(rosy::bench::referenceGreedyTwoOpt(sets[k], 250, &passes));
        opt.twoOptMaxPasses = 0; // greedy alone, for scale
        const double greedy = penUpLength(sortStrokes(sets[k], opt));
        opt.twoOptMaxPasses = PlotterOptions{}.twoOptMaxPasses;
        std::printf("set %zu: %zu strokes, pen-up greedy %.1f, greedy+2-opt reference %.1f (%d passes), "
                    "ours %.1f px (%.3fx the reference)\n",
                    k, sets[k].size(), greedy, reference, passes, ours, ours / reference);
        EXPECT_LE(ours, reference * (1 + 1e-9)) << "set " << k;
        EXPECT_LT(ours, greedy) << "set " << k;
        // Every stroke drawn once: same pen-down, same count.
        EXPECT_NEAR(penDownLength(sortStrokes(sets[k], opt)), penDownLength(sets[k]), 1e-6);
    }
}

TEST(Plotter, SortedOrderIsTwoOptOptimal) {
    // The 29 contour paths of the default scene at 4096² (endpoints as drawn):
    // after the sort no single 2-opt move (reversing a run, each stroke turned)
    // may shorten the travel, checked here by brute force over every pair.
    std::vector<Stroke> in{
        line({1589.9096432073575, 3267.1869382905734}, {1589.4742782973767, 3270.0540355855132}),
        line({1588.89386660082, 3273.8763390532467}, {984.79204120090867, 2866.3468197763027}),
        line({985.69877211186622, 2867.371238883713}, {988.53992851718954, 2871.9774726959272}),
        line({987.15341461768264, 2870.1953359872909}, {862.9783712915023, 2283.985631500158}),
        line({836.44016302164619, 2236.0425885586965}, {786.47680445863966, 1742.7967706859131}),
        line({788.74159491672413, 1757.9502669757594}, {957.6067726979993, 1381.4780119128586}),
        line({951.75484554376931, 1385.6546144086078}, {952.83463528312609, 1353.4410503622701}),
        line({943.39649174601595, 1388.5970416584812}, {925.99194807337346, 1345.4706989312799}),
        line({926.36773011786306, 1346.7862150112576}, {925.5809432242487, 1346.8940703659803}),
        line({924.71599322608779, 1345.9685609237179}, {917.6694544378588, 1317.7503303383151}),
        line({916.8105677165795, 1321.7918451165554}, {912.81527498565254, 1295.691069879505}),
        line({912.8879687225392, 1296.7933943575965}, {912.1813050410401, 1277.8696899283373}),
        line({948.70564174266065, 1343.7220089961706}, {1195.3776359951453, 1340.6952658141354}),
        line({1178.8261511524588, 1338.5324676543914}, {1642.2946396089935, 1792.8015446314241}),
        line({1640.004011638724, 1789.6390268300959}, {1641.5600354542157, 1790.9596322327739}),
        line({1638.4739585081968, 1786.4665849625128}, {3114.1518871302715, 3077.8373573068516}),
        line({3116.3933771302482, 3073.8822020691582}, {3131.350864526552, 3044.2144129755634}),
        line({3195.0648311440605, 2786.4582007053723}, {3197.5963698239907, 2767.20452478984}),
        line({3198.0363919941901, 2762.4634332467931}, {3198.3000051177642, 2759.623090110782}),
        line({3213.116158233036, 2592.3488919887518}, {3006.5208019111997, 3264.2097063906836}),
        line({3049.231303724283, 3185.3493694974541}, {1474.5439918430748, 3425.5043612260361}),
        line({1384.4644349075681, 3532.837549400831}, {1214.3710910950604, 3278.4854099335589}),
        line({1206.5160634738279, 3285.5532496842043}, {1388.0814899387951, 3116.5760036011025}),
        line({1457.6002297346449, 2237.7508696293057}, {821.96379992438119, 2178.5962497488786}),
        line({1456.3616724088367, 2240.1489429671037}, {1454.0864257116059, 2243.4981475329641}),
        line({1539.2361573368291, 1617.8108130454596}, {1545.2376164186535, 1640.557162253675}),
        line({1544.5503989461563, 1637.4289199607927}, {1494.1605961643086, 1415.7708975450046}),
        line({1495.7481788621585, 1417.4379774737786}, {1504.2764329952429, 1429.7466267478112}),
        line({2970.1593927849381, 3222.8031708169528}, {2970.1593927849381, 3222.8031708169528})};
    const std::vector<Stroke> out = sortStrokes(in, PlotterOptions{});
    const double travel = penUpLength(out);
    const int n = int(out.size());
    double bestGain = 0;
    for (int b1 = 0; b1 < n; ++b1)
        for (int b2 = b1 + 1; b2 <= n; ++b2) {
            std::vector<Stroke> t = out;
            std::reverse(t.begin() + b1, t.begin() + b2);
            for (int p = b1; p < b2; ++p) std::reverse(t[size_t(p)].points.begin(), t[size_t(p)].points.end());
            bestGain = std::max(bestGain, travel - penUpLength(t));
        }
    EXPECT_LT(bestGain, 1e-6);
    const double reference = penUpLength(rosy::bench::referenceGreedyTwoOpt(in));
    PlotterOptions g;
    g.twoOptMaxPasses = 0;
    std::printf("ours %.1f, reference %.1f px, greedy %.1f\n", travel, reference, penUpLength(sortStrokes(in, g)));
    EXPECT_LE(travel, reference * (1 + 1e-9));
}

// --- page from the style ------------------------------------------------------

TEST(Svg, PageComesFromTheStyleAndTurnsForAWidePicture) {
    rosy::styles::PageStyle page;
    page.widthMm = 297; // A3
    page.heightMm = 420;
    page.marginMm = 20;
    StrokeList list;
    list.width = 300;
    list.height = 100; // wide: A3 landscape holds it at 380/300 mm/px, portrait only at 257/300
    list.strokes.push_back(line({0, 0}, {300, 100}, 1));
    SvgReport report;
    auto els = parseOrFail(svgDocument(list, svgOptionsFor(page), &report));
    EXPECT_EQ(els[0].attrs.at("width"), "420mm");
    EXPECT_EQ(els[0].attrs.at("height"), "297mm");
    EXPECT_EQ(els[0].attrs.at("viewBox"), "0 0 420 297");
    EXPECT_NEAR(report.mmPerPx, (420.0 - 40) / 300, 1e-12);
    page.orientation = rosy::styles::PageStyle::Orientation::Portrait;
    els = parseOrFail(svgDocument(list, svgOptionsFor(page), &report));
    EXPECT_EQ(els[0].attrs.at("width"), "297mm");
    EXPECT_NEAR(report.mmPerPx, (297.0 - 40) / 300, 1e-12);
    // A square picture on a square-ish choice: auto keeps the size as written.
    EXPECT_EQ(orientedPage(210, 297, rosy::styles::PageStyle::Orientation::Auto, 10, 50, 50),
              (std::pair{210.0, 297.0}));
    EXPECT_EQ(orientedPage(297, 210, rosy::styles::PageStyle::Orientation::Portrait, 10, 50, 50),
              (std::pair{210.0, 297.0}));
    EXPECT_EQ(orientedPage(210, 297, rosy::styles::PageStyle::Orientation::Landscape, 10, 50, 50),
              (std::pair{297.0, 210.0}));
}

TEST(Svg, StrokeWidthIsTheStyleWidthInMillimetresOrTheFixedPen) {
    // 100 px across 190 mm: 1.9 mm/px. A stroke 1.4 px wide is 2.66 mm; one whose
    // width runs 1 -> 3 px linearly has a length-weighted mean of 2 px = 3.8 mm.
    StrokeList list;
    list.width = list.height = 100;
    list.strokes.push_back(line({0, 10}, {90, 10}, 1.4f));
    Stroke ramp;
    ramp.points = {{0, 50}, {30, 50}, {33, 53}};
    ramp.widths = {1, 2, 2.2f}; // not a linear ramp per point: weighting by length matters
    list.strokes.push_back(ramp);
    SvgOptions opt;
    opt.plotterPass = false;
    std::vector<std::string> widths;
    for (const Element &e : parseOrFail(svgDocument(list, opt)))
        if (e.name == "path") widths.push_back(e.attrs.at("stroke-width"));
    ASSERT_EQ(widths.size(), 2u);
    EXPECT_EQ(widths[0], "2.66");
    // (1.5 * 30 + 2.1 * sqrt(18)) / (30 + sqrt(18)) px = 1.57435 px -> 2.991 mm
    const double mean = (1.5 * 30 + 2.1 * std::sqrt(18.0)) / (30 + std::sqrt(18.0));
    EXPECT_NEAR(std::stod(widths[1]), mean * 1.9, 0.0006);
    opt.penWidthMm = 0.3;
    for (const Element &e : parseOrFail(svgDocument(list, opt)))
        if (e.name == "path") {
            EXPECT_EQ(e.attrs.at("stroke-width"), "0.3");
        }
}

TEST(Svg, HiddenContourLayerIsOptional) {
    StrokeList list;
    list.width = list.height = 64;
    list.strokes.push_back(line({1, 1}, {30, 1}, 1, StrokeKind::Contour));
    list.strokes.push_back(line({1, 10}, {30, 10}, 1, StrokeKind::HiddenContour));
    SvgOptions opt;
    opt.hiddenContours = false;
    const auto counts = pathsPerLayer(parseOrFail(svgDocument(list, opt)));
    EXPECT_EQ(counts.count("4 hidden contours"), 0u);
    EXPECT_EQ(counts.at("3 contours"), 1);
}

// --- collinear overlaps -----------------------------------------------------------

TEST(Plotter, ExactDuplicateStrokeIsDropped) {
    std::vector<Stroke> in{line({0, 0}, {10, 0}), line({10, 0}, {0, 0}), line({0, 5}, {10, 5})};
    double removed = 0;
    const auto out = removeOverlaps(in, 0.1, 1.0, &removed);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].points, in[0].points);
    EXPECT_EQ(out[1].points, in[2].points);
    EXPECT_NEAR(removed, 10.0, 1e-12);
}

TEST(Plotter, PartialCollinearOverlapIsTrimmed) {
    // The second line runs 0.05 px beside the first and overlaps it over x in [5, 10].
    Stroke b;
    b.points = {{5, 0.05}, {15, 0.05}};
    b.widths = {1, 3};
    std::vector<Stroke> in{line({0, 0}, {10, 0}), b};
    double removed = 0;
    const auto out = removeOverlaps(in, 0.1, 1.0, &removed);
    ASSERT_EQ(out.size(), 2u);
    ASSERT_EQ(out[1].points.size(), 2u);
    EXPECT_NEAR(out[1].points[0].x(), 10.0, 1e-12);
    EXPECT_NEAR(out[1].points[0].y(), 0.05, 1e-12);
    EXPECT_EQ(out[1].points[1], Eigen::Vector2d(15, 0.05));
    EXPECT_NEAR(out[1].widths[0], 2.0f, 1e-6); // interpolated half way along
    EXPECT_NEAR(removed, 5.0, 1e-12);
}

TEST(Plotter, RetraceWithinAStrokeIsDropped) {
    Stroke s;
    s.points = {{0, 0}, {10, 0}, {4, 0}};
    s.widths = {1, 1, 1};
    const auto out = removeOverlaps({s}, 0.1);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].points, (std::vector<Eigen::Vector2d>{{0, 0}, {10, 0}}));
}

TEST(Plotter, CrossingsParallelNeighboursAndStraightRunsAreKept) {
    // A 90° crossing, a 20° crossing (beyond the 10° bound), a parallel line
    // 1 px away (beyond the 0.1 px tolerance) and a stroke running straight on.
    const double a = 20 * 3.14159265358979323846 / 180;
    Stroke straight;
    straight.points = {{0, 20}, {5, 20}, {10, 20}};
    straight.widths = {1, 1, 1};
    std::vector<Stroke> in{line({0, 0}, {10, 0}), line({5, -5}, {5, 5}),
                           line({5 - 4 * std::cos(a), -4 * std::sin(a)}, {5 + 4 * std::cos(a), 4 * std::sin(a)}),
                           line({0, 1}, {10, 1}), straight};
    double removed = 0;
    const auto out = removeOverlaps(in, 0.1, 1.0, &removed);
    ASSERT_EQ(out.size(), in.size());
    for (size_t i = 0; i < in.size(); ++i) EXPECT_EQ(out[i].points, in[i].points) << i;
    EXPECT_EQ(removed, 0.0);
}

TEST(Plotter, ShortInteriorOverlapKeepsTheStrokeWholeLongOneSplitsIt) {
    // A 0.6 px stroke lies on the middle of a 10 px one: splitting would add a pen lift for nothing.
    auto out = removeOverlaps({line({4.7, 0}, {5.3, 0}), line({0, 0}, {10, 0})}, 0.1, 1.0);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[1].points, (std::vector<Eigen::Vector2d>{{0, 0}, {10, 0}}));
    // A 4 px one does split it into [0, 3] and [7, 10].
    double removed = 0;
    out = removeOverlaps({line({3, 0}, {7, 0}), line({0, 0}, {10, 0})}, 0.1, 1.0, &removed);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_EQ(out[1].points, (std::vector<Eigen::Vector2d>{{0, 0}, {3, 0}}));
    EXPECT_EQ(out[2].points, (std::vector<Eigen::Vector2d>{{7, 0}, {10, 0}}));
    EXPECT_NEAR(removed, 4.0, 1e-12);
}

TEST(Plotter, PassDropsDuplicatedInkButKeepsEveryDistinctLine) {
    // 2000 random strokes, then 500 of them again reversed and 0.03 px off: the
    // pass must remove about the repeated length and keep the rest (within 1%).
    auto base = randomShortStrokes(2000, 1000, 5);
    std::vector<Stroke> in = base;
    double repeated = 0;
    for (size_t i = 0; i < 500; ++i) {
        Stroke s = base[i * 4];
        for (auto &p : s.points) p += Eigen::Vector2d(0.0, 0.03);
        std::reverse(s.points.begin(), s.points.end());
        repeated += penDownLength({s});
        in.push_back(s);
    }
    PlotterReport report;
    (void)optimizeForPlotter(in, PlotterOptions{}, &report);
    EXPECT_NEAR(report.overlapRemovedPx, repeated, 0.01 * repeated);
    EXPECT_NEAR(report.penDownPx, penDownLength(base), 0.01 * penDownLength(base));
}
