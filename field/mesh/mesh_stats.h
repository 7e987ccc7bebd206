#pragma once
/// \file mesh_stats.h
/// Topological and geometric summary of a mesh.

#include "field/mesh/mesh.h"

#include <vector>

namespace rosy::field {

struct MeshStats {
    int vertices = 0, edges = 0, faces = 0;
    int components = 0;
    int boundaryLoops = 0;
    int eulerCharacteristic = 0; ///< χ = V − E + F, summed over components
    int genus = 0;               ///< Σ over components of (2 − χ_c − b_c) / 2
    Vec3 boundsMin = Vec3::Zero(), boundsMax = Vec3::Zero();
};

MeshStats computeStats(const Mesh &mesh);

/// Component id of every face (#F, ids 0..n−1 numbered by smallest face index).
std::vector<int> faceComponents(const Mesh &mesh, int *nComponents = nullptr);

/// Boundary loops as ordered lists of boundary halfedges (each loop starts at its
/// smallest halfedge index; loops sorted by that index).
std::vector<std::vector<int>> boundaryLoops(const Mesh &mesh);

/// Euler characteristic of each component (indexed like faceComponents()).
std::vector<int> componentEulerCharacteristics(const Mesh &mesh);

} // namespace rosy::field
