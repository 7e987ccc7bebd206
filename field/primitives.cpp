#include "field/primitives.h"

#include "core/error.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <unordered_map>

namespace rosy::field {
namespace {

constexpr double kPi = std::numbers::pi;

void requireAtLeast(const char *function, const char *what, int value, int minimum) {
    if (value < minimum)
        throw InputError(FileLoc{function},
                         std::string(what) + " is " + std::to_string(value) + ", must be at least " +
                             std::to_string(minimum));
}

/// Split quad (a, b, c, d), given counter-clockwise, into two triangles.
void addQuad(std::vector<Face> &faces, int a, int b, int c, int d) {
    faces.push_back({a, b, c});
    faces.push_back({a, c, d});
}

/// 1-to-4 split with new vertices at edge midpoints (shared through an edge map,
/// keyed by the sorted vertex pair so that both faces of an edge agree).
void subdivideRaw(std::vector<Vec3> &positions, std::vector<Face> &faces) {
    std::unordered_map<uint64_t, int> midpoint;
    midpoint.reserve(faces.size() * 2);
    auto mid = [&](int a, int b) {
        const uint64_t key = (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b));
        auto it = midpoint.find(key);
        if (it != midpoint.end()) return it->second;
        const int v = int(positions.size());
        positions.push_back(0.5 * (positions[a] + positions[b]));
        midpoint.emplace(key, v);
        return v;
    };
    std::vector<Face> out;
    out.reserve(4 * faces.size());
    for (const Face &t : faces) {
        const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
        out.push_back({t[0], ab, ca});
        out.push_back({t[1], bc, ab});
        out.push_back({t[2], ca, bc});
        out.push_back({ab, bc, ca});
    }
    faces.swap(out);
}

/// Flips faces of a convex solid around the origin so their normals point away from it.
void orientOutward(const std::vector<Vec3> &positions, std::vector<Face> &faces) {
    for (Face &t : faces) {
        const Vec3 &a = positions[t[0]], &b = positions[t[1]], &c = positions[t[2]];
        if ((b - a).cross(c - a).dot(a + b + c) < 0) std::swap(t[1], t[2]);
    }
}

std::vector<Vec3> icosahedronVertices() {
    const double phi = (1 + std::sqrt(5.0)) / 2;
    std::vector<Vec3> v;
    for (double s : {-1.0, 1.0})
        for (double t : {-1.0, 1.0}) {
            v.emplace_back(0, s, t * phi);
            v.emplace_back(s, t * phi, 0);
            v.emplace_back(t * phi, 0, s);
        }
    for (Vec3 &p : v) p.normalize();
    return v;
}

std::vector<Vec3> dodecahedronVertices() {
    const double phi = (1 + std::sqrt(5.0)) / 2;
    std::vector<Vec3> v;
    for (double a : {-1.0, 1.0})
        for (double b : {-1.0, 1.0}) {
            for (double c : {-1.0, 1.0}) v.emplace_back(a, b, c);
            // This cyclic order makes it the dual of icosahedronVertices():
            // its vertices are the directions of the icosahedron's face centres.
            v.emplace_back(a / phi, 0, b * phi);
            v.emplace_back(b * phi, a / phi, 0);
            v.emplace_back(0, b * phi, a / phi);
        }
    for (Vec3 &p : v) p.normalize();
    return v;
}

/// Faces of the convex hull of `vertices` whose outward normals are `normals`:
/// each face is the set of vertices farthest along its normal, ordered
/// counter-clockwise around it. Triangles stay, quads are split in two and
/// larger polygons get a centre vertex fan; all new points lie in the face plane.
void polytopeFaces(std::vector<Vec3> &vertices, const std::vector<Vec3> &normals,
                   std::vector<Face> &faces) {
    const int nOriginal = int(vertices.size());
    for (const Vec3 &nIn : normals) {
        const Vec3 n = nIn.normalized();
        double best = -1e300;
        for (int i = 0; i < nOriginal; ++i) best = std::max(best, vertices[i].dot(n));
        std::vector<int> poly;
        for (int i = 0; i < nOriginal; ++i)
            if (vertices[i].dot(n) > best - 1e-9) poly.push_back(i);
        Vec3 centre = Vec3::Zero();
        for (int i : poly) centre += vertices[i];
        centre /= double(poly.size());
        const Vec3 e1 = (vertices[poly[0]] - centre).normalized();
        const Vec3 e2 = n.cross(e1);
        std::sort(poly.begin(), poly.end(), [&](int a, int b) {
            const Vec3 pa = vertices[a] - centre, pb = vertices[b] - centre;
            return std::atan2(pa.dot(e2), pa.dot(e1)) < std::atan2(pb.dot(e2), pb.dot(e1));
        });
        if (poly.size() == 3) {
            faces.push_back({poly[0], poly[1], poly[2]});
        } else if (poly.size() == 4) {
            addQuad(faces, poly[0], poly[1], poly[2], poly[3]);
        } else {
            const int c = int(vertices.size());
            vertices.push_back(centre);
            for (size_t k = 0; k < poly.size(); ++k)
                faces.push_back({c, poly[k], poly[(k + 1) % poly.size()]});
        }
    }
}

} // namespace

