#pragma once
// Meshes built by hand for renderer tests, so these tests do not depend on
// field/primitives.cpp.

#include "field/mesh.h"

#include <map>
#include <utility>

namespace rosy::test {

/// Octahedron midpoint-subdivided `levels` times and projected onto the sphere of
/// radius `radius` around `centre`: 8 * 4^levels faces, CCW seen from outside.
inline field::Mesh makeSphere(int levels, double radius = 1.0,
                              const field::Vec3 &centre = field::Vec3::Zero()) {
    using field::Vec3;
    std::vector<Vec3> p = {Vec3(1, 0, 0),  Vec3(-1, 0, 0), Vec3(0, 1, 0),
                           Vec3(0, -1, 0), Vec3(0, 0, 1),  Vec3(0, 0, -1)};
    std::vector<field::Face> f = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                  {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            p.push_back((p[size_t(a)] + p[size_t(b)]).normalized());
            return mid[key] = int(p.size()) - 1;
        };
        std::vector<field::Face> g;
        for (const auto &t : f) {
            int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
            g.push_back({t[0], ab, ca});
            g.push_back({ab, t[1], bc});
            g.push_back({ca, bc, t[2]});
            g.push_back({ab, bc, ca});
        }
        f = std::move(g);
    }
    for (Vec3 &q : p) q = centre + radius * q.normalized();
    return field::Mesh::fromTriangles(p, f, "test-sphere");
}

/// A sphere (levels as above) above a square floor: floor z = floorZ, x, y in
/// [-halfSize, halfSize], normal +z; the sphere has radius 1 around the origin.
inline field::Mesh makeSphereOverFloor(int levels, double floorZ, double halfSize) {
    field::Mesh s = makeSphere(levels);
    std::vector<field::Vec3> p = s.positions();
    std::vector<field::Face> f = s.faces();
    int b = int(p.size());
    p.push_back(field::Vec3(-halfSize, -halfSize, floorZ));
    p.push_back(field::Vec3(halfSize, -halfSize, floorZ));
    p.push_back(field::Vec3(halfSize, halfSize, floorZ));
    p.push_back(field::Vec3(-halfSize, halfSize, floorZ));
    f.push_back({b, b + 1, b + 2});
    f.push_back({b, b + 2, b + 3});
    return field::Mesh::fromTriangles(p, f, "sphere-over-floor");
}

} // namespace rosy::test
