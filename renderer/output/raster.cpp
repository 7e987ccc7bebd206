#include "renderer/output/raster.h"
#include "renderer/output/large_buffer.h"

#include "core/error.h"
#include "core/parallel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace rosy::renderer {

namespace {

enum Layer : int { kHatch0 = 0, kHatch1 = 1, kContour = 2, kHidden = 3, kLayerCount = 4 };

uint8_t layerOf(const Stroke &s) {
    switch (s.kind) {
    case StrokeKind::Hatch: return s.family == 1 ? kHatch1 : kHatch0;
    case StrokeKind::Contour: return kContour;
    case StrokeKind::HiddenContour: return kHidden;
    }
    return kHatch0;
}

/// One polyline segment, copied out of the stroke list once: the strokes' own
/// vectors are scattered over the heap, and the three passes below (count, fill,
/// draw) would otherwise spend most of their time waiting for those cache misses.
struct Segment {
    float ax, ay, bx, by; ///< end points, raster px
    float wa, wb;         ///< full widths at the end points, >= 0; both < 0 marks a skipped segment
    float arc0;           ///< arc length of the stroke before this segment (dashing)
    uint32_t stroke;      ///< index into the stroke list
};

/// Inclusive pixel rectangle.
struct PixelBox {
    int x0, y0, x1, y1;
    bool empty() const { return x1 < x0 || y1 < y0; }
};

/// Pixels whose centre may lie within reach of `s`, clipped to the image; empty
/// for a segment that cannot ink anything. Avoids libm calls: after the bounds
/// test every value lies within a few pixels of the image, where truncation
/// toward zero can stand in for floor and ceil.
PixelBox segmentBox(const Segment &s, int width, int height) {
    const float r = 0.5f * std::max(s.wa, s.wb) + 0.5f;
    if (r <= 0.5f) return {0, 0, -1, -1}; // zero width (or a skipped segment) inks nothing
    // Pixel x has its centre at x + 0.5; keep every centre within r of the box.
    const float lox = std::min(s.ax, s.bx) - r - 0.5f, hix = std::max(s.ax, s.bx) + r - 0.5f;
    const float loy = std::min(s.ay, s.by) - r - 0.5f, hiy = std::max(s.ay, s.by) + r - 0.5f;
    if (!(hix >= 0 && hiy >= 0 && lox <= float(width) && loy <= float(height))) return {0, 0, -1, -1};
    auto ceilClamped = [](float v, int hi) {
        if (v <= 0.0f) return 0;
        int i = int(std::min(v, float(hi)));
        return float(i) < v ? i + 1 : i;
    };
    auto floorClamped = [](float v, int hi) { return v >= float(hi) ? hi : int(v); }; // v >= 0 here
    return {ceilClamped(lox, width), ceilClamped(loy, height), floorClamped(hix, width - 1),
            floorClamped(hiy, height - 1)};
}

/// Anti-aliased dash mask at arc length `s`: 1 inside a dash, 0 in a gap, linear
/// over one pixel at either end of a dash.
float dashFactor(float s, float on, float period) {
    float phase = s - period * std::floor(s / period);
    float inDash = std::min(phase, on - phase) + 0.5f;
    float nextDash = phase - period + 0.5f;
    return std::clamp(std::max(inDash, nextDash), 0.0f, 1.0f);
}

/// Copies every stroke's segments into one array, in stroke order. Segments
/// with a non-finite (or absurdly far, beyond 1e15 px) end point or width are
/// marked skipped; negative widths become 0.
std::vector<Segment> flattenSegments(const std::vector<Stroke> &strokes, std::vector<uint8_t> &layers) {
    const int64_t nStrokes = int64_t(strokes.size());
    std::vector<size_t> offset(strokes.size() + 1, 0);
    layers.resize(strokes.size());
    for (size_t i = 0; i < strokes.size(); ++i) {
        const Stroke &s = strokes[i];
        ROSY_CHECK_EQ(s.widths.size(), s.points.size());
        offset[i + 1] = offset[i] + (s.points.size() >= 2 ? s.points.size() - 1 : 0);
        layers[i] = layerOf(s);
    }
    std::vector<Segment> segs(offset.back());
    // Written so that NaN fails the comparison.
    auto usable = [](double v, double limit) { return std::fabs(v) < limit; };
    parallelFor(0, nStrokes, [&](int64_t si) {
        const Stroke &s = strokes[size_t(si)];
        double arc = 0.0;
        for (size_t k = 0; k + 1 < s.points.size(); ++k) {
            const Eigen::Vector2d &a = s.points[k], &b = s.points[k + 1];
            Segment &g = segs[offset[size_t(si)] + k];
            g = {float(a.x()), float(a.y()), float(b.x()), float(b.y()), std::max(0.0f, s.widths[k]),
                 std::max(0.0f, s.widths[k + 1]), float(arc), uint32_t(si)};
            if (!(usable(a.x(), 1e15) && usable(a.y(), 1e15) && usable(b.x(), 1e15) && usable(b.y(), 1e15) &&
                  usable(s.widths[k], 1e6) && usable(s.widths[k + 1], 1e6))) {
                g.wa = g.wb = -1.0f;
                continue;
            }
            arc += (b - a).norm();
        }
    }, 64);
    return segs;
}

/// Per-tile working memory. Coverage of the stroke being drawn lives in `cov`,
/// valid where stamp == the stroke's stamp; `touched` lists those pixels so
/// folding a stroke into its layer costs only the pixels it reached.
struct TileScratch {
    std::vector<float> transmittance[kLayerCount];
    std::vector<float> cov;
    std::vector<uint32_t> stamp;
    std::vector<int> touched;
};

} // namespace

