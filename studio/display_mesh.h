#pragma once
/// \file display_mesh.h
/// What the studio's page draws of a large mesh: a coarser mesh made once at load by
/// vertex clustering, whose vertices are vertices of the full mesh. The library
/// keeps working on the full mesh; the page gets the display mesh and the field at
/// its vertices (the full field sampled there), and a click on it is mapped back to
/// the full surface by a ray cast (Studio::pick()).

#include "field/mesh.h"

#include <vector>

namespace rosy::studio {

struct DisplayMesh {
    /// Corners index the display vertices, 0 .. fullVertex.size() - 1.
    std::vector<field::Face> faces;
    /// The full mesh's vertex shown as each display vertex.
    std::vector<int> fullVertex;
    /// The clustering's cell size (world units); 0 when the display mesh is the full mesh.
    double cellSize = 0.0;
};

/// A display mesh of at most `maxFaces` faces (when the mesh has more; else the mesh
/// itself). Vertex clustering on a uniform grid: the vertices in one cell become one,
/// the full-mesh vertex nearest to their mean; faces whose corners fall into fewer
/// than three cells disappear, duplicates are dropped, and the others keep their
/// orientation. The cell starts at the mean edge length times
/// sqrt(nFaces / maxFaces) and grows by 1.25 until the faces fit. Linear in the mesh
/// per try (the faces are sorted once per try); deterministic.
DisplayMesh makeDisplayMesh(const field::Mesh &mesh, int maxFaces);

} // namespace rosy::studio
