#include "core/json.h"
#include "field/design.h"
#include "field/frames.h"
#include "field/primitives.h"
#include "field/separatrices.h"
#include "field/singularities.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace rosy::field;

namespace {

/// Rays θ ∈ [0, 2π) from a brute-force scan of Eq. 9 for sign changes, classified by Eq. 8
/// (outgoing: Nθ ≡ arg(Jv)) and Eq. 12 (incoming, odd N: Nθ ≡ arg(Jv) + π).
std::vector<SeparatrixDirection> bruteForce(const Eigen::Matrix2d &j, int n) {
    auto f = [&](double t) {
        return std::sin(n * t) * (j(0, 0) * std::cos(t) + j(0, 1) * std::sin(t)) -
               std::cos(n * t) * (j(1, 0) * std::cos(t) + j(1, 1) * std::sin(t));
    };
    std::vector<SeparatrixDirection> out;
    const int steps = 200000;
    const double h = 2 * M_PI / steps;
    for (int i = 0; i < steps; ++i) {
        double a = i * h + 1e-9, b = a + h; // offset: keep a scan point off exact roots like θ = 0
        if (f(a) * f(b) > 0) continue;
        for (int it = 0; it < 60; ++it) {
            double m = 0.5 * (a + b);
            (f(a) * f(m) <= 0 ? b : a) = m;
        }
        double t = 0.5 * (a + b);
        if (t > 2 * M_PI - 1e-6) t -= 2 * M_PI; // the root at θ = 0 is found at the end of the scan
        Eigen::Vector2d w = j * Eigen::Vector2d(std::cos(t), std::sin(t));
        double diff = wrapAngle(n * t - std::atan2(w.y(), w.x()));
        if (std::abs(diff) < 1e-3) out.push_back({t, false});
        else if (n % 2 == 1 && std::abs(std::abs(diff) - M_PI) < 1e-3) out.push_back({t, true});
    }
    std::sort(out.begin(), out.end(),
              [](const SeparatrixDirection &x, const SeparatrixDirection &y) { return x.angleRad < y.angleRad; });
    return out;
}

int countIncoming(const std::vector<Separatrix> &s, bool incoming) {
    int c = 0;
    for (const Separatrix &x : s) c += x.incoming == incoming;
    return c;
}

/// Disk with one designed singularity of order L at the centre; its separatrices.
std::vector<Separatrix> designedSeparatrices(int nSym, int order, double phase, int &nSingularities) {
    Mesh m = makeDisk(12);
    TangentFrames fr(m);
    DesignElement e;
    e.position = Vec3(0.01, 0.02, 0);
    e.order = order;
    e.phaseRad = phase;
    RosyField f = designField(fr, nSym, {e});
    SingularityReport rep = findSingularities(fr, f);
    nSingularities = int(rep.singularities.size());
    SeparatrixOptions opt;
    opt.maxLengthRelative = 2;
    std::vector<Separatrix> seps = traceSeparatrices(fr, f, rep.singularities, opt);
    for (const Separatrix &s : seps) {
        EXPECT_EQ(s.line.stop, StreamlineStop::Boundary) << "N = " << nSym << " L = " << order;
        for (const Vec3 &p : s.line.points) EXPECT_TRUE(p.allFinite());
    }
    return seps;
}

} // namespace

TEST(SeparatrixDirections, MatchBruteForceScanOfHandBuiltFace) {
    // One triangle whose corner values come from a known linear field u(p) = J (p − p*).
    Mesh m = Mesh::fromTriangles({Vec3(0, 0, 0), Vec3(1, 0.1, 0), Vec3(0.3, 0.8, 0)}, {Face{0, 1, 2}});
    TangentFrames fr(m);
    const Vec2 pStar(0.4, 0.3);
    const Eigen::Matrix2d jacobians[] = {
        (Eigen::Matrix2d() << 1, 0, 0, -1).finished(),     // saddle-like
        (Eigen::Matrix2d() << 0.7, 0.4, -0.2, 1.3).finished(),
        (Eigen::Matrix2d() << -0.3, 1.1, 0.9, 0.5).finished(),
        (Eigen::Matrix2d() << 0.2, -1.0, 1.0, 0.3).finished(), // spiral
    };
    for (const Eigen::Matrix2d &j : jacobians) {
        for (int n : {1, 2, 3, 4, 5, 6}) {
            RosyField f{n, Eigen::VectorXcd(3)};
            for (int c = 0; c < 3; ++c) {
                Vec2 q = fr.toFace2D(0, m.position(c));
                Vec2 w = j * (q - pStar);
                // Face-frame value back into the vertex frame (inverse of faceValues' rotation).
                f.u[c] = Complex(w.x(), w.y()) * std::polar(1.0, -n * fr.vertexToFace(c));
            }
            Eigen::Matrix2d jf = faceJacobian(fr, f, 0);
            EXPECT_LT((jf - j).norm(), 1e-9);
            std::vector<SeparatrixDirection> got = separatrixDirections(jf, n);
            std::vector<SeparatrixDirection> want = bruteForce(j, n);
            ASSERT_EQ(got.size(), want.size()) << "N = " << n << "\nJ =\n" << j;
            for (const SeparatrixDirection &w : want) {
                int matches = 0;
                for (const SeparatrixDirection &g : got) {
                    EXPECT_GE(g.angleRad, 0.0);
                    EXPECT_LT(g.angleRad, 2 * M_PI);
                    matches += std::abs(wrapAngle(g.angleRad - w.angleRad)) < 1e-6 && g.incoming == w.incoming;
                }
                EXPECT_EQ(matches, 1) << "N = " << n << " θ = " << w.angleRad << " incoming " << w.incoming;
            }
        }
    }
}