InkLayers blankInkLayers(int width, int height) {
    InkLayers out;
    if (width < 1 || height < 1) return out;
    const size_t nPixels = size_t(width) * size_t(height);
    out.width = width;
    out.height = height;
    assignLarge(out.hatch0, nPixels, 0.0f);
    assignLarge(out.hatch1, nPixels, 0.0f);
    assignLarge(out.contour, nPixels, 0.0f);
    assignLarge(out.hiddenContour, nPixels, 0.0f);
    return out;
}

InkLayers rasterizeStrokes(const StrokeList &list, const RasterOptions &options) {
    return rasterizeStrokes(list, blankInkLayers(list.width, list.height), options);
}

InkLayers rasterizeStrokes(const StrokeList &list, InkLayers blank, const RasterOptions &options) {
    InkLayers out = std::move(blank);
    if (list.width < 1 || list.height < 1) return InkLayers{};
    ROSY_CHECK_GE(options.tileSize, 1);
    const int width = list.width, height = list.height, tile = options.tileSize;
    const size_t nPixels = size_t(width) * size_t(height);
    // Blank: blankInkLayers() of the list's size, nothing drawn yet.
    ROSY_CHECK_EQ(out.width, width);
    ROSY_CHECK_EQ(out.height, height);
    for (const std::vector<float> *v : {&out.hatch0, &out.hatch1, &out.contour, &out.hiddenContour})
        ROSY_CHECK_EQ(v->size(), nPixels);

    std::vector<uint8_t> strokeLayer;
    const std::vector<Segment> segs = flattenSegments(list.strokes, strokeLayer);
    const int64_t nSegs = int64_t(segs.size());
    ROSY_CHECK_LT(nSegs, int64_t(UINT32_MAX));
    const int tilesX = (width + tile - 1) / tile, tilesY = (height + tile - 1) / tile;
    const int64_t nTiles = int64_t(tilesX) * tilesY;

    // Binning as a two-pass counting sort over fixed chunks of segments: chunks
    // are counted and filled in parallel, and each tile's list is laid out chunk
    // after chunk, so every tile sees its segments in stroke order whatever the
    // thread count (and whatever the chunk size).
    const int64_t nChunks = std::clamp<int64_t>((nSegs + 4095) / 4096, 1, 64);
    const int64_t chunkSize = (nSegs + nChunks - 1) / nChunks;
    std::vector<uint32_t> counts(size_t(nChunks * nTiles), 0);
    auto forEachBinnedSegment = [&](int64_t chunk, auto &&emit) {
        int64_t begin = chunk * chunkSize, end = std::min(nSegs, begin + chunkSize);
        for (int64_t i = begin; i < end; ++i) {
            PixelBox box = segmentBox(segs[size_t(i)], width, height);
            if (box.empty()) continue;
            for (int ty = box.y0 / tile; ty <= box.y1 / tile; ++ty)
                for (int tx = box.x0 / tile; tx <= box.x1 / tile; ++tx)
                    emit(int64_t(ty) * tilesX + tx, uint32_t(i));
        }
    };
    parallelFor(0, nChunks, [&](int64_t c) {
        uint32_t *row = &counts[size_t(c * nTiles)];
        forEachBinnedSegment(c, [&](int64_t t, uint32_t) { ++row[t]; });
    }, 1);
    std::vector<size_t> cursor(counts.size()), tileStart(size_t(nTiles) + 1);
    size_t total = 0;
    for (int64_t t = 0; t < nTiles; ++t) {
        tileStart[size_t(t)] = total;
        for (int64_t c = 0; c < nChunks; ++c) {
            cursor[size_t(c * nTiles + t)] = total;
            total += counts[size_t(c * nTiles + t)];
        }
    }
    tileStart[size_t(nTiles)] = total;
    std::vector<uint32_t> entries(total);
    parallelFor(0, nChunks, [&](int64_t c) {
        size_t *row = &cursor[size_t(c * nTiles)];
        forEachBinnedSegment(c, [&](int64_t t, uint32_t i) { entries[row[t]++] = i; });
    }, 1);

    const bool dashed = options.dashOffPx > 0.0 && options.dashOnPx > 0.0;
    const bool combineMax = options.combine == RasterOptions::Combine::Max;
    const float dashOn = float(options.dashOnPx), dashPeriod = float(options.dashOnPx + options.dashOffPx);
    std::vector<float> *layerOut[kLayerCount] = {&out.hatch0, &out.hatch1, &out.contour, &out.hiddenContour};

    parallelFor(0, nTiles, [&](int64_t t) {
        const size_t first = tileStart[size_t(t)], last = tileStart[size_t(t) + 1];
        if (first == last) return;
        const int tx0 = int(t % tilesX) * tile, ty0 = int(t / tilesX) * tile;
        const int tw = std::min(tile, width - tx0), th = std::min(tile, height - ty0);
        const size_t tilePixels = size_t(tw) * size_t(th);
        TileScratch sc;
        bool layerUsed[kLayerCount] = {false, false, false, false};
        sc.cov.assign(tilePixels, 0.0f);
        sc.stamp.assign(tilePixels, 0);
        sc.touched.reserve(tilePixels);
        uint32_t currentStamp = 0;
        int currentLayer = -1;

        auto fold = [&] {
            if (currentLayer < 0) return;
            std::vector<float> &tr = sc.transmittance[currentLayer];
            if (combineMax)
                for (int p : sc.touched) tr[size_t(p)] = std::min(tr[size_t(p)], 1.0f - sc.cov[size_t(p)]);
            else
                for (int p : sc.touched) tr[size_t(p)] *= 1.0f - sc.cov[size_t(p)];
            sc.touched.clear();
        };

        uint32_t currentStroke = UINT32_MAX;
        for (size_t e = first; e < last; ++e) {
            const Segment &g = segs[entries[e]];
            if (g.stroke != currentStroke) {
                fold();
                currentStroke = g.stroke;
                ++currentStamp;
                currentLayer = strokeLayer[g.stroke];
                if (!layerUsed[currentLayer]) {
                    layerUsed[currentLayer] = true;
                    sc.transmittance[currentLayer].assign(tilePixels, 1.0f);
                }
            }
            const PixelBox box = segmentBox(g, width, height);
            const int x0 = std::max(box.x0, tx0), x1 = std::min(box.x1, tx0 + tw - 1);
            const int y0 = std::max(box.y0, ty0), y1 = std::min(box.y1, ty0 + th - 1);
            const float dx = g.bx - g.ax, dy = g.by - g.ay, dw = g.wb - g.wa;
            const float len2 = dx * dx + dy * dy;
            const float invLen2 = len2 > 0.0f ? 1.0f / len2 : 0.0f;
            const float reach = 0.5f * std::max(g.wa, g.wb) + 0.5f;
            const float reach2 = reach * reach;
            const bool dash = dashed && currentLayer == kHidden;
            const float len = std::sqrt(len2);
            for (int y = y0; y <= y1; ++y) {
                const float py = float(y) + 0.5f - g.ay;
                for (int x = x0; x <= x1; ++x) {
                    const float px = float(x) + 0.5f - g.ax;
                    const float u = std::clamp((px * dx + py * dy) * invLen2, 0.0f, 1.0f);
                    const float qx = px - u * dx, qy = py - u * dy;
                    const float d2 = qx * qx + qy * qy;
                    if (d2 >= reach2) continue;
                    const float w = g.wa + u * dw;
                    // Box-filtered band profile: integrates to w across the stroke.
                    float c = std::min(std::min(w, 1.0f), 0.5f * w + 0.5f - std::sqrt(d2));
                    if (dash) c = std::min(c, dashFactor(g.arc0 + u * len, dashOn, dashPeriod));
                    if (c <= 0.0f) continue;
                    const size_t p = size_t(y - ty0) * size_t(tw) + size_t(x - tx0);
                    if (sc.stamp[p] != currentStamp) {
                        sc.stamp[p] = currentStamp;
                        sc.cov[p] = c;
                        sc.touched.push_back(int(p));
                    } else if (c > sc.cov[p]) {
                        sc.cov[p] = c;
                    }
                }
            }
        }
        fold();

        for (int l = 0; l < kLayerCount; ++l) {
            if (!layerUsed[l]) continue;
            std::vector<float> &dst = *layerOut[l];
            const std::vector<float> &tr = sc.transmittance[l];
            for (int y = 0; y < th; ++y)
                for (int x = 0; x < tw; ++x)
                    dst[size_t(ty0 + y) * size_t(width) + size_t(tx0 + x)] =
                        std::clamp(1.0f - tr[size_t(y) * size_t(tw) + size_t(x)], 0.0f, 1.0f);
        }
    }, 1);
    return out;
}

