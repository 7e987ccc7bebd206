#include "scenes/print_units.h"

#include "renderer/output/svg.h"

#include <algorithm>
#include <sstream>

namespace rosy::scenes {

PrintSetup applyPrintUnits(SceneDesc &desc, bool keepResolution) {
    PrintSetup setup;
    styles::Style &style = desc.style.style;
    setup.lengths = styles::printLengths(style);
    setup.warnings = styles::printProblems(setup.lengths);
    const renderer::SvgOptions page = renderer::svgOptionsFor(style.page);
    std::array<int, 2> &res = desc.camera.resolution.value;
    if (!keepResolution) {
        bool capped = false;
        // The scene's resolution is a budget: at most kPrintBudget times its longer side.
        const int maxSide = std::min(kMaxPrintSide, kPrintBudget * std::max(res[0], res[1]));
        const auto [w, h] = renderer::printResolution(page, res[0], res[1], style.page.pxMm, maxSide, &capped);
        if (capped) {
            std::ostringstream os;
            os << "the page needs more than " << maxSide << " px at style.page.px_mm " << style.page.pxMm
               << " (at most " << kPrintBudget << " x camera.resolution and " << kMaxPrintSide << "): traced at "
               << w << " x " << h << " px instead; raise camera.resolution or style.page.px_mm, or use a smaller paper";
            setup.warnings.push_back(os.str());
        }
        res = {w, h};
        setup.resolutionChosen = true;
    }
    setup.resolution = res;
    setup.mmPerPx = renderer::pictureMmPerPx(page, res[0], res[1]);
    const double f = style.page.pxMm / setup.mmPerPx;
    setup.plotter.mergeTolerancePx *= f;
    setup.plotter.simplifyTolerancePx *= f;
    setup.plotter.overlapTolerancePx *= f;
    setup.plotter.overlapMinGapPx *= f;
    bool coarsened = false;
    style = styles::printStyle(style, setup.mmPerPx, &coarsened);
    if (coarsened) {
        std::ostringstream os;
        os << "at " << res[0] << " x " << res[1] << " px one pixel is " << setup.mmPerPx
           << " mm on the page, coarser than the densest spacing (" << setup.lengths.minSpacingMm
           << " mm): the style's pixel lengths are used instead, so lines are wider and sparser on paper; "
              "raise camera.resolution";
        setup.warnings.push_back(os.str());
    }
    return setup;
}

} // namespace rosy::scenes
