#pragma once
/// \file style.h
/// The look of a rendering. For now only what the Lambert preview needs: the
/// colours of paper and ink and how dark the unlit side may get. The pen-and-ink
/// parameters (stroke widths, spacing, taper) join this struct later.

#include <array>

namespace rosy::styles {

/// Linear-light RGB, each channel in [0, 1] (not sRGB-encoded).
using Rgb = std::array<double, 3>;

struct Style {
    /// Colour of the background and of fully lit surfaces (linear RGB).
    Rgb paper = {1.0, 1.0, 1.0};
    /// Colour of the darkest tone (linear RGB). A pixel of tone t in [0, 1]
    /// gets ink + t (paper - ink).
    Rgb ink = {0.0, 0.0, 0.0};
    /// Tone floor of the Lambert preview in [0, 1]: surfaces no light reaches get
    /// this tone, so shadowed sides keep their shape instead of turning solid ink.
    double ambient = 0.15;
};

/// Linear-light colour of tone t (0 = ink, 1 = paper); t is clamped to [0, 1].
Rgb toneToColor(const Style &style, double tone);

} // namespace rosy::styles
