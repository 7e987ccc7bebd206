#include "renderer/evaluation/image_diff.h"

#include "core/error.h"
#include "core/parallel.h"
#include "renderer/output/raster.h"

#include "renderer/output/image_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace rosy::renderer {

const char *toString(DiffVerdict verdict) {
    switch (verdict) {
    case DiffVerdict::Pass: return "PASS";
    case DiffVerdict::Warn: return "WARNING";
    case DiffVerdict::Fail: return "FAILURE";
    }
    return "";
}

namespace {

double srgbToLinear(double v) {
    if (!(v > 0.0)) return 0.0;
    if (v >= 1.0) return 1.0;
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

int channelIndex(const Image &image, const std::string &name) {
    for (int c = 0; c < image.nChannels; ++c)
        if (image.channelNames[size_t(c)] == name) return c;
    return -1;
}

std::vector<float> channel(const Image &image, int c) {
    const size_t n = size_t(image.width) * size_t(image.height);
    std::vector<float> out(n, 0.0f);
    if (c < 0) return out;
    for (size_t i = 0; i < n; ++i) {
        float v = image.data[i * size_t(image.nChannels) + size_t(c)];
        out[i] = std::isfinite(v) ? v : 0.0f;
    }
    return out;
}

/// Linear luminance (Rec. 709 weights) per pixel; a single-channel or grey+alpha
/// image is its first channel.
std::vector<float> luminance(const Image &image) {
    int r = channelIndex(image, "R"), g = channelIndex(image, "G"), b = channelIndex(image, "B");
    if (r < 0 || g < 0 || b < 0) {
        if (image.nChannels >= 3 && channelIndex(image, "A") != 0) {
            r = 0, g = 1, b = 2; // unnamed colour channels
        } else {
            return channel(image, 0);
        }
    }
    std::vector<float> cr = channel(image, r), cg = channel(image, g), cb = channel(image, b);
    std::vector<float> out(cr.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = 0.2126f * cr[i] + 0.7152f * cg[i] + 0.0722f * cb[i];
    return out;
}

struct Paper {
    double luminance = 1.0;
    double rgb[3] = {1.0, 1.0, 1.0};
};

/// The paper is what most of a drawing shows and the brightest thing in it; with
/// grain it varies by a few percent, so take a high percentile, not the maximum
/// (one bright pixel of noise must not darken the whole coverage estimate).
Paper estimatePaper(const Image &image, const std::vector<float> &lum) {
    Paper paper;
    if (lum.empty()) return paper;
    std::vector<float> sorted = lum;
    const size_t k = std::min(sorted.size() - 1, size_t(std::floor(0.995 * double(sorted.size() - 1))));
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(k), sorted.end());
    const double level = sorted[k];
    paper.luminance = level;
    int idx[3] = {channelIndex(image, "R"), channelIndex(image, "G"), channelIndex(image, "B")};
    if (idx[0] < 0 || idx[1] < 0 || idx[2] < 0) {
        for (double &c : paper.rgb) c = level;
        return paper;
    }
    double sum[3] = {0, 0, 0};
    long long count = 0;
    for (size_t i = 0; i < lum.size(); ++i) {
        if (lum[i] < level) continue;
        for (int c = 0; c < 3; ++c) {
            float v = image.data[i * size_t(image.nChannels) + size_t(idx[c])];
            sum[c] += std::isfinite(v) ? v : 0.0;
        }
        ++count;
    }
    for (int c = 0; c < 3; ++c) paper.rgb[c] = count > 0 ? sum[c] / double(count) : level;
    return paper;
}

std::vector<float> coverageOf(const std::vector<float> &lum, double paperLum) {
    std::vector<float> out(lum.size());
    // An all-black picture has no paper to measure against: read it as full ink.
    const double denom = paperLum > 1e-6 ? paperLum : 1.0;
    for (size_t i = 0; i < lum.size(); ++i) out[i] = float(std::clamp(1.0 - double(lum[i]) / denom, 0.0, 1.0));
    return out;
}

/// Min and max over the (2r + 1)² window around every pixel (edges clamped):
/// separable, rows then columns.
void windowRange(const std::vector<float> &v, int w, int h, int r, std::vector<float> &lo,
                 std::vector<float> &hi) {
    lo = v;
    hi = v;
    if (r <= 0) return;
    std::vector<float> tlo(v.size()), thi(v.size());
    parallelFor(0, h, [&](int64_t y) {
        for (int x = 0; x < w; ++x) {
            float mn = v[size_t(y) * size_t(w) + size_t(x)], mx = mn;
            for (int d = -r; d <= r; ++d) {
                int xx = std::clamp(x + d, 0, w - 1);
                float s = v[size_t(y) * size_t(w) + size_t(xx)];
                mn = std::min(mn, s);
                mx = std::max(mx, s);
            }
            tlo[size_t(y) * size_t(w) + size_t(x)] = mn;
            thi[size_t(y) * size_t(w) + size_t(x)] = mx;
        }
    }, 8);
    parallelFor(0, h, [&](int64_t y) {
        for (int x = 0; x < w; ++x) {
            float mn = tlo[size_t(y) * size_t(w) + size_t(x)], mx = thi[size_t(y) * size_t(w) + size_t(x)];
            for (int d = -r; d <= r; ++d) {
                int yy = std::clamp(int(y) + d, 0, h - 1);
                mn = std::min(mn, tlo[size_t(yy) * size_t(w) + size_t(x)]);
                mx = std::max(mx, thi[size_t(yy) * size_t(w) + size_t(x)]);
            }
            lo[size_t(y) * size_t(w) + size_t(x)] = mn;
            hi[size_t(y) * size_t(w) + size_t(x)] = mx;
        }
    }, 8);
}

float outside(float v, float lo, float hi) { return v < lo ? lo - v : (v > hi ? v - hi : 0.0f); }

/// Shift-tolerant difference of two blurred maps: how far each pixel of one lies
/// outside the range the other takes within r pixels, the larger of both
/// directions (so the measure is symmetric). Also the signed B − A for the diff image.
std::vector<float> tolerantDiff(const std::vector<float> &a, const std::vector<float> &b, int w, int h, int r) {
    std::vector<float> aLo, aHi, bLo, bHi;
    windowRange(a, w, h, r, aLo, aHi);
    windowRange(b, w, h, r, bLo, bHi);
    std::vector<float> out(a.size());
    for (size_t i = 0; i < a.size(); ++i)
        out[i] = std::max(outside(a[i], bLo[i], bHi[i]), outside(b[i], aLo[i], aHi[i]));
    return out;
}

void checkOption(double value, const char *name) {
    if (!std::isfinite(value) || value < 0.0)
        throw InputError(FileLoc{name}, std::string(name) + " must be a finite number >= 0",
                         "give a threshold such as 0.02 (coverage, 0..1) or a percentage such as 0.1");
}

ChannelDiff statsOf(const std::string &name, const std::vector<float> &err, int w, const DiffOptions &opt) {
    ChannelDiff d;
    d.name = name;
    double sum = 0.0;
    for (size_t i = 0; i < err.size(); ++i) {
        const double e = err[i];
        sum += e;
        if (e > d.maxError) {
            d.maxError = e;
            d.maxX = int(i % size_t(w));
            d.maxY = int(i / size_t(w));
        }
        if (e > opt.fail) ++d.nFail;
        if (e > opt.warn) ++d.nWarn;
    }
    const double n = double(std::max<size_t>(err.size(), 1));
    d.meanError = sum / n;
    d.failPercent = 100.0 * double(d.nFail) / n;
    if (double(d.nFail) > opt.failPercent / 100.0 * n || d.maxError > opt.hardFail)
        d.verdict = DiffVerdict::Fail;
    else if (double(d.nWarn) > opt.warnPercent / 100.0 * n)
        d.verdict = DiffVerdict::Warn;
    return d;
}

} // namespace

std::vector<float> gaussianBlur(const std::vector<float> &values, int width, int height, double sigmaPx) {
    ROSY_CHECK_EQ(values.size(), size_t(std::max(width, 0)) * size_t(std::max(height, 0)));
    if (!(sigmaPx > 0.0) || values.empty()) return values;
    const int radius = std::max(1, int(std::ceil(3.0 * sigmaPx)));
    std::vector<float> kernel(size_t(2 * radius + 1));
    double total = 0.0;
    for (int k = -radius; k <= radius; ++k) total += kernel[size_t(k + radius)] = float(std::exp(-0.5 * k * k / (sigmaPx * sigmaPx)));
    for (float &k : kernel) k = float(k / total);
    const size_t w = size_t(width);
    std::vector<float> tmp(values.size()), out(values.size());
    // Each output row depends only on the input, so rows run in parallel and the
    // result is the same for any thread count.
    parallelFor(0, height, [&](int64_t y) {
        for (int x = 0; x < width; ++x) {
            double s = 0.0;
            for (int k = -radius; k <= radius; ++k)
                s += kernel[size_t(k + radius)] * values[size_t(y) * w + size_t(std::clamp(x + k, 0, width - 1))];
            tmp[size_t(y) * w + size_t(x)] = float(s);
        }
    }, 8);
    parallelFor(0, height, [&](int64_t y) {
        for (int x = 0; x < width; ++x) {
            double s = 0.0;
            for (int k = -radius; k <= radius; ++k)
                s += kernel[size_t(k + radius)] * tmp[size_t(std::clamp(int(y) + k, 0, height - 1)) * w + size_t(x)];
            out[size_t(y) * w + size_t(x)] = float(s);
        }
    }, 8);
    return out;
}

DiffInput readDiffInput(const std::string &path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path, "no such file (or not a regular file)");
    std::string error;
    std::unique_ptr<ImageFileReader> in = imageIo().open(path, error);
    if (!in)
        throw InputError(FileLoc{path}, "not an image OpenImageIO can read: " + error,
                         "compare two images, e.g. the .png or .exr written by rosyhatch render");
    const ImageFileHeader &spec = in->header();
    if (spec.width < 1 || spec.height < 1 || spec.depth > 1 || spec.nChannels < 1)
        throw InputError(FileLoc{path}, "not a 2D image with pixels");
    // Refuse absurd headers before allocating (a 16-bit PNG may claim 2^31 pixels).
    const double nValues = double(spec.width) * double(spec.height) * double(spec.nChannels);
    if (nValues > double(1u << 30))
        throw InputError(FileLoc{path}, "image too large to compare (" + std::to_string(spec.width) + "x" +
                                            std::to_string(spec.height) + "x" + std::to_string(spec.nChannels) + ")",
                         "compare images of at most 2^30 channel values");
    std::vector<std::string> names = spec.channelNames;
    names.resize(size_t(spec.nChannels));
    for (size_t c = 0; c < names.size(); ++c)
        if (names[c].empty()) names[c] = "channel" + std::to_string(c);
    DiffInput result;
    result.image = Image(spec.width, spec.height, names);
    if (!in->readFloat(result.image.data.data(), error)) throw IoError(path, "cannot read the pixels: " + error);
    const bool floating = spec.floating;
    const std::string &colorSpace = spec.colorSpace;
    const bool linear = floating || colorSpace == "Linear" || colorSpace == "linear";
    const size_t nc = size_t(spec.nChannels);
    if (!linear) {
        for (size_t i = 0; i < result.image.data.size(); ++i)
            if (int(i % nc) != spec.alphaChannel) result.image.data[i] = float(srgbToLinear(result.image.data[i]));
    }
    // Premultiplied colour (OpenEXR's convention, rosyhatch's ink matte): what the
    // eye reads is the picture over white paper, colour + (1 − alpha).
    if (floating && spec.alphaChannel >= 0 && spec.alphaChannel < spec.nChannels &&
        in->floatAttribute("oiio:UnassociatedAlpha", 0.0f) == 0.0f) {
        const std::vector<std::string> &cn = result.image.channelNames;
        const size_t a = size_t(spec.alphaChannel);
        for (size_t c = 0; c < nc; ++c) {
            if (cn[c] != "R" && cn[c] != "G" && cn[c] != "B") continue;
            for (size_t i = 0; i < result.image.data.size(); i += nc) {
                const float alpha = result.image.data[i + a];
                if (std::isfinite(alpha)) result.image.data[i + c] += 1.0f - std::clamp(alpha, 0.0f, 1.0f);
            }
        }
    }
    const float spacing = in->floatAttribute(kHatchSpacingAttribute, 0.0f);
    result.hatchSpacingPx = std::isfinite(spacing) && spacing > 0.0f ? double(spacing) : 0.0;
    return result;
}

