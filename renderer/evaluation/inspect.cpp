#include "renderer/evaluation/inspect.h"

#include "core/error.h"
#include "core/json.h"
#include "core/parallel.h"
#include "renderer/output/raster.h"

#include "renderer/output/image_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <limits>

namespace rosy::renderer {

InkMaps readInkMaps(const std::string &path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw IoError(path, "no such file (or not a regular file)");
    std::string error;
    std::unique_ptr<ImageFileReader> in = imageIo().open(path, error);
    if (!in)
        throw InputError(FileLoc{path}, "not an image OpenImageIO can read: " + error,
                         "pass the .exr written by rosyhatch render");
    const ImageFileHeader &spec = in->header();
    struct Wanted {
        const char *name;
        std::vector<float> InkMaps::*member;
    };
    const Wanted wanted[] = {{"ink.hatch0", &InkMaps::hatch0},   {"ink.hatch1", &InkMaps::hatch1},
                             {"ink.coverage", &InkMaps::coverage}, {"tone.target", &InkMaps::target},
                             {"field.angle0", &InkMaps::angle0}, {"field.angle1", &InkMaps::angle1},
                             {"mask", &InkMaps::mask}};
    std::vector<int> index;
    std::string missing;
    for (const Wanted &w : wanted) {
        auto it = std::find(spec.channelNames.begin(), spec.channelNames.end(), w.name);
        index.push_back(it == spec.channelNames.end() ? -1 : int(it - spec.channelNames.begin()));
        if (index.back() < 0) missing += std::string(missing.empty() ? "" : ", ") + w.name;
    }
    if (!missing.empty())
        throw InputError(FileLoc{path}, "the image lacks the channel(s) " + missing,
                         "inspect reads the multi-channel .exr of rosyhatch render");
    if (spec.width < 1 || spec.height < 1 || spec.depth > 1)
        throw InputError(FileLoc{path}, "not a 2D image with pixels");

    InkMaps maps;
    maps.width = spec.width;
    maps.height = spec.height;
    const size_t n = size_t(spec.width) * size_t(spec.height), nc = size_t(spec.nChannels);
    std::vector<float> all(n * nc);
    if (!in->readFloat(all.data(), error)) throw IoError(path, "cannot read the pixels: " + error);
    for (size_t k = 0; k < std::size(wanted); ++k) {
        std::vector<float> &dst = maps.*(wanted[k].member);
        dst.resize(n);
        for (size_t i = 0; i < n; ++i) {
            float v = all[i * nc + size_t(index[k])];
            dst[i] = std::isfinite(v) ? v : 0.0f;
        }
    }
    float spacing = in->floatAttribute(kHatchSpacingAttribute, 0.0f);
    maps.hatchSpacingPx = std::isfinite(spacing) && spacing > 0.0f ? double(spacing) : 0.0;
    const float cross = in->floatAttribute(kCrossDensityAttribute, std::nanf(""));
    if (std::isfinite(cross)) maps.crossDensity = double(cross);
    return maps;
}

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Grid {
    int width, height;
    size_t size() const { return size_t(width) * size_t(height); }
};

/// Three passes of a separable box filter of radius r, zero outside the image:
/// close to a Gaussian of σ = sqrt(r (r + 1)). Zero padding (rather than
/// clamping) makes blur(f · m) / blur(m) a proper normalized convolution.
std::vector<float> blur3(std::vector<float> v, Grid g, int r) {
    if (r < 1 || v.empty()) return v;
    std::vector<float> tmp(v.size());
    const float norm = 1.0f / float(2 * r + 1);
    for (int pass = 0; pass < 3; ++pass) {
        // Running sums in double so the result does not drift along long rows.
        parallelFor(0, g.height, [&](int64_t y) {
            const float *row = &v[size_t(y) * size_t(g.width)];
            float *dst = &tmp[size_t(y) * size_t(g.width)];
            double sum = 0.0;
            for (int x = 0; x <= std::min(r, g.width - 1); ++x) sum += row[x];
            for (int x = 0; x < g.width; ++x) {
                dst[x] = float(sum) * norm;
                if (x + r + 1 < g.width) sum += row[x + r + 1];
                if (x - r >= 0) sum -= row[x - r];
            }
        }, 16);
        // Columns in blocks, walking down the rows: running sums for a whole block
        // at once keep the memory access row-wise (a column walk misses the cache).
        constexpr int kBlock = 64;
        parallelFor(0, (g.width + kBlock - 1) / kBlock, [&](int64_t b) {
            const int x0 = int(b) * kBlock, nx = std::min(kBlock, g.width - x0);
            double sum[kBlock] = {};
            auto row = [&](int y) { return &tmp[size_t(y) * size_t(g.width) + size_t(x0)]; };
            for (int y = 0; y <= std::min(r, g.height - 1); ++y)
                for (int i = 0; i < nx; ++i) sum[i] += row(y)[i];
            for (int y = 0; y < g.height; ++y) {
                float *dst = &v[size_t(y) * size_t(g.width) + size_t(x0)];
                for (int i = 0; i < nx; ++i) dst[i] = float(sum[i]) * norm;
                if (y + r + 1 < g.height)
                    for (int i = 0; i < nx; ++i) sum[i] += row(y + r + 1)[i];
                if (y - r >= 0)
                    for (int i = 0; i < nx; ++i) sum[i] -= row(y - r)[i];
            }
        }, 1);
    }
    return v;
}

/// Box radius whose three passes approximate a Gaussian of σ = spacing / 2, i.e.
/// a window about one hatch spacing wide on either side of the pixel.
int radiusFor(double spacingPx) { return std::max(1, int(std::lround(0.5 * spacingPx - 0.5))); }

/// Line orientation and coherence of one layer from its smoothed structure tensor.
struct Orientation {
    std::vector<float> angle;     ///< line direction (radians, raster frame), mod π
    std::vector<float> coherence; ///< (λ1 − λ2) / (λ1 + λ2), 0 where flat
};

Orientation orientationOf(const std::vector<float> &layerIn, Grid g, double spacingPx) {
    const size_t n = g.size();
    // Derivative of Gaussian rather than raw central differences: anti-aliased
    // one-pixel lines hold energy near the Nyquist frequency, where central
    // differences are strongly anisotropic and bias the angle by several degrees.
    const std::vector<float> layer = blur3(layerIn, g, 1);
    std::vector<float> jxx(n), jxy(n), jyy(n);
    auto at = [&](int x, int y) {
        x = std::clamp(x, 0, g.width - 1);
        y = std::clamp(y, 0, g.height - 1);
        return layer[size_t(y) * size_t(g.width) + size_t(x)];
    };
    parallelFor(0, g.height, [&](int64_t yy) {
        int y = int(yy);
        for (int x = 0; x < g.width; ++x) {
            // Scharr's 3 x 3 derivative: optimised for a rotation-invariant gradient direction.
            float gx = 3.0f * (at(x + 1, y - 1) - at(x - 1, y - 1) + at(x + 1, y + 1) - at(x - 1, y + 1)) +
                       10.0f * (at(x + 1, y) - at(x - 1, y));
            float gy = 3.0f * (at(x - 1, y + 1) - at(x - 1, y - 1) + at(x + 1, y + 1) - at(x + 1, y - 1)) +
                       10.0f * (at(x, y + 1) - at(x, y - 1));
            size_t i = size_t(y) * size_t(g.width) + size_t(x);
            jxx[i] = gx * gx;
            jxy[i] = gx * gy;
            jyy[i] = gy * gy;
        }
    }, 16);
    int r = radiusFor(spacingPx);
    jxx = blur3(std::move(jxx), g, r);
    jxy = blur3(std::move(jxy), g, r);
    jyy = blur3(std::move(jyy), g, r);
    Orientation o;
    o.angle.resize(n);
    o.coherence.resize(n);
    parallelFor(0, int64_t(n), [&](int64_t ii) {
        size_t i = size_t(ii);
        double a = jxx[i], b = jxy[i], c = jyy[i];
        double trace = a + c;
        double diff = std::sqrt((a - c) * (a - c) + 4.0 * b * b);
        // The dominant eigenvector is the gradient, across the line: turn by 90°.
        o.angle[i] = float(0.5 * std::atan2(2.0 * b, a - c) + 0.5 * kPi);
        o.coherence[i] = trace > 1e-12 ? float(diff / trace) : 0.0f;
    }, 4096);
    return o;
}

/// Unsigned angle between two line directions, modulo π, in [0, π/2].
double lineAngleBetween(double a, double b) {
    double d = std::fmod(std::fabs(a - b), kPi);
    return std::min(d, kPi - d);
}

/// Linear-interpolated quantile of sorted values, q in [0, 1].
double quantile(const std::vector<double> &sorted, double q) {
    if (sorted.empty()) return kNaN;
    double pos = q * double(sorted.size() - 1);
    size_t i = size_t(pos);
    if (i + 1 >= sorted.size()) return sorted.back();
    return sorted[i] + (pos - double(i)) * (sorted[i + 1] - sorted[i]);
}

float bilinear(const std::vector<float> &v, Grid g, double x, double y) {
    // Pixel centres sit at +0.5.
    double fx = x - 0.5, fy = y - 0.5;
    int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    double u = fx - x0, w = fy - y0;
    auto at = [&](int xi, int yi) {
        xi = std::clamp(xi, 0, g.width - 1);
        yi = std::clamp(yi, 0, g.height - 1);
        return double(v[size_t(yi) * size_t(g.width) + size_t(xi)]);
    };
    return float((at(x0, y0) * (1 - u) + at(x0 + 1, y0) * u) * (1 - w) +
                 (at(x0, y0 + 1) * (1 - u) + at(x0 + 1, y0 + 1) * u) * w);
}

/// Distances between neighbouring lines of one layer, measured along profiles
/// perpendicular to the field. Profiles start on a regular grid of confident ink
/// pixels and extend each way until the object or the even-tone region ends.
/// Returns per profile the list of distances (only profiles with >= 2).
std::vector<std::vector<double>> lineDistances(const InkMaps &maps, const std::vector<float> &layer,
                                               const Orientation &orient, double spacingPx,
                                               const InspectOptions &options) {
    const Grid g{maps.width, maps.height};
    const int step = std::max(4, int(std::lround(spacingPx)));
    const double halfLength = std::max(24.0, 4.0 * spacingPx), dt = 0.25;
    const int nSteps = int(halfLength / dt);
    const int nx = (g.width + step - 1) / step, ny = (g.height + step - 1) / step;
    std::vector<std::vector<double>> perProfile(size_t(nx) * size_t(ny));
    parallelFor(0, int64_t(nx) * ny, [&](int64_t id) {
        int x = int(id % nx) * step + step / 2, y = int(id / nx) * step + step / 2;
        if (x >= g.width || y >= g.height) return;
        size_t i = size_t(y) * size_t(g.width) + size_t(x);
        if (maps.mask[i] <= 0.5f || orient.coherence[i] < options.minCoherence) return;
        // Direction across the lines: perpendicular to the closer field angle.
        double theta = orient.angle[i];
        double phi = lineAngleBetween(theta, maps.angle0[i]) <= lineAngleBetween(theta, maps.angle1[i])
                         ? maps.angle0[i]
                         : maps.angle1[i];
        double ux = -std::sin(phi), uy = std::cos(phi);
        double cx = x + 0.5, cy = y + 0.5;
        float tone0 = maps.target[i];
        auto inside = [&](double t) {
            double px = cx + t * ux, py = cy + t * uy;
            if (px < 0 || py < 0 || px > g.width || py > g.height) return false;
            return bilinear(maps.mask, g, px, py) > 0.5f &&
                   std::fabs(bilinear(maps.target, g, px, py) - tone0) <= options.evenToneTolerance;
        };
        int lo = 0, hi = 0;
        while (lo < nSteps && inside(-(lo + 1) * dt)) ++lo;
        while (hi < nSteps && inside((hi + 1) * dt)) ++hi;
        // Centres of the runs above the ink threshold; runs cut by the profile's
        // ends are dropped since their centre is unknown.
        std::vector<double> centres;
        double sumW = 0.0, sumWT = 0.0;
        bool inRun = false, runCut = false;
        const float thr = float(options.inkThreshold);
        for (int k = -lo; k <= hi; ++k) {
            double t = k * dt;
            float v = bilinear(layer, g, cx + t * ux, cy + t * uy);
            if (v >= thr) {
                if (!inRun) {
                    inRun = true;
                    runCut = k == -lo;
                    sumW = sumWT = 0.0;
                }
                sumW += v;
                sumWT += v * t;
            } else if (inRun) {
                inRun = false;
                if (!runCut && sumW > 0) centres.push_back(sumWT / sumW);
            }
        }
        if (centres.size() < 3) return;
        auto &d = perProfile[size_t(id)];
        for (size_t k = 1; k < centres.size(); ++k) d.push_back(centres[k] - centres[k - 1]);
    }, 16);
    perProfile.erase(std::remove_if(perProfile.begin(), perProfile.end(),
                                    [](const std::vector<double> &d) { return d.size() < 2; }),
                     perProfile.end());
    return perProfile;
}

/// Separable Gaussian of σ = sigma (kernel cut at 3σ), zero outside the image.
std::vector<float> gaussianBlur(const std::vector<float> &v, Grid g, double sigma) {
    const int r = std::max(1, int(std::ceil(3.0 * sigma)));
    std::vector<float> k(size_t(2 * r + 1));
    double sum = 0.0;
    for (int i = -r; i <= r; ++i) sum += k[size_t(i + r)] = float(std::exp(-0.5 * i * i / (sigma * sigma)));
    for (float &x : k) x = float(x / sum);
    std::vector<float> tmp(v.size()), out(v.size());
    parallelFor(0, g.height, [&](int64_t y) {
        const size_t row = size_t(y) * size_t(g.width);
        for (int x = 0; x < g.width; ++x) {
            double acc = 0.0;
            for (int i = std::max(-r, -x); i <= std::min(r, g.width - 1 - x); ++i)
                acc += double(k[size_t(i + r)]) * v[row + size_t(x + i)];
            tmp[row + size_t(x)] = float(acc);
        }
    }, 16);
    parallelFor(0, g.height, [&](int64_t yy) {
        const int y = int(yy);
        for (int x = 0; x < g.width; ++x) {
            double acc = 0.0;
            for (int i = std::max(-r, -y); i <= std::min(r, g.height - 1 - y); ++i)
                acc += double(k[size_t(i + r)]) * tmp[size_t(y + i) * size_t(g.width) + size_t(x)];
            out[size_t(y) * size_t(g.width) + size_t(x)] = float(acc);
        }
    }, 16);
    return out;
}

/// seam_fraction (see InspectResult::seamFraction).
void measureSeams(const InkMaps &maps, Grid g, const InspectOptions &options, InspectResult &res) {
    const size_t n = g.size();
    const double cross = res.crossDensity;
    // Pixels at least seamEdgeDistancePx from anything off the object (or the frame).
    const double rEdge = options.seamEdgeDistancePx;
    const int ri = int(std::ceil(rEdge));
    std::vector<std::pair<int, int>> disc;
    for (int dy = -ri; dy <= ri; ++dy)
        for (int dx = -ri; dx <= ri; ++dx)
            if (dx * dx + dy * dy <= rEdge * rEdge) disc.emplace_back(dx, dy);
    auto onObject = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < g.width && y < g.height && maps.mask[size_t(y) * size_t(g.width) + size_t(x)] > 0.5f;
    };
    std::vector<uint8_t> candidate(n, 0);
    std::vector<float> m(n), cm(n);
    for (size_t i = 0; i < n; ++i) {
        m[i] = maps.mask[i] > 0.5f ? 1.0f : 0.0f;
        cm[i] = m[i] * std::clamp(maps.coverage[i], 0.0f, 1.0f);
    }
    const std::vector<float> bm = gaussianBlur(m, g, options.seamBlurSigmaPx);
    const std::vector<float> bcm = gaussianBlur(cm, g, options.seamBlurSigmaPx);
    std::vector<long long> crossPerRow(size_t(g.height), 0);
    parallelFor(0, g.height, [&](int64_t yy) {
        const int y = int(yy);
        for (int x = 0; x < g.width; ++x) {
            const size_t i = size_t(y) * size_t(g.width) + size_t(x);
            if (m[i] == 0.0f || !(maps.target[i] >= cross)) continue;
            bool interior = true;
            for (const auto &[dx, dy] : disc)
                if (!onObject(x + dx, y + dy)) {
                    interior = false;
                    break;
                }
            if (!interior) continue;
            ++crossPerRow[size_t(y)];
            const double blurred = bm[i] > 1e-6f ? double(bcm[i]) / double(bm[i]) : 0.0;
            if (blurred < options.seamCoverageRatio * double(maps.target[i])) candidate[i] = 1;
        }
    }, 8);
    long long crossPixels = 0;
    for (long long c : crossPerRow) crossPixels += c;
    // 8-connected groups of gap pixels; only groups of seamMinGroupPx or more count.
    long long seam = 0;
    std::vector<uint8_t> seen(n, 0);
    std::vector<size_t> stack, group;
    for (size_t start = 0; start < n; ++start) {
        if (!candidate[start] || seen[start]) continue;
        group.clear();
        stack.assign(1, start);
        seen[start] = 1;
        while (!stack.empty()) {
            const size_t i = stack.back();
            stack.pop_back();
            group.push_back(i);
            const int x = int(i % size_t(g.width)), y = int(i / size_t(g.width));
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= g.width || yy >= g.height) continue;
                    const size_t j = size_t(yy) * size_t(g.width) + size_t(xx);
                    if (candidate[j] && !seen[j]) {
                        seen[j] = 1;
                        stack.push_back(j);
                    }
                }
        }
        if (int(group.size()) >= options.seamMinGroupPx) {
            seam += (long long)group.size();
            if (options.keepSeamMask) {
                res.seamMask.resize(n, 0);
                for (size_t i : group) res.seamMask[i] = 1;
            }
        }
    }
    res.crossPixels = crossPixels;
    res.seamPixels = seam;
    res.seamFraction = crossPixels > 0 ? double(seam) / double(crossPixels) : kNaN;
}

