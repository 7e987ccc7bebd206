#include "styles/style.h"

#include <algorithm>
#include <cstdio>

namespace rosy::styles {

Rgb toneToColor(const Style &style, double tone) {
    // NaN would survive std::clamp; treat it as ink so no NaN reaches an image.
    double t = tone == tone ? std::clamp(tone, 0.0, 1.0) : 0.0;
    Rgb c;
    for (int i = 0; i < 3; ++i) c[i] = style.ink[i] + t * (style.paper[i] - style.ink[i]);
    return c;
}

PrintLengths printLengths(const Style &style) {
    const PageStyle &page = style.page;
    PrintLengths l;
    l.penWidthMm = page.penWidthMm > 0 ? page.penWidthMm : style.hatch.strokeWidthPx * page.pxMm;
    l.minSpacingMm = page.minSpacingMm > 0 ? page.minSpacingMm : style.hatch.minSpacingPx * page.pxMm;
    l.maxSpacingMm = page.maxSpacingMm > 0 ? page.maxSpacingMm : style.hatch.maxSpacingPx * page.pxMm;
    l.maxSpacingMm = std::max(l.maxSpacingMm, l.minSpacingMm);
    l.minLengthMm = page.minLengthMm >= 0 ? page.minLengthMm : style.hatch.minLengthPx * page.pxMm;
    return l;
}

Style printStyle(const Style &style, double mmPerPx, bool *coarsened) {
    const PrintLengths l = printLengths(style);
    // Lengths in px of this grid; below 1 px spacing the tracer cannot separate
    // lines, so the drawing falls back to style pixels (the caller warns).
    double scale = 1.0 / mmPerPx;
    const bool coarse = l.minSpacingMm * scale < 1.0;
    if (coarse) scale = 1.0 / style.page.pxMm;
    if (coarsened) *coarsened = coarse;
    Style s = style;
    s.hatch.strokeWidthPx = std::max(l.penWidthMm * scale, 0.05);
    s.hatch.minSpacingPx = l.minSpacingMm * scale;
    s.hatch.maxSpacingPx = l.maxSpacingMm * scale;
    s.hatch.minLengthPx = l.minLengthMm * scale;
    s.hatch.jitterPx = style.hatch.jitterPx * style.page.pxMm * scale;
    s.hatch.quadEdgePx = style.hatch.quadEdgePx * style.page.pxMm * scale;
    s.hatch.pixelScale = style.page.pxMm * scale;
    s.hatch.calibrateInk = true;
    if (s.contour.widthPx > 0) s.contour.widthPx = s.hatch.strokeWidthPx;
    if (s.contour.creaseWidthPx > 0) s.contour.creaseWidthPx = s.hatch.strokeWidthPx;
    return s;
}

std::vector<std::string> printProblems(const PrintLengths &l) {
    std::vector<std::string> out;
    const auto mm = [](double v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.3g mm", v);
        return std::string(buf);
    };
    if (l.penWidthMm < kMinPenWidthMm)
        out.push_back("the pen is " + mm(l.penWidthMm) + " wide: no plotter pen draws lines under " +
                      mm(kMinPenWidthMm) + "; set style.page.pen_width_mm (or raise style.page.px_mm)");
    if (l.minSpacingMm < l.penWidthMm)
        out.push_back("the densest hatches are " + mm(l.minSpacingMm) + " apart, closer than the " +
                      mm(l.penWidthMm) + " pen: dark tones fill solid and the paper may tear; raise "
                      "style.page.min_spacing_mm or use a finer pen");
    return out;
}

} // namespace rosy::styles
