#pragma once
/// \file poly_mesh.h
/// Polygon meshes in OpenMesh's halfedge structure, and writing meshes through
/// OpenMesh's writers.
///
/// PolyMesh is the type for meshes whose faces are not all triangles: quad
/// remeshing will produce it, and `rosyhatch field --export-mesh` writes the
/// repaired input through it. Points are in the input's own units and frame
/// (double precision; the readers round coordinates to float, so nothing is lost
/// writing them as float). Faces are counter-clockwise seen from outside, as in
/// Mesh (mesh.h).
///
/// Reading stays with our own checked readers (mesh_io.h): docs/meshes.md,
/// "Why not OpenMesh's readers", says what OpenMesh 9's readers do with
/// untrusted files.

#include "field/mesh/mesh.h"

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/Traits.hh>

#include <string>
#include <vector>

namespace rosy::field {

/// OpenMesh traits of PolyMesh: double-precision points and normals; vertex
/// normals are requested only when a writer needs them.
struct PolyMeshTraits : public OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
};

/// A polygon mesh (OpenMesh PolyMesh_ArrayKernelT with PolyMeshTraits).
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<PolyMeshTraits>;

/// The triangles of `mesh` as a PolyMesh: vertex i and face f keep their indices.
PolyMesh toPolyMesh(const Mesh &mesh);

/// A PolyMesh from positions (#V) and polygons (each >= 3 vertex indices into
/// positions, counter-clockwise). Isolated vertices are kept.
/// \throws InputError naming `name` and the polygon if an index is out of range or
///   a polygon cannot be added without breaking the 2-manifold halfedge structure
///   (OpenMesh's "complex edge" or "complex vertex"): run repairAndBuild() first.
PolyMesh polyMeshFromPolygons(const std::vector<Vec3> &positions, const std::vector<std::vector<int>> &polygons,
                              const std::string &name);

/// What writePolyMesh() adds besides points and faces.
struct MeshExportOptions {
    /// Per-vertex unit directions (#V, world frame), e.g. the field's first member
    /// direction, written in the format's per-vertex normal slot: OBJ `vn` lines,
    /// OFF as `NOFF`, PLY `nx ny nz`. Empty: none. STL has no per-vertex data.
    std::vector<Vec3> vertexDirections;
};

/// The mesh formats writePolyMesh() accepts, for messages: ".obj, .off, .ply or .stl".
const char *meshExportExtensions();

/// True if `path` ends (case-insensitively) in one of meshExportExtensions().
bool isMeshExportPath(const std::string &path);

/// Writes `mesh` to `path` through OpenMesh's writer for the extension, atomically
/// (core/atomic_file.h: a temporary renamed into place, or published with the
/// current OutputBatch). OBJ and OFF are ASCII with 9 significant digits (float
/// coordinates round-trip exactly); PLY is binary little-endian and STL binary,
/// the compact forms for scan-sized meshes. STL has only triangles: polygons are
/// fan-triangulated first (OpenMesh's STL writer would skip them).
/// \throws InputError (path) for an unknown extension, for vertexDirections with
///   STL or of the wrong size. \throws IoError (path) if writing fails.
void writePolyMesh(const std::string &path, const PolyMesh &mesh, const MeshExportOptions &options = {});

} // namespace rosy::field
