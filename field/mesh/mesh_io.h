#pragma once
/// \file mesh_io.h
/// Reading meshes from OBJ, PLY (ascii and binary, faces or triangle strips),
/// OFF and STL files with our own checked readers (one per format, read_*.cpp;
/// docs/meshes.md says why not OpenMesh's), followed by validation and repair
/// into a clean Mesh (see mesh.h) in named steps (repair.cpp). Every repair is
/// reported once per kind through rosy::warn() with the file name; formats,
/// limits, errors and every repair treatment are documented in docs/meshes.md.
/// Writing goes through OpenMesh (poly_mesh.h).

#include "field/mesh/mesh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rosy::field {

struct LoadOptions {
    /// Files with more faces than this are rejected before allocating (InputError).
    int64_t maxFaces = 20'000'000;
    /// Repair awkward but valid meshes (the default). When false, anything that
    /// would need a repair is an InputError instead.
    bool repair = true;
    /// Point-in-triangle tests ear clipping may spend on one file (quadratic in a
    /// polygon's size); past it the remaining non-convex polygons are fanned and
    /// reported (LoadReport::largePolygonsFanned). The default keeps a file of large
    /// non-convex polygons to about half a second of loading (one polygon of about
    /// 14,000 corners exhausts it).
    int64_t earClipBudget = 200'000'000;
};

/// Counts of the repairs made while loading (all zero for a clean file).
struct LoadReport {
    int polygonsTriangulated = 0;          ///< polygons of more than 3 vertices
    int nonConvexPolygonsTriangulated = 0; ///< ... of them non-convex in their plane, ear-clipped
    int polygonsFanned = 0;                ///< ... non-convex ones ear clipping could not cut (self-crossing): fanned
    int largePolygonsFanned = 0;           ///< ... non-convex ones past the ear-clipping budget: fanned
    int degenerateFacesDropped = 0;   ///< repeated vertex or zero area
    int duplicateVerticesMerged = 0;
    int duplicateFacesDropped = 0;
    int isolatedVerticesDropped = 0;
    int nonManifoldEdgesSplit = 0;
    int nonManifoldVerticesSplit = 0;
    int facesReoriented = 0;

    /// Whether anything was repaired: what a load with LoadOptions::repair off rejects.
    /// (Triangulating, and ear-clipping non-convex polygons, is not a repair.)
    bool anyRepair() const {
        return polygonsFanned || largePolygonsFanned || degenerateFacesDropped || duplicateVerticesMerged ||
               duplicateFacesDropped || isolatedVerticesDropped || nonManifoldEdgesSplit ||
               nonManifoldVerticesSplit || facesReoriented;
    }
};

/// Loads and repairs a mesh. The format comes from the extension (.obj .ply .off .stl,
/// case-insensitive).
/// \throws IoError if the file is missing, unreadable or a folder.
/// \throws InputError naming the file for: unknown extension, unparsable content,
///   no faces after repair, a non-finite coordinate, a face index out of range,
///   more faces than options.maxFaces, a non-orientable surface.
Mesh loadMesh(const std::string &path, const LoadOptions &options = {},
              LoadReport *report = nullptr);

/// Builds a clean Mesh from a raw polygon soup with the same repairs as loadMesh().
/// Polygons (>= 3 vertices) are triangulated after dropping consecutive repeated
/// indices: fanned from their first vertex when convex in the plane of their Newell
/// normal, ear-clipped in that plane when not (an L-shaped CAD face fanned would
/// fold over its notch); one that crosses itself is fanned with a warning
/// (`self-crossing-polygons`), and so are those past the ear clipping's budget
/// (`large-nonconvex-polygons`, about 14,000 corners per file). `name` is used in messages.
/// A soup whose vertices are listed in no spatial order (more than half of the face
/// edges join vertices 4096 or more apart in the numbering: bunny00, scans) is
/// renumbered along a Morton curve, its faces ordered by their first vertex in the
/// new numbering (windings kept): what is near on the surface is then near in
/// memory, about 10 % off a render of bunny00. A soup already in spatial order keeps
/// its numbering and face order.
Mesh repairAndBuild(std::vector<Vec3> positions, const std::vector<std::vector<int>> &polygons,
                    const std::string &name, const LoadOptions &options = {},
                    LoadReport *report = nullptr);

} // namespace rosy::field
