#include "field/streamlines.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rosy::field {

const char *toString(StreamlineStop stop) {
    switch (stop) {
    case StreamlineStop::MaxLength: return "max-length";
    case StreamlineStop::MaxSteps: return "max-steps";
    case StreamlineStop::Boundary: return "boundary";
    case StreamlineStop::Singularity: return "singularity";
    case StreamlineStop::Closed: return "closed";
    case StreamlineStop::ZeroField: return "zero-field";
    case StreamlineStop::Stalled: return "stalled";
    }
    return "unknown";
}

Vec3 barycentricOf(const Mesh &mesh, int face, const Vec3 &p) {
    const Face &t = mesh.face(face);
    Vec3 e1 = mesh.position(t[1]) - mesh.position(t[0]);
    Vec3 e2 = mesh.position(t[2]) - mesh.position(t[0]);
    Vec3 d = p - mesh.position(t[0]);
    double a = e1.dot(e1), b = e1.dot(e2), c = e2.dot(e2);
    double det = a * c - b * b;
    if (!(std::abs(det) > 0)) return Vec3::Constant(1.0 / 3.0);
    double r1 = d.dot(e1), r2 = d.dot(e2);
    double b1 = (c * r1 - b * r2) / det, b2 = (a * r2 - b * r1) / det;
    return Vec3(1 - b1 - b2, b1, b2);
}

namespace {

/// One face in its own 2D frame, with what a step needs.
struct FaceChart {
    int face = -1;
    Vec2 q[3];                  // corners in the face frame
    Eigen::Matrix2d toBary;     // (b1, b2) = toBary * (p − q0)
    std::array<Complex, 3> u{}; // corner representation vectors in the face frame
    double uScale = 0;          // max |u| at the corners
    bool degenerate = false;