namespace {

/// combinedCoverage() of one pixel (layers already checked against n).
struct CoverageOf {
    const InkLayers &layers;
    size_t n;
    float hidden;

    static float get(const std::vector<float> &v, size_t i) {
        if (v.empty()) return 0.0f;
        float c = v[i];
        return c == c ? std::clamp(c, 0.0f, 1.0f) : 0.0f;
    }
    float operator()(size_t k) const {
        float t = (1.0f - get(layers.hatch0, k)) * (1.0f - get(layers.hatch1, k)) *
                  (1.0f - get(layers.contour, k)) * (1.0f - hidden * get(layers.hiddenContour, k));
        return 1.0f - t;
    }
};

CoverageOf coverageOf(const InkLayers &layers, const CompositeOptions &options) {
    const size_t n = size_t(std::max(0, layers.width)) * size_t(std::max(0, layers.height));
    for (const std::vector<float> *v : {&layers.hatch0, &layers.hatch1, &layers.contour, &layers.hiddenContour})
        if (!v->empty()) ROSY_CHECK_EQ(v->size(), n);
    return {layers, n, float(std::clamp(options.hiddenOpacity, 0.0, 1.0))};
}

} // namespace

std::vector<float> combinedCoverage(const InkLayers &layers, const CompositeOptions &options) {
    const CoverageOf coverage = coverageOf(layers, options);
    std::vector<float> c;
    assignLarge(c, coverage.n, 0.0f);
    parallelFor(0, int64_t(coverage.n), [&](int64_t i) { c[size_t(i)] = coverage(size_t(i)); }, 4096);
    return c;
}