/// `channels` of `maps`: empty ones zero-filled, non-finite values zeroed; a
/// non-empty channel of the wrong size is a caller bug.
void sanitize(InkMaps &maps, Grid g, std::initializer_list<std::vector<float> InkMaps::*> channels) {
    for (std::vector<float> InkMaps::*c : channels) {
        std::vector<float> &v = maps.*c;
        if (v.empty()) v.assign(g.size(), 0.0f);
        ROSY_CHECK_EQ(v.size(), g.size());
        for (float &x : v)
            if (!std::isfinite(x)) x = 0.0f;
    }
}

} // namespace

InspectResult inspectSeams(const InkMaps &mapsIn, const InspectOptions &options) {
    InspectResult res;
    res.alignmentMedianDeg = res.alignmentP90Deg = res.toneMae = res.spacingCv = res.seamFraction = kNaN;
    res.measuredSpacingPx = res.hatchSpacingPx = kNaN;
    const Grid g{std::max(0, mapsIn.width), std::max(0, mapsIn.height)};
    if (g.size() == 0) return res;
    // Only the three channels the seams read are copied.
    InkMaps maps;
    maps.width = mapsIn.width;
    maps.height = mapsIn.height;
    maps.coverage = mapsIn.coverage;
    maps.target = mapsIn.target;
    maps.mask = mapsIn.mask;
    sanitize(maps, g, {&InkMaps::coverage, &InkMaps::target, &InkMaps::mask});
    res.crossDensity = std::isfinite(mapsIn.crossDensity) ? mapsIn.crossDensity : options.crossDensity;
    measureSeams(maps, g, options, res);
    return res;
}