    void load(const TangentFrames &frames, const RosyField &field, int f) {
        const Mesh &mesh = frames.mesh();
        face = f;
        for (int c = 0; c < 3; ++c) q[c] = frames.toFace2D(f, mesh.position(mesh.face(f)[c]));
        Eigen::Matrix2d m;
        m.col(0) = q[1] - q[0];
        m.col(1) = q[2] - q[0];
        double det = m.determinant();
        degenerate = !(std::abs(det) > 1e-14 * m.squaredNorm());
        toBary = degenerate ? Eigen::Matrix2d::Zero() : Eigen::Matrix2d(m.inverse());
        u = frames.faceValues(f, field);
        uScale = std::max({std::abs(u[0]), std::abs(u[1]), std::abs(u[2])});
    }
    Complex value(const Vec3 &b) const { return b[0] * u[0] + b[1] * u[1] + b[2] * u[2]; }
    /// Change of the barycentrics per unit move along 2D direction d.
    Vec3 baryRate(const Vec2 &d) const {
        Vec2 r = toBary * d;
        return Vec3(-r[0] - r[1], r[0], r[1]);
    }
};

/// The member angle of u closest to heading angle h: members are arg(u)/N + 2πk/N,
/// so the offset from h is (arg u − N h)/N taken in (−π/N, π/N].
double closestMember(Complex u, int nSym, double headingRad) {
    return headingRad + wrapAngle(std::arg(u) - nSym * headingRad) / nSym;
}

/// Largest t ≥ 0 such that b + t·rate stays in the triangle, and the corner whose
/// coordinate hits zero there (its opposite edge is crossed). corner = −1: no exit.
double exitParameter(const Vec3 &b, const Vec3 &rate, int &corner) {
    double best = std::numeric_limits<double>::infinity();
    corner = -1;
    for (int c = 0; c < 3; ++c) {
        if (rate[c] < 0) {
            double t = std::max(0.0, b[c]) / -rate[c];
            if (t < best) { best = t; corner = c; }
        }
    }
    return best;
}

double distanceToSegment(const Vec3 &p, const Vec3 &a, const Vec3 &b) {
    Vec3 ab = b - a;
    double l2 = ab.squaredNorm();
    double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    return (a + t * ab - p).norm();
}

/// One direction of tracing; appends to `line` (which already holds the seed point).
StreamlineStop traceHalf(const TangentFrames &frames, const RosyField &field, int face, Vec3 b,
                         Vec3 direction3D, const StreamlineOptions &opt, double step, double maxLength,
                         double closeTol, const std::vector<int> *faceIndex, bool reverse,
                         Streamline &line) {
    const Mesh &mesh = frames.mesh();
    const int nSym = field.nSym;
    FaceChart chart;
    chart.load(frames, field, face);
    auto world = [&](const Vec3 &bb) {
        const Face &t = mesh.face(chart.face);
        return Vec3(bb[0] * mesh.position(t[0]) + bb[1] * mesh.position(t[1]) + bb[2] * mesh.position(t[2]));
    };
    Vec2 d2(direction3D.dot(frames.faceAxisX(face)), direction3D.dot(frames.faceAxisY(face)));
    double heading = d2.squaredNorm() > 0 ? std::atan2(d2.y(), d2.x()) : 0.0;

    const Vec3 start = world(b);
    const Vec3 startDir = frames.faceDirection(face, heading);
    bool leftStart = false;
    bool straight = opt.leaveStartFaceStraight;
    double length = 0;
    int stalls = 0;
    // Against the flow the line follows the negated member closest to the reversed
    // heading; for odd N this is the only way back along a line, for even N it agrees
    // with the forward rule.
    auto follow = [&](Complex u, double headingRad) {
        return reverse ? closestMember(u, nSym, headingRad + M_PI) + M_PI : closestMember(u, nSym, headingRad);
    };
    auto singular = [&](int f) {
        return opt.stopAtSingularFaces && faceIndex && (*faceIndex)[f] != 0;
    };
    if (!straight && singular(face)) return StreamlineStop::Singularity;

    for (int stepCount = 0;; ++stepCount) {
        if (stepCount >= opt.maxSteps) return StreamlineStop::MaxSteps;
        if (chart.degenerate) return StreamlineStop::ZeroField;
        double h = std::min(step, maxLength - length);
        if (h <= 0) return StreamlineStop::MaxLength;

        double angle = heading;
        if (!straight) {
            Complex u0 = chart.value(b);
            // Relative threshold: the field's own scale in this face decides what "zero" is.
            if (!(std::abs(u0) > 1e-9 * chart.uScale)) return StreamlineStop::ZeroField;
            angle = follow(u0, heading);
        }
        // Implicit midpoint: the direction is the field's at the middle of the segment
        // it produces. For a linear rotational field this keeps |p| exactly, so closed
        // orbits close instead of spiralling out as with explicit RK2.
        double t = 0;
        int corner = -1;
        for (int iter = 0; iter < (straight ? 1 : 4); ++iter) {
            Vec2 d(std::cos(angle), std::sin(angle));
            Vec3 rate = chart.baryRate(d);
            t = std::min(h, exitParameter(b, rate, corner));
            if (straight) break;
            Complex um = chart.value(b + 0.5 * t * rate);
            if (!(std::abs(um) > 1e-9 * chart.uScale)) break;
            angle = follow(um, angle);
        }
        Vec2 d(std::cos(angle), std::sin(angle));
        Vec3 rate = chart.baryRate(d);
        double tExit = exitParameter(b, rate, corner);
        bool crossing = tExit <= h;
        t = crossing ? tExit : h;
        heading = angle;

        Vec3 pOld = world(b);
        b += t * rate;
        if (crossing) b[corner] = 0;
        b = b.cwiseMax(0.0);
        b /= b.sum();
        Vec3 pNew = world(b);
        length += t;

        // Closed loop: back near the start, heading the same way.
        // The test uses whether the line had left the start before this segment, so the
        // first segments (which start at the seed) never count.
        if (leftStart && distanceToSegment(start, pOld, pNew) < closeTol && (pNew - pOld).dot(startDir) > 0) {
            line.length += (start - pOld).norm();
            line.points.push_back(start);
            line.faces.push_back(chart.face);
            return StreamlineStop::Closed;
        }
        if (!leftStart && (pNew - start).norm() > 4 * closeTol) leftStart = true;
        if (!crossing) {
            stalls = 0;
            line.points.push_back(pNew);
            line.faces.push_back(chart.face);
            line.length += t;
            continue;
        }

        // Cross the edge opposite `corner` into the neighbour.
        stalls = t > 1e-12 * step ? 0 : stalls + 1;
        if (stalls > 4) {
            line.points.push_back(pNew);
            line.faces.push_back(chart.face);
            line.length += t;
            return StreamlineStop::Stalled;
        }
        const int f = chart.face;
        const int kt = (corner + 1) % 3, kh = (corner + 2) % 3; // h runs kt → kh
        const int hEdge = 3 * f + kt;
        const int twin = mesh.twin(hEdge);
        line.length += t;
        if (twin < 0) {
            line.points.push_back(pNew);
            line.faces.push_back(f);
            return StreamlineStop::Boundary;
        }
        double s = b[kh] / (b[kt] + b[kh]);
        // Keep off the vertices: a crossing exactly at a corner has no well-defined next face.
        s = std::clamp(s, 1e-9, 1.0 - 1e-9);
        const Vec2 edgeF = chart.q[kh] - chart.q[kt];
        const double toEdge = heading - std::atan2(edgeF.y(), edgeF.x());
        const int g = twin / 3, k = twin % 3; // twin runs head(h) → tail(h)
        chart.load(frames, field, g);
        b = Vec3::Zero();
        b[k] = s;
        b[(k + 1) % 3] = 1 - s;
        const Vec2 edgeG = chart.q[k] - chart.q[(k + 1) % 3];
        heading = std::atan2(edgeG.y(), edgeG.x()) + toEdge; // unfolding keeps the angle to the edge
        straight = false;
        line.points.push_back(world(b));
        line.faces.push_back(g);
        if (singular(g)) return StreamlineStop::Singularity;
    }
}

} // namespace