namespace {

/// Uniform value in [0, 1) from (seed, i, j): a 64-bit integer finalizer
/// (SplitMix64), so the grain depends only on the seed and the lattice point.
double latticeValue(uint32_t seed, int64_t i, int64_t j) {
    uint64_t z = (uint64_t(seed) << 32) ^ (uint64_t(uint32_t(i)) * 0x9E3779B97F4A7C15ull) ^
                 (uint64_t(uint32_t(j)) * 0xC2B2AE3D27D4EB4Full);
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return double(z >> 11) * (1.0 / 9007199254740992.0);
}

/// Smooth value noise in [0, 1]: bilinear with a smoothstep fade between lattice values.
double valueNoise(uint32_t seed, double x, double y) {
    double fx = std::floor(x), fy = std::floor(y);
    int64_t i = int64_t(fx), j = int64_t(fy);
    double u = x - fx, v = y - fy;
    u = u * u * (3.0 - 2.0 * u);
    v = v * v * (3.0 - 2.0 * v);
    double a = latticeValue(seed, i, j), b = latticeValue(seed, i + 1, j);
    double c = latticeValue(seed, i, j + 1), d = latticeValue(seed, i + 1, j + 1);
    return (a + (b - a) * u) * (1.0 - v) + (c + (d - c) * u) * v;
}

} // namespace