Mesh makeIcosphere(int subdivisions, double radius) {
    requireAtLeast("makeIcosphere", "subdivisions", subdivisions, 0);
    std::vector<Vec3> positions = icosahedronVertices();
    std::vector<Face> faces;
    polytopeFaces(positions, dodecahedronVertices(), faces);
    for (int s = 0; s < subdivisions; ++s) {
        subdivideRaw(positions, faces);
        for (Vec3 &p : positions) p.normalize();
    }
    for (Vec3 &p : positions) p *= radius;
    return Mesh::fromTriangles(std::move(positions), std::move(faces), "icosphere");
}

Mesh makeEllipsoid(int subdivisions, double a, double b, double c) {
    Mesh sphere = makeIcosphere(subdivisions);
    std::vector<Vec3> positions = sphere.positions();
    for (Vec3 &p : positions) p = p.cwiseProduct(Vec3(a, b, c));
    std::vector<Face> faces = sphere.faces();
    // A negative semi-axis mirrors the surface; flip faces to keep it outward.
    if (a * b * c < 0)
        for (Face &t : faces) std::swap(t[1], t[2]);
    return Mesh::fromTriangles(std::move(positions), std::move(faces), "ellipsoid");
}

Mesh makeTorus(double majorRadius, double minorRadius, int nU, int nV) {
    requireAtLeast("makeTorus", "nU", nU, 3);
    requireAtLeast("makeTorus", "nV", nV, 3);
    std::vector<Vec3> positions;
    std::vector<Face> faces;
    for (int i = 0; i < nU; ++i)
        for (int j = 0; j < nV; ++j) {
            const double u = 2 * kPi * i / nU, v = 2 * kPi * j / nV;
            const double rho = majorRadius + minorRadius * std::cos(v);
            positions.emplace_back(rho * std::cos(u), rho * std::sin(u), minorRadius * std::sin(v));
        }
    // d/du x d/dv points away from the tube's core circle, so (u, v) order is outward.
    auto id = [&](int i, int j) { return (i % nU) * nV + (j % nV); };
    for (int i = 0; i < nU; ++i)
        for (int j = 0; j < nV; ++j) addQuad(faces, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
    return Mesh::fromTriangles(std::move(positions), std::move(faces), "torus");
}

Mesh makeCube(int n) {
    requireAtLeast("makeCube", "n", n, 1);
    // Vertices live on the integer lattice {0..n}^3; keying them by lattice
    // coordinates welds the six face grids exactly.
    std::map<std::array<int, 3>, int> index;
    std::vector<Vec3> positions;
    auto vertex = [&](std::array<int, 3> q) {
        auto [it, inserted] = index.emplace(q, int(positions.size()));
        if (inserted)
            positions.emplace_back(-1 + 2.0 * q[0] / n, -1 + 2.0 * q[1] / n, -1 + 2.0 * q[2] / n);
        return it->second;
    };
    std::vector<Face> faces;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3; // e_a1 x e_a2 = e_axis
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    std::array<int, 3> q[4];
                    const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
                    for (int k = 0; k < 4; ++k) {
                        q[k][axis] = side * n;
                        q[k][a1] = i + di[k];
                        q[k][a2] = j + dj[k];
                    }
                    int v[4];
                    for (int k = 0; k < 4; ++k) v[k] = vertex(q[k]);
                    if (side == 1) addQuad(faces, v[0], v[1], v[2], v[3]);
                    else addQuad(faces, v[0], v[3], v[2], v[1]);
                }
        }
    return Mesh::fromTriangles(std::move(positions), std::move(faces), "cube");
}

