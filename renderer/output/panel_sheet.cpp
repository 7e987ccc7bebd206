#include "renderer/output/panel_sheet.h"

#include "core/error.h"
#include "renderer/output/bitmap_font.h"

#include <algorithm>
#include <cmath>

namespace rosy::renderer {

Image panelSheet(const std::vector<Image> &pictures, const std::vector<std::string> &labels,
                 const std::array<float, 3> &paper, const std::array<float, 3> &ink) {
    ROSY_CHECK(!pictures.empty() && pictures.size() == labels.size());
    const int w = pictures.front().width, h = pictures.front().height;
    for (const Image &pic : pictures) ROSY_CHECK(pic.width == w && pic.height == h && pic.nChannels >= 3);
    const int n = int(pictures.size());
    const int gap = std::max(4, std::min(w, h) / 32);
    size_t longest = 0;
    for (const std::string &label : labels) longest = std::max(longest, label.size());
    // Labels about 2.5% of the panel height tall, shrunk to fit the panel width;
    // a label still too wide breaks after its ':' (field, then count), and a line
    // still too wide is clipped at the panel's edges.
    int scale = std::max(1, int(std::lround(std::min(w, h) * 0.025 / 7.0)));
    while (scale > 1 && textWidthPx(std::string(longest, 'x'), scale) > w) --scale;
    std::vector<std::vector<std::string>> labelLines;
    size_t maxLines = 1;
    for (const std::string &label : labels) {
        std::vector<std::string> lines{label};
        const size_t colon = label.rfind(": ");
        if (textWidthPx(label, scale) > w && colon != std::string::npos)
            lines = {label.substr(0, colon + 1), label.substr(colon + 2)};
        maxLines = std::max(maxLines, lines.size());
        labelLines.push_back(lines);
    }
    const int lineHeight = (kFontGlyphRows + 2) * scale;
    const int band = int(maxLines) * lineHeight + gap;
    Image sheet(n * w + (n + 1) * gap, h + 2 * gap + band, {"R", "G", "B"});
    for (int y = 0; y < sheet.height; ++y)
        for (int x = 0; x < sheet.width; ++x)
            for (int c = 0; c < 3; ++c) sheet.at(x, y, c) = paper[size_t(c)];
    for (int k = 0; k < n; ++k) {
        const Image &pic = pictures[size_t(k)];
        const int x0 = gap + k * (w + gap), y0 = gap;
        const bool hasAlpha = pic.nChannels >= 4;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float a = hasAlpha ? pic.at(x, y, 3) : 1.0f;
                for (int c = 0; c < 3; ++c)
                    sheet.at(x0 + x, y0 + y, c) = pic.at(x, y, c) * a + paper[size_t(c)] * (1 - a);
            }
        const std::vector<std::string> &lines = labelLines[size_t(k)];
        for (size_t i = 0; i < lines.size(); ++i)
            drawText(sheet, lines[i], x0 + std::max(0, (w - textWidthPx(lines[i], scale)) / 2),
                     y0 + h + gap / 2 + int(i) * lineHeight, scale, ink, x0, x0 + w);
    }
    return sheet;
}

} // namespace rosy::renderer