namespace {

/// paperColors() of one pixel: the paper colour times the grain factor at (x, y).
struct PaperOf {
    const styles::Style &style;
    double grain, scale;

    PaperOf(const styles::Style &s, const CompositeOptions &options)
        : style(s), grain(std::isfinite(s.paperGrain) ? std::clamp(s.paperGrain, 0.0, 1.0) : 0.0),
          scale(options.grainScalePx > 0.0 ? options.grainScalePx : 1.0) {}
    void operator()(int x, int64_t y, float rgb[3]) const {
        double f = 1.0;
        if (grain > 0.0) {
            // Two octaves (the second at half the feature size, half the weight,
            // own seed) read more like fibre than a single soft blob pattern.
            double px = (x + 0.5) / scale, py = (double(y) + 0.5) / scale;
            double n2 = (valueNoise(style.seed, px, py) +
                         0.5 * valueNoise(style.seed ^ 0x5bd1e995u, 2.0 * px, 2.0 * py)) / 1.5;
            f = 1.0 - grain * n2;
        }
        for (int ch = 0; ch < 3; ++ch) rgb[ch] = float(style.paper[size_t(ch)] * f);
    }
};

} // namespace

std::vector<float> paperColors(int width, int height, const styles::Style &style,
                               const CompositeOptions &options) {
    const size_t n = size_t(std::max(0, width)) * size_t(std::max(0, height));
    std::vector<float> rgb;
    assignLarge(rgb, 3 * n, 0.0f);
    const PaperOf paper(style, options);
    parallelFor(0, height, [&](int64_t y) {
        for (int x = 0; x < width; ++x) paper(x, y, &rgb[3 * (size_t(y) * size_t(width) + size_t(x))]);
    }, 8);
    return rgb;
}

Image paperImage(int width, int height, const styles::Style &style, const CompositeOptions &options) {
    width = std::max(0, width);
    height = std::max(0, height);
    Image image(width, height, {"R", "G", "B", "A"});
    const PaperOf paper(style, options);
    parallelFor(0, height, [&](int64_t y) {
        for (int x = 0; x < width; ++x) {
            const size_t k = size_t(y) * size_t(width) + size_t(x);
            paper(x, y, &image.data[4 * k]);
            image.data[4 * k + 3] = 1.0f;
        }
    }, 8);
    return image;
}

Image compositeInk(const InkLayers &layers, const styles::Style &style, const CompositeOptions &options) {
    return compositeInk(layers, style, paperImage(layers.width, layers.height, style, options), options);
}

Image compositeInk(const InkLayers &layers, const styles::Style &style, Image paper, const CompositeOptions &options) {
    const int width = std::max(0, layers.width), height = std::max(0, layers.height);
    Image image = std::move(paper);
    // paperImage() of the layers' size: R, G, B the paper, A = 1.
    ROSY_CHECK_EQ(image.width, width);
    ROSY_CHECK_EQ(image.height, height);
    ROSY_CHECK_EQ(image.nChannels, 4);
    // combinedCoverage() per pixel, without the plane in memory, over the paper's
    // colour as paperColors() gives it (stored as the same floats).
    const CoverageOf coverage = coverageOf(layers, options);
    parallelFor(0, height, [&](int64_t y) {
        for (int x = 0; x < width; ++x) {
            const size_t k = size_t(y) * size_t(width) + size_t(x);
            const float c = coverage(k);
            float *rgb = &image.data[4 * k];
            // Mixing in linear light: 50 % ink on white paper reflects half the light.
            for (int ch = 0; ch < 3; ++ch) rgb[ch] = float(rgb[ch] * (1.0f - c) + style.ink[size_t(ch)] * c);
        }
    }, 8);
    return image;
}

