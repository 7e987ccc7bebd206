#include "remesh/input_refinement.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>

namespace rosy::remesh {

field::Mesh refineCoarseInput(const field::Mesh &mesh, double edgeLength, long long maxVertices,
                              InputRefinement *report) {
    ROSY_CHECK(edgeLength > 0 && std::isfinite(edgeLength));
    InputRefinement r;
    r.maxEdge = kRefineEdgeRatio * edgeLength;
    r.verticesBefore = r.verticesAfter = mesh.nVertices();
    double total = 0, inLong = 0, longestOfAll = 0;
    for (int f = 0; f < mesh.nFaces(); ++f) {
        const double a = mesh.faceArea(f);
        double longest = 0;
        for (int k = 0; k < 3; ++k) longest = std::max(longest, mesh.vector(3 * f + k).norm());
        total += a;
        if (longest > r.maxEdge) inLong += a;
        longestOfAll = std::max(longestOfAll, longest);
    }
    r.longEdgeAreaFraction = total > 0 ? inLong / total : 0.0;
    r.applied = r.longEdgeAreaFraction >= kRefineAreaFraction;
    field::Mesh out = r.applied ? field::flipCoplanarToDelaunay(
                                      field::refineLongEdges(mesh, r.maxEdge, maxVertices, &r.refinement),
                                      &r.delaunayFlips)
                                : mesh;
    r.refinement.maxEdgeBefore = longestOfAll;
    r.verticesAfter = out.nVertices();
    if (report) *report = r;
    return out;
}

} // namespace rosy::remesh
