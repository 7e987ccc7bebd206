#include "field/mesh/mesh_stats.h"

namespace rosy::field {

std::vector<int> faceComponents(const Mesh &mesh, int *nComponents) {
    const int nF = mesh.nFaces();
    std::vector<int> comp(nF, -1);
    std::vector<int> stack;
    int n = 0;
    // Seeds in increasing face order, so ids are numbered by smallest face index.
    for (int seed = 0; seed < nF; ++seed) {
        if (comp[seed] >= 0) continue;
        comp[seed] = n;
        stack.assign(1, seed);
        while (!stack.empty()) {
            const int f = stack.back();
            stack.pop_back();
            for (int k = 0; k < 3; ++k) {
                const int t = mesh.twin(3 * f + k);
                if (t < 0) continue;
                const int g = Mesh::faceOf(t);
                if (comp[g] < 0) {
                    comp[g] = n;
                    stack.push_back(g);
                }
            }
        }
        ++n;
    }
    if (nComponents) *nComponents = n;
    return comp;
}

std::vector<std::vector<int>> boundaryLoops(const Mesh &mesh) {
    const int nH = mesh.nHalfedges();
    std::vector<uint8_t> seen(nH, 0);
    std::vector<std::vector<int>> loops;
    // Scanning halfedges in increasing order makes each loop start at its
    // smallest halfedge and sorts the loops by it.
    for (int h0 = 0; h0 < nH; ++h0) {
        if (!mesh.isBoundaryHalfedge(h0) || seen[h0]) continue;
        std::vector<int> loop;
        int h = h0;
        // A manifold boundary vertex has exactly one outgoing boundary halfedge,
        // stored first in its ring; the guard only protects against a broken mesh.
        while (!seen[h] && int(loop.size()) < nH) {
            seen[h] = 1;
            loop.push_back(h);
            h = *mesh.outgoingBegin(mesh.head(h));
        }
        loops.push_back(std::move(loop));
    }
    return loops;
}

std::vector<int> componentEulerCharacteristics(const Mesh &mesh) {
    int nC = 0;
    const std::vector<int> comp = faceComponents(mesh, &nC);
    std::vector<int> chi(nC, 0);
    for (int f = 0; f < mesh.nFaces(); ++f) ++chi[comp[f]];
    for (int e = 0; e < mesh.nEdges(); ++e) --chi[comp[Mesh::faceOf(mesh.edgeHalfedge(e))]];
    // Every vertex of a clean mesh lies in exactly one component: that of any of its faces.
    for (int v = 0; v < mesh.nVertices(); ++v)
        if (mesh.degree(v) > 0) ++chi[comp[Mesh::faceOf(*mesh.outgoingBegin(v))]];
    return chi;
}

MeshStats computeStats(const Mesh &mesh) {
    MeshStats s;
    s.vertices = mesh.nVertices();
    s.edges = mesh.nEdges();
    s.faces = mesh.nFaces();
    s.eulerCharacteristic = s.vertices - s.edges + s.faces;
    if (s.faces == 0) return s;
    const std::vector<int> comp = faceComponents(mesh, &s.components);
    const std::vector<std::vector<int>> loops = boundaryLoops(mesh);
    s.boundaryLoops = int(loops.size());
    std::vector<int> loopsPerComponent(s.components, 0);
    for (const std::vector<int> &loop : loops) ++loopsPerComponent[comp[Mesh::faceOf(loop[0])]];
    const std::vector<int> chi = componentEulerCharacteristics(mesh);
    for (int c = 0; c < s.components; ++c) s.genus += (2 - chi[c] - loopsPerComponent[c]) / 2;
    mesh.bounds(s.boundsMin, s.boundsMax);
    return s;
}

} // namespace rosy::field