Mesh makeRoundedCubePair(int n) {
    requireAtLeast("makeRoundedCubePair", "n", n, 2);
    // Signed distance to a box of half-side h, edges rounded with radius r, centred at c.
    auto roundedBox = [](const Vec3 &p, const Vec3 &c, double h, double r) {
        const Vec3 q = (p - c).cwiseAbs() - Vec3::Constant(h - r);
        return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0) - r;
    };
    // Polynomial smooth minimum (blend radius k): the joint gets a fillet.
    auto smoothUnion = [](double a, double b, double k) {
        const double h = std::clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
        return b + (a - b) * h - k * h * (1 - h);
    };
    const Vec3 big(0, 0, 0), small(0, 0, 1.5);
    auto sdf = [&](const Vec3 &p) {
        return smoothUnion(roundedBox(p, big, 1.0, 0.25), roundedBox(p, small, 0.6, 0.2), 0.15);
    };
    const Vec3 centre(0, 0, 0.95); // inside both cubes (the small one reaches down to z = 0.9)
    // A cube sphere: the six faces of makeCube(n), each vertex a direction from the centre.
    Mesh cube = makeCube(n);
    std::vector<Vec3> positions;
    positions.reserve(cube.positions().size());
    for (const Vec3 &c : cube.positions()) {
        const Vec3 dir = c.normalized();
        // Inside at t = 0, outside at t = 4 (the solid lies within distance 2.2 of the
        // centre); bisection to the crossing, which is the only one along the ray.
        double lo = 0, hi = 4;
        for (int it = 0; it < 60; ++it) {
            const double mid = 0.5 * (lo + hi);
            (sdf(centre + mid * dir) < 0 ? lo : hi) = mid;
        }
        positions.push_back(centre + 0.5 * (lo + hi) * dir);
    }
    return Mesh::fromTriangles(std::move(positions), cube.faces(), "rounded-cube-pair");
}

Mesh makePlatonic(Platonic solid, int subdivisions) {
    requireAtLeast("makePlatonic", "subdivisions", subdivisions, 0);
    std::vector<Vec3> tetra = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    std::vector<Vec3> cube, octa;
    for (int i = 0; i < 8; ++i) cube.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
    for (int a = 0; a < 3; ++a)
        for (double s : {-1.0, 1.0}) {
            Vec3 p = Vec3::Zero();
            p[a] = s;
            octa.push_back(p);
        }
    // Each solid's face normals are the vertex directions of its dual.
    std::vector<Vec3> vertices, normals;
    switch (solid) {
    case Platonic::Tetrahedron:
        vertices = tetra;
        for (const Vec3 &p : tetra) normals.push_back(-p);
        break;
    case Platonic::Cube: vertices = cube, normals = octa; break;
    case Platonic::Octahedron: vertices = octa, normals = cube; break;
    case Platonic::Dodecahedron:
        vertices = dodecahedronVertices(), normals = icosahedronVertices();
        break;
    case Platonic::Icosahedron:
        vertices = icosahedronVertices(), normals = dodecahedronVertices();
        break;
    }
    for (Vec3 &p : vertices) p.normalize();
    std::vector<Face> faces;
    polytopeFaces(vertices, normals, faces);
    orientOutward(vertices, faces);
    for (int s = 0; s < subdivisions; ++s) subdivideRaw(vertices, faces);
    return Mesh::fromTriangles(std::move(vertices), std::move(faces), "platonic");
}