Streamline traceStreamline(const TangentFrames &frames, const RosyField &field, int face,
                           const Vec3 &barycentric, const Vec3 &direction3D,
                           const StreamlineOptions &options, const std::vector<int> *faceIndex) {
    const Mesh &mesh = frames.mesh();
    Streamline line;
    Vec3 b = barycentric.cwiseMax(0.0);
    b = b.sum() > 0 && b.allFinite() ? Vec3(b / b.sum()) : Vec3::Constant(1.0 / 3.0);
    const Face &t = mesh.face(face);
    const Vec3 seed = b[0] * mesh.position(t[0]) + b[1] * mesh.position(t[1]) + b[2] * mesh.position(t[2]);
    Vec3 dir = direction3D.allFinite() ? direction3D : Vec3(frames.faceAxisX(face));
    {
        Vec3 n = mesh.faceNormal(face);
        dir -= dir.dot(n) * n;
        if (!(dir.norm() > 1e-12)) dir = frames.faceAxisX(face);
    }
    double step = options.stepLength > 0 ? options.stepLength : 0.5 * mesh.meanEdgeLength();
    if (!(step > 0)) step = 1;
    const double maxLength = options.maxLength > 0 ? options.maxLength : std::numeric_limits<double>::infinity();
    const double closeTol = options.closeTolerance > 0 ? options.closeTolerance : 0.5 * step;

    line.points.push_back(seed);
    line.faces.push_back(face);
    line.stop = traceHalf(frames, field, face, b, dir, options, step, maxLength, closeTol, faceIndex, options.reverseField, line);
    if (options.bothDirections && line.stop != StreamlineStop::Closed) {
        Streamline back;
        back.points.push_back(seed);
        back.faces.push_back(face);
        line.stopBackward = traceHalf(frames, field, face, b, -dir, options, step,
                                      maxLength, closeTol, faceIndex, !options.reverseField, back);
        std::vector<Vec3> pts(back.points.rbegin(), back.points.rend());
        std::vector<int> fcs(back.faces.rbegin(), back.faces.rend());
        pts.insert(pts.end(), line.points.begin() + 1, line.points.end());
        fcs.insert(fcs.end(), line.faces.begin() + 1, line.faces.end());
        line.points = std::move(pts);
        line.faces = std::move(fcs);
        line.length += back.length;
    } else {
        line.stopBackward = line.stop;
    }
    return line;
}

} // namespace rosy::field