InspectResult inspectInk(const InkMaps &mapsIn, const InspectOptions &options) {
    InspectResult res;
    InkMaps maps = mapsIn;
    const Grid g{std::max(0, maps.width), std::max(0, maps.height)};
    const size_t n = g.size();
    sanitize(maps, g, {&InkMaps::hatch0, &InkMaps::hatch1, &InkMaps::coverage, &InkMaps::target, &InkMaps::angle0,
                       &InkMaps::angle1, &InkMaps::mask});
    res.alignmentMedianDeg = res.alignmentP90Deg = res.toneMae = res.spacingCv = res.seamFraction = kNaN;
    res.measuredSpacingPx = kNaN;
    res.hatchSpacingPx = maps.hatchSpacingPx > 0 ? maps.hatchSpacingPx : options.fallbackSpacingPx;
    if (n == 0) return res;
    const std::vector<float> *layers[2] = {&maps.hatch0, &maps.hatch1};

    // Spacing first: without a header value it sets the scale of everything else.
    auto measureSpacing = [&](double spacing, Orientation *orient) {
        std::vector<std::vector<double>> profiles;
        for (int l = 0; l < 2; ++l) {
            orient[l] = orientationOf(*layers[l], g, spacing);
            auto p = lineDistances(maps, *layers[l], orient[l], spacing, options);
            profiles.insert(profiles.end(), p.begin(), p.end());
        }
        return profiles;
    };
    Orientation orient[2];
    std::vector<std::vector<double>> profiles = measureSpacing(res.hatchSpacingPx, orient);
    std::vector<double> raw;
    for (const auto &p : profiles) raw.insert(raw.end(), p.begin(), p.end());
    std::sort(raw.begin(), raw.end());
    res.measuredSpacingPx = quantile(raw, 0.5);
    if (maps.hatchSpacingPx <= 0 && std::isfinite(res.measuredSpacingPx)) {
        // Without a header value the measured spacing sets the scale; if the
        // fallback scale was far off, measure again at the measured one.
        bool farOff = std::fabs(res.measuredSpacingPx - res.hatchSpacingPx) > 0.25 * res.hatchSpacingPx;
        res.hatchSpacingPx = res.measuredSpacingPx;
        if (farOff) profiles = measureSpacing(res.hatchSpacingPx, orient);
    }
    {
        double sum2 = 0.0;
        long long count = 0;
        for (const auto &p : profiles) {
            double mean = 0.0;
            for (double d : p) mean += d;
            mean /= double(p.size());
            for (double d : p) {
                double e = d / mean - 1.0;
                sum2 += e * e;
                ++count;
            }
        }
        res.spacingSamples = count;
        if (count > 0) res.spacingCv = std::sqrt(sum2 / double(count));
    }

    // Alignment: each confident hatch pixel against the closer field angle.
    {
        std::vector<double> angles;
        for (int l = 0; l < 2; ++l)
            for (size_t i = 0; i < n; ++i) {
                if ((*layers[l])[i] < options.inkThreshold || maps.mask[i] <= 0.5f ||
                    orient[l].coherence[i] < options.minCoherence)
                    continue;
                double theta = orient[l].angle[i];
                double e = std::min(lineAngleBetween(theta, maps.angle0[i]),
                                    lineAngleBetween(theta, maps.angle1[i]));
                angles.push_back(e * 180.0 / kPi);
            }
        std::sort(angles.begin(), angles.end());
        res.alignmentSamples = (long long)angles.size();
        res.alignmentMedianDeg = quantile(angles, 0.5);
        res.alignmentP90Deg = quantile(angles, 0.9);
    }

    // Tone: hatch coverage blurred over the object only, against the target.
    {
        std::vector<float> m(n), cm(n);
        for (size_t i = 0; i < n; ++i) {
            m[i] = maps.mask[i] > 0.5f ? 1.0f : 0.0f;
            float h = 1.0f - (1.0f - std::clamp(maps.hatch0[i], 0.0f, 1.0f)) *
                                 (1.0f - std::clamp(maps.hatch1[i], 0.0f, 1.0f));
            cm[i] = h * m[i];
        }
        int r = radiusFor(res.hatchSpacingPx);
        std::vector<float> bm = blur3(m, g, r), bcm = blur3(cm, g, r);
        double sum = 0.0;
        long long count = 0;
        for (size_t i = 0; i < n; ++i) {
            if (m[i] == 0.0f || bm[i] <= 1e-6f) continue;
            sum += std::fabs(double(maps.target[i]) - double(bcm[i]) / double(bm[i]));
            ++count;
        }
        res.tonePixels = count;
        if (count > 0) res.toneMae = sum / double(count);
    }

    // Ink beyond the one-pixel anti-aliasing border of the silhouette.
    {
        long long count = 0;
        for (int y = 0; y < g.height; ++y)
            for (int x = 0; x < g.width; ++x) {
                size_t i = size_t(y) * size_t(g.width) + size_t(x);
                if (maps.coverage[i] < options.inkThreshold || maps.mask[i] > 0.5f) continue;
                bool nearObject = false;
                for (int dy = -1; dy <= 1 && !nearObject; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        int xx = x + dx, yy = y + dy;
                        if (xx < 0 || yy < 0 || xx >= g.width || yy >= g.height) continue;
                        if (maps.mask[size_t(yy) * size_t(g.width) + size_t(xx)] > 0.5f) {
                            nearObject = true;
                            break;
                        }
                    }
                if (!nearObject) ++count;
            }
        res.inkOutsideSilhouettePx = count;
    }

    res.crossDensity = std::isfinite(maps.crossDensity) ? maps.crossDensity : options.crossDensity;
    measureSeams(maps, g, options, res);
    return res;
}