TEST(SeparatrixDirections, VerticalRootIsFound) {
    // J = [[0, 1], [1, 0]]: arg Jv = π/2 − θ, and Eq. 9's t³ coefficient (here d) vanishes,
    // so the root at θ = 3π/2 is at t = ∞ and has to be found by the cos θ = 0 check.
    Eigen::Matrix2d j;
    j << 0, 1, 1, 0;
    // N = 2: 2θ ≡ π/2 − θ → θ = π/6 + 2πk/3: π/6, 5π/6, 3π/2.
    std::vector<SeparatrixDirection> got = separatrixDirections(j, 2);
    ASSERT_EQ(got.size(), 3u);
    EXPECT_NEAR(got[0].angleRad, M_PI / 6, 1e-9);
    EXPECT_NEAR(got[1].angleRad, 5 * M_PI / 6, 1e-9);
    EXPECT_NEAR(got[2].angleRad, 3 * M_PI / 2, 1e-9);
}

TEST(SeparatrixDirections, SourceAndCentreHaveNoneForN1) {
    // N = 1 source (J = I): Eq. 9 ≡ 0; centre (J = rotation by π/2): Eq. 9 ≡ −1.
    EXPECT_TRUE(separatrixDirections(Eigen::Matrix2d::Identity(), 1).empty());
    Eigen::Matrix2d centre;
    centre << 0, -1, 1, 0;
    EXPECT_TRUE(separatrixDirections(centre, 1).empty());
    EXPECT_TRUE(separatrixDirections(Eigen::Matrix2d::Zero(), 4).empty());
}

TEST(Separatrices, NegativeFirstOrderHasNPlusOneOutgoing) {
    for (int n : {1, 2, 3, 4, 6}) {
        int nSing = 0;
        std::vector<Separatrix> s = designedSeparatrices(n, -1, 0.0, nSing);
        ASSERT_EQ(nSing, 1) << "N = " << n;
        // (N + 1)θ ≡ c: N + 1 outgoing rays; odd N adds N + 1 incoming ones (N = 1: a saddle's 2 + 2).
        EXPECT_EQ(countIncoming(s, false), n + 1) << "N = " << n;
        EXPECT_EQ(countIncoming(s, true), n % 2 == 1 ? n + 1 : 0) << "N = " << n;
    }
}

TEST(Separatrices, PositiveFirstOrderHasNMinusOneOutgoing) {
    for (int n : {2, 3, 4}) {
        int nSing = 0;
        std::vector<Separatrix> s = designedSeparatrices(n, 1, 0.0, nSing);
        ASSERT_EQ(nSing, 1) << "N = " << n;
        // (N − 1)θ ≡ c: N − 1 outgoing rays, and N − 1 incoming for odd N: a positive
        // 3-RoSy singularity has 4 = N + 1 rays bounding its 4 hyperbolic sectors (P&Z Fig. 5).
        EXPECT_EQ(countIncoming(s, false), n - 1) << "N = " << n;
        EXPECT_EQ(countIncoming(s, true), n % 2 == 1 ? n - 1 : 0) << "N = " << n;
    }
    for (double phase : {0.0, M_PI / 2}) { // N = 1 source and centre: no separatrix
        int nSing = 0;
        std::vector<Separatrix> s = designedSeparatrices(1, 1, phase, nSing);
        ASSERT_EQ(nSing, 1);
        EXPECT_TRUE(s.empty()) << "phase " << phase;
    }
}

TEST(Separatrices, JsonListsEveryPolyline) {
    int nSing = 0;
    std::vector<Separatrix> s = designedSeparatrices(2, -1, 0.0, nSing);
    ASSERT_EQ(s.size(), 3u);
    rosy::JsonWriter json;
    json.beginObject();
    writeSeparatricesJson(json, s);
    json.endObject();
    const std::string out = json.str();
    auto count = [&](const std::string &k) {
        size_t c = 0;
        for (size_t pos = out.find(k); pos != std::string::npos; pos = out.find(k, pos + 1)) ++c;
        return c;
    };
    EXPECT_EQ(count("\"separatrices\""), 1u);
    EXPECT_EQ(count("\"polyline\""), 3u);
    EXPECT_EQ(count("\"incoming\": false"), 3u);
    EXPECT_EQ(count("\"singularity\": 0"), 3u);
}