DiffResult compareImages(const Image &a, const Image &b, const DiffOptions &options, double hatchSpacingPx) {
    checkOption(options.fail, "--fail");
    checkOption(options.failPercent, "--failpercent");
    checkOption(options.hardFail, "--hardfail");
    checkOption(options.warn, "--warn");
    checkOption(options.warnPercent, "--warnpercent");
    checkOption(options.blurPx, "--blur");
    checkOption(options.shiftPx, "--shift");
    if (options.blurPx > 1000 || options.shiftPx > 1000)
        throw InputError(FileLoc{"--blur"}, "blur and shift are limited to 1000 pixels",
                         "blur at about half the hatch spacing (a few pixels)");

    DiffResult result;
    result.width = a.width;
    result.height = a.height;
    result.blurPx = options.blurPx > 0 ? options.blurPx : (hatchSpacingPx > 0 ? 0.5 * hatchSpacingPx : kDefaultBlurPx);
    result.shiftPx = std::round(options.shiftPx);
    if (a.width != b.width || a.height != b.height) {
        result.mismatch = "images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                          " against " + std::to_string(b.width) + "x" + std::to_string(b.height);
        result.verdict = DiffVerdict::Fail;
        return result;
    }
    if (a.width < 1 || a.height < 1 || a.nChannels < 1 || b.nChannels < 1)
        throw InputError(FileLoc{}, "cannot compare images without pixels");
    const int w = a.width, h = a.height, r = int(result.shiftPx);
    const double sigma = result.blurPx;
    auto blur = [&](const std::vector<float> &v) { return gaussianBlur(v, w, h, sigma); };

    // Coverage and paper from the pictures themselves.
    const std::vector<float> lumA = luminance(a), lumB = luminance(b);
    const Paper paperA = estimatePaper(a, lumA), paperB = estimatePaper(b, lumB);
    const std::vector<float> covA = blur(coverageOf(lumA, paperA.luminance));
    const std::vector<float> covB = blur(coverageOf(lumB, paperB.luminance));
    const std::vector<float> covErr = tolerantDiff(covA, covB, w, h, r);
    result.channels.push_back(statsOf("coverage", covErr, w, options));
    {
        double e = 0.0;
        for (int c = 0; c < 3; ++c) e = std::max(e, std::abs(paperA.rgb[c] - paperB.rgb[c]));
        ChannelDiff paper = statsOf("paper", std::vector<float>{float(e)}, 1, options);
        paper.maxX = paper.maxY = -1;
        result.channels.push_back(paper);
    }

    const bool exr = options.exrChannels && channelIndex(a, "mask") >= 0 && channelIndex(b, "mask") >= 0;
    if (exr) {
        for (const char *name :
             {"tone.target", "ink.coverage", "ink.hatch0", "ink.hatch1", "ink.contour", "ink.hidden", "mask"}) {
            const int ia = channelIndex(a, name), ib = channelIndex(b, name);
            if (ia < 0 || ib < 0) continue;
            result.channels.push_back(
                statsOf(name, tolerantDiff(blur(channel(a, ia)), blur(channel(b, ib)), w, h, r), w, options));
        }
        // Depth: Z (+inf where nothing is seen, read as 0 here like the former `depth`
        // channel's background), or `depth` in EXRs written before Z.
        const char *depthName = channelIndex(a, "Z") >= 0 && channelIndex(b, "Z") >= 0 ? "Z" : "depth";
        const int da = channelIndex(a, depthName), db = channelIndex(b, depthName);
        if (da >= 0 && db >= 0) {
            std::vector<float> za = channel(a, da), zb = channel(b, db);
            float scale = 0.0f;
            for (float z : za) scale = std::max(scale, std::abs(z));
            for (float z : zb) scale = std::max(scale, std::abs(z));
            if (scale > 0.0f)
                for (size_t i = 0; i < za.size(); ++i) za[i] /= scale, zb[i] /= scale;
            result.channels.push_back(statsOf(depthName, tolerantDiff(blur(za), blur(zb), w, h, r), w, options));
        }
        // Vector-valued channels: tolerate each component, then combine the
        // components' excesses into one length.
        auto vectorChannel = [&](const std::string &name, const std::vector<std::vector<float>> &ca,
                                 const std::vector<std::vector<float>> &cb, double scale) {
            std::vector<float> err(size_t(w) * size_t(h), 0.0f);
            for (size_t k = 0; k < ca.size(); ++k) {
                const std::vector<float> e = tolerantDiff(blur(ca[k]), blur(cb[k]), w, h, r);
                for (size_t i = 0; i < err.size(); ++i) err[i] += e[i] * e[i];
            }
            for (float &e : err) e = float(std::sqrt(double(e)) * scale);
            result.channels.push_back(statsOf(name, err, w, options));
        };
        const int nxa = channelIndex(a, "N.x"), nya = channelIndex(a, "N.y"), nza = channelIndex(a, "N.z");
        const int nxb = channelIndex(b, "N.x"), nyb = channelIndex(b, "N.y"), nzb = channelIndex(b, "N.z");
        if (nxa >= 0 && nya >= 0 && nza >= 0 && nxb >= 0 && nyb >= 0 && nzb >= 0)
            vectorChannel("normal", {channel(a, nxa), channel(a, nya), channel(a, nza)},
                          {channel(b, nxb), channel(b, nyb), channel(b, nzb)}, 0.5);
        // The filter-safe field pair (cos Kθ, sin Kθ): a vector already, compared as one.
        {
            const int ca = channelIndex(a, "field.cos"), sa = channelIndex(a, "field.sin");
            const int cb = channelIndex(b, "field.cos"), sb = channelIndex(b, "field.sin");
            if (ca >= 0 && sa >= 0 && cb >= 0 && sb >= 0)
                vectorChannel("field.cos/sin", {channel(a, ca), channel(a, sa)}, {channel(b, cb), channel(b, sb)}, 0.5);
        }
        const std::vector<float> maskA = channel(a, channelIndex(a, "mask")), maskB = channel(b, channelIndex(b, "mask"));
        for (const char *name : {"field.angle0", "field.angle1"}) {
            const int ia = channelIndex(a, name), ib = channelIndex(b, name);
            if (ia < 0 || ib < 0) continue;
            // Lines are defined modulo π: compare the doubled angle as a unit vector,
            // weighted by the mask so the background (angle 0 by convention) adds nothing.
            auto doubled = [](const std::vector<float> &angle, const std::vector<float> &mask) {
                std::vector<std::vector<float>> v(2, std::vector<float>(angle.size()));
                for (size_t i = 0; i < angle.size(); ++i) {
                    const double m = std::clamp(double(mask[i]), 0.0, 1.0);
                    v[0][i] = float(m * std::cos(2.0 * angle[i]));
                    v[1][i] = float(m * std::sin(2.0 * angle[i]));
                }
                return v;
            };
            vectorChannel(name, doubled(channel(a, ia), maskA), doubled(channel(b, ib), maskB), 0.5);
        }
    }
    for (const ChannelDiff &c : result.channels) result.verdict = std::max(result.verdict, c.verdict);

    // The amplified picture: A faint, the coverage change in colour.
    result.diffImage = Image(w, h, {"R", "G", "B"});
    const double full = 2.0 * std::max(options.fail, 1e-6);
    for (size_t i = 0; i < covErr.size(); ++i) {
        const double base = 1.0 - 0.25 * std::clamp(double(covA[i]) * 2.0, 0.0, 1.0);
        const double t = std::clamp(double(covErr[i]) / full, 0.0, 1.0);
        const bool moreInk = covB[i] > covA[i];
        const double red[3] = {1.0, 0.0, 0.0}, blue[3] = {0.0, 0.25, 1.0};
        for (int c = 0; c < 3; ++c) {
            const double target = moreInk ? red[c] : blue[c];
            result.diffImage.data[i * 3 + size_t(c)] = float(base * (1.0 - t) + target * t);
        }
    }
    return result;
}