std::string inspectJson(const InspectResult &r) {
    JsonWriter w;
    w.beginObject();
    w.field("alignment_median_deg", r.alignmentMedianDeg);
    w.field("alignment_p90_deg", r.alignmentP90Deg);
    w.field("tone_mae", r.toneMae);
    w.field("spacing_cv", r.spacingCv);
    w.field("ink_outside_silhouette_px", r.inkOutsideSilhouettePx);
    w.field("seam_fraction", r.seamFraction);
    w.field("alignment_samples", r.alignmentSamples);
    w.field("tone_pixels", r.tonePixels);
    w.field("spacing_samples", r.spacingSamples);
    w.field("measured_spacing_px", r.measuredSpacingPx);
    w.field("hatch_spacing_px", r.hatchSpacingPx);
    w.field("seam_pixels", r.seamPixels);
    w.field("cross_pixels", r.crossPixels);
    w.field("cross_density", r.crossDensity);
    w.endObject();
    return w.str();
}

Image seamPicture(const InkMaps &maps, const InspectResult &result) {
    Image out(maps.width, maps.height, {"R", "G", "B"});
    const size_t n = size_t(maps.width) * size_t(maps.height);
    for (size_t i = 0; i < n; ++i) {
        const bool seam = i < result.seamMask.size() && result.seamMask[i];
        const float grey = 1.0f - 0.8f * std::clamp(i < maps.coverage.size() ? maps.coverage[i] : 0.0f, 0.0f, 1.0f);
        out.data[3 * i + 0] = seam ? 1.0f : grey;
        out.data[3 * i + 1] = seam ? 0.0f : grey;
        out.data[3 * i + 2] = seam ? 0.0f : grey;
    }
    return out;
}

} // namespace rosy::renderer