Mesh makeDisk(int rings) {
    requireAtLeast("makeDisk", "rings", rings, 1);
    // Ring k has 6k vertices at radius k / rings: nearly equilateral triangles.
    std::vector<Vec3> positions{Vec3::Zero()};
    std::vector<int> ringStart{0};
    for (int k = 1; k <= rings; ++k) {
        ringStart.push_back(int(positions.size()));
        for (int i = 0; i < 6 * k; ++i) {
            const double t = 2 * kPi * i / (6 * k), r = double(k) / rings;
            positions.emplace_back(r * std::cos(t), r * std::sin(t), 0);
        }
    }
    std::vector<Face> faces;
    for (int i = 0; i < 6; ++i) faces.push_back({0, 1 + i, 1 + (i + 1) % 6});
    for (int k = 2; k <= rings; ++k) {
        // Zip ring k-1 (inner, nA) to ring k (outer, nB) in angle order; angles
        // are compared as integer fractions so ties are exact.
        const int nA = 6 * (k - 1), nB = 6 * k, a0 = ringStart[k - 1], b0 = ringStart[k];
        int i = 0, j = 0;
        while (i < nA || j < nB) {
            const bool advanceInner = j == nB || (i < nA && int64_t(i + 1) * nB <= int64_t(j + 1) * nA);
            if (advanceInner) {
                faces.push_back({a0 + i % nA, b0 + j % nB, a0 + (i + 1) % nA});
                ++i;
            } else {
                faces.push_back({a0 + i % nA, b0 + j % nB, b0 + (j + 1) % nB});
                ++j;
            }
        }
    }
    return Mesh::fromTriangles(std::move(positions), std::move(faces), "disk");
}

Mesh makeGrid(int n) {
    requireAtLeast("makeGrid", "n", n, 1);
    std::vector<Vec3> positions;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) positions.emplace_back(-1 + 2.0 * i / n, -1 + 2.0 * j / n, 0);
    std::vector<Face> faces;
    auto id = [&](int i, int j) { return j * (n + 1) + i; };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) addQuad(faces, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
    return Mesh::fromTriangles(std::move(positions), std::move(faces), "grid");
}