void paintOver(Image &image, const std::vector<float> &coverage, const styles::Rgb &colour, double opacity) {
    const size_t n = size_t(std::max(0, image.width)) * size_t(std::max(0, image.height));
    ROSY_CHECK_EQ(coverage.size(), n);
    ROSY_CHECK(image.nChannels == 3 || image.nChannels == 4);
    const size_t nc = size_t(image.nChannels);
    const float o = float(std::clamp(opacity, 0.0, 1.0));
    const float ink[3] = {float(colour[0]), float(colour[1]), float(colour[2])};
    parallelFor(0, int64_t(n), [&](int64_t i) {
        const float c = coverage[size_t(i)];
        const float a = o * (c == c ? std::clamp(c, 0.0f, 1.0f) : 0.0f);
        if (a <= 0.0f) return;
        float *px = &image.data[nc * size_t(i)];
        for (int ch = 0; ch < 3; ++ch) px[ch] = px[ch] * (1.0f - a) + ink[ch] * a;
    }, 4096);
}

const std::vector<std::string> &inkExrChannelNames() {
    static const std::vector<std::string> names = {
        "R",          "G",          "B",           "A",   "tone.target", "ink.coverage",
        "ink.hatch0", "ink.hatch1", "ink.contour", "depth", "N.x",       "N.y",
        "N.z",        "field.angle0", "field.angle1", "mask"};
    return names;
}

Image inkExrImage(const InkLayers &layers, const Image &composite, const SurfaceChannels &surface,
                  const CompositeOptions &options) {
    const int width = std::max(0, layers.width), height = std::max(0, layers.height);
    const size_t n = size_t(width) * size_t(height);
    ROSY_CHECK_EQ(composite.width, width);
    ROSY_CHECK_EQ(composite.height, height);
    ROSY_CHECK(composite.nChannels == 3 || composite.nChannels == 4);
    for (const std::vector<float> *v :
         {&surface.targetDensity, &surface.depth, &surface.normalX, &surface.normalY, &surface.normalZ,
          &surface.angle0, &surface.angle1, &surface.mask, &layers.hatch0, &layers.hatch1, &layers.contour,
          &layers.hiddenContour})
        if (!v->empty()) ROSY_CHECK_EQ(v->size(), n);

    Image image(width, height, inkExrChannelNames());
    const int nc = image.nChannels;
    std::vector<float> coverage = combinedCoverage(layers, options);
    auto get = [](const std::vector<float> &v, size_t i) {
        if (v.empty()) return 0.0f;
        return std::isfinite(v[i]) ? v[i] : 0.0f;
    };
    parallelFor(0, int64_t(n), [&](int64_t ii) {
        size_t i = size_t(ii);
        float *px = &image.data[i * size_t(nc)];
        for (int ch = 0; ch < 3; ++ch) {
            float v = composite.data[i * size_t(composite.nChannels) + size_t(ch)];
            px[ch] = std::isfinite(v) ? v : 0.0f;
        }
        float a = composite.nChannels == 4 ? composite.data[i * 4 + 3] : 1.0f;
        px[3] = std::isfinite(a) ? a : 0.0f;
        bool onObject = get(surface.mask, i) > 0.5f;
        px[4] = get(surface.targetDensity, i);
        px[5] = coverage[i];
        px[6] = get(layers.hatch0, i);
        px[7] = get(layers.hatch1, i);
        px[8] = get(layers.contour, i);
        px[9] = get(surface.depth, i);
        px[10] = get(surface.normalX, i);
        px[11] = get(surface.normalY, i);
        px[12] = get(surface.normalZ, i);
        px[13] = onObject ? get(surface.angle0, i) : 0.0f;
        px[14] = onObject ? get(surface.angle1, i) : 0.0f;
        px[15] = get(surface.mask, i);
    }, 4096);
    return image;
}

ImageWriteOptions inkExrWriteOptions(double hatchSpacingPx, double crossDensity) {
    ImageWriteOptions options;
    options.exrHalf = false;
    if (std::isfinite(hatchSpacingPx) && hatchSpacingPx > 0.0)
        options.floatAttributes.emplace_back(kHatchSpacingAttribute, float(hatchSpacingPx));
    if (std::isfinite(crossDensity))
        options.floatAttributes.emplace_back(kCrossDensityAttribute, float(crossDensity));
    return options;
}

} // namespace rosy::renderer
