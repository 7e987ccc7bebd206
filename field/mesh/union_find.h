#pragma once
/// \file union_find.h
/// Disjoint sets over 0..n-1 with path halving. The smaller id becomes the root, so
/// the sets' representatives do not depend on the order of unite() calls (mesh
/// repair's vertex welding, the remesher's lattice collapse).

#include <algorithm>
#include <numeric>
#include <vector>

namespace rosy::field {

struct UnionFind {
    std::vector<int> parent;
    explicit UnionFind(int n) : parent(size_t(n)) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int x) {
        while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
        return x;
    }
    void unite(int a, int b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
    }
};

} // namespace rosy::field