Mesh makeCylinder(double radius, double height, int nAround, int nAlong) {
    requireAtLeast("makeCylinder", "nAround", nAround, 3);
    requireAtLeast("makeCylinder", "nAlong", nAlong, 1);
    std::vector<Vec3> positions;
    for (int j = 0; j <= nAlong; ++j)
        for (int i = 0; i < nAround; ++i) {
            const double t = 2 * kPi * i / nAround;
            positions.emplace_back(radius * std::cos(t), radius * std::sin(t),
                                   height * (double(j) / nAlong - 0.5));
        }
    std::vector<Face> faces;
    auto id = [&](int i, int j) { return j * nAround + i % nAround; };
    for (int j = 0; j < nAlong; ++j)
        for (int i = 0; i < nAround; ++i) addQuad(faces, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
    return Mesh::fromTriangles(std::move(positions), std::move(faces), "cylinder");
}

namespace {

/// The voxels of makeGenus2(): a plate with two rectangular holes. Holes keep a
/// margin of at least two cells, so no two voxels touch only along an edge or
/// corner and the voxel boundary is a closed 2-manifold of genus 2 (χ = −2).
struct Genus2Plate {
    int W, H, T, m;
    explicit Genus2Plate(int resolution)
        : W(resolution), H(std::max(8, resolution / 2)), T(std::max(2, resolution / 8)),
          m(std::max(2, resolution / 8)) {}
    bool hole(int x, int y) const {
        if (y < m || y >= H - m) return false;
        return (x >= m && x < W / 2 - m / 2) || (x >= W / 2 + (m + 1) / 2 && x < W - m);
    }
    bool solid(int x, int y, int z) const {
        return x >= 0 && x < W && y >= 0 && y < H && z >= 0 && z < T && !hole(x, y);
    }
    /// Exposed voxel sides, each two triangles.
    long long boundarySquares() const {
        long long n = 0;
        for (int x = 0; x < W; ++x)
            for (int y = 0; y < H; ++y)
                for (int z = 0; z < T; ++z) {
                    if (!solid(x, y, z)) continue;
                    n += !solid(x - 1, y, z) + !solid(x + 1, y, z) + !solid(x, y - 1, z) + !solid(x, y + 1, z) +
                         !solid(x, y, z - 1) + !solid(x, y, z + 1);
                }
        return n;
    }
};

} // namespace

long long genus2FaceCount(int resolution) {
    requireAtLeast("genus2FaceCount", "resolution", resolution, 16);
    return 2 * Genus2Plate(resolution).boundarySquares();
}

Mesh makeGenus2(int resolution) {
    requireAtLeast("makeGenus2", "resolution", resolution, 16);
    const Genus2Plate plate(resolution);
    const int W = plate.W, H = plate.H, T = plate.T;
    auto solid = [&](int x, int y, int z) { return plate.solid(x, y, z); };
    std::map<std::array<int, 3>, int> index;
    std::vector<Vec3> positions;
    auto vertex = [&](std::array<int, 3> q) {
        auto [it, inserted] = index.emplace(q, int(positions.size()));
        if (inserted) positions.emplace_back(q[0], q[1], q[2]);
        return it->second;
    };
    std::vector<Face> faces;
    for (int x = 0; x < W; ++x)
        for (int y = 0; y < H; ++y)
            for (int z = 0; z < T; ++z) {
                if (!solid(x, y, z)) continue;
                const int c[3] = {x, y, z};
                for (int axis = 0; axis < 3; ++axis)
                    for (int side = 0; side < 2; ++side) {
                        int nb[3] = {x, y, z};
                        nb[axis] += side ? 1 : -1;
                        if (solid(nb[0], nb[1], nb[2])) continue;
                        const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
                        std::array<int, 3> q[4];
                        const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
                        for (int k = 0; k < 4; ++k) {
                            q[k][axis] = c[axis] + side;
                            q[k][a1] = c[a1] + di[k];
                            q[k][a2] = c[a2] + dj[k];
                        }
                        int v[4];
                        for (int k = 0; k < 4; ++k) v[k] = vertex(q[k]);
                        if (side == 1) addQuad(faces, v[0], v[1], v[2], v[3]);
                        else addQuad(faces, v[0], v[3], v[2], v[1]);
                    }
            }
    // Centre and scale so the long side spans [−1, 1].
    const Vec3 centre(W / 2.0, H / 2.0, T / 2.0);
    for (Vec3 &p : positions) p = (p - centre) * (2.0 / W);

    // Taubin λ/μ smoothing (Taubin 1995): alternating shrink and inflate steps
    // with the uniform Laplacian round off the voxel staircase without the
    // shrinkage of plain Laplacian smoothing.
    std::vector<std::vector<int>> nbrs(positions.size());
    for (const Face &t : faces)
        for (int k = 0; k < 3; ++k) {
            nbrs[t[k]].push_back(t[(k + 1) % 3]);
            nbrs[t[k]].push_back(t[(k + 2) % 3]);
        }
    for (auto &list : nbrs) {
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    std::vector<Vec3> next(positions.size());
    for (int iter = 0; iter < 2 * 20; ++iter) {
        const double factor = iter % 2 == 0 ? 0.5 : -0.53;
        for (size_t v = 0; v < positions.size(); ++v) {
            Vec3 mean = Vec3::Zero();
            for (int w : nbrs[v]) mean += positions[w];
            mean /= double(nbrs[v].size());
            next[v] = positions[v] + factor * (mean - positions[v]);
        }
        positions.swap(next);
    }
    return Mesh::fromTriangles(std::move(positions), std::move(faces), "genus2");
}

Mesh subdivideMidpoint(const Mesh &mesh) {
    std::vector<Vec3> positions = mesh.positions();
    std::vector<Face> faces = mesh.faces();
    subdivideRaw(positions, faces);
    return Mesh::fromTriangles(std::move(positions), std::move(faces), mesh.name());
}

} // namespace rosy::field
