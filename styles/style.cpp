#include "styles/style.h"

#include <algorithm>

namespace rosy::styles {

Rgb toneToColor(const Style &style, double tone) {
    // NaN would survive std::clamp; treat it as ink so no NaN reaches an image.
    double t = tone == tone ? std::clamp(tone, 0.0, 1.0) : 0.0;
    Rgb c;
    for (int i = 0; i < 3; ++i) c[i] = style.ink[i] + t * (style.paper[i] - style.ink[i]);
    return c;
}

} // namespace rosy::styles