DiffResult compareImageFiles(const std::string &pathA, const std::string &pathB, const DiffOptions &options) {
    const DiffInput a = readDiffInput(pathA);
    const DiffInput b = readDiffInput(pathB);
    return compareImages(a.image, b.image, options, a.hatchSpacingPx);
}

std::string diffReportText(const DiffResult &result, const DiffOptions &options) {
    std::ostringstream os;
    if (!result.mismatch.empty()) {
        os << result.mismatch << "\n" << toString(result.verdict) << "\n";
        return os.str();
    }
    os << "compared " << result.width << "x" << result.height << " with blur sigma " << result.blurPx
       << " px, shift tolerance " << result.shiftPx << " px; fail " << options.fail << " (" << options.failPercent
       << "% allowed), hardfail " << options.hardFail << ", warn " << options.warn << " (" << options.warnPercent
       << "% allowed)\n";
    for (const ChannelDiff &c : result.channels) {
        os << "  " << std::left << std::setw(13) << c.name << std::right << " max " << std::fixed
           << std::setprecision(4) << c.maxError;
        if (c.maxX >= 0) os << " @ (" << c.maxX << ", " << c.maxY << ")";
        os << "  mean " << std::setprecision(5) << c.meanError << "  " << c.nFail << " pixels ("
           << std::setprecision(3) << c.failPercent << "%) over " << std::defaultfloat << options.fail;
        if (c.verdict != DiffVerdict::Pass) os << "  " << toString(c.verdict);
        os << "\n";
    }
    os << toString(result.verdict) << "\n";
    return os.str();
}

} // namespace rosy::renderer
