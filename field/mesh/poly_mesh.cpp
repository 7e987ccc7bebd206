#include "field/mesh/poly_mesh.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <fstream>

namespace rosy::field {
namespace {

/// The extension without the dot, lower case ("ply"), or "" if not one we write.
std::string exportFormat(const std::string &path) {
    const size_t dot = path.find_last_of("./");
    if (dot == std::string::npos || path[dot] != '.') return {};
    std::string ext = path.substr(dot + 1);
    for (char &c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    for (const char *known : {"obj", "off", "ply", "stl"})
        if (ext == known) return ext;
    return {};
}

OpenMesh::Vec3d toOpenMesh(const Vec3 &p) { return OpenMesh::Vec3d(p.x(), p.y(), p.z()); }

} // namespace

const char *meshExportExtensions() { return ".obj, .off, .ply or .stl"; }

bool isMeshExportPath(const std::string &path) { return !exportFormat(path).empty(); }

PolyMesh toPolyMesh(const Mesh &mesh) {
    PolyMesh out;
    out.reserve(size_t(mesh.nVertices()), size_t(mesh.nEdges()), size_t(mesh.nFaces()));
    for (int v = 0; v < mesh.nVertices(); ++v) out.add_vertex(toOpenMesh(mesh.position(v)));
    for (int f = 0; f < mesh.nFaces(); ++f) {
        const Face &t = mesh.face(f);
        // Mesh is a clean oriented 2-manifold, so OpenMesh accepts every face.
        const PolyMesh::FaceHandle fh =
            out.add_face(out.vertex_handle(unsigned(t[0])), out.vertex_handle(unsigned(t[1])),
                         out.vertex_handle(unsigned(t[2])));
        ROSY_CHECK(fh.is_valid());
    }
    return out;
}

PolyMesh polyMeshFromPolygons(const std::vector<Vec3> &positions, const std::vector<std::vector<int>> &polygons,
                              const std::string &name) {
    PolyMesh out;
    out.reserve(positions.size(), 0, polygons.size());
    for (const Vec3 &p : positions) out.add_vertex(toOpenMesh(p));
    std::vector<PolyMesh::VertexHandle> handles;
    for (size_t f = 0; f < polygons.size(); ++f) {
        handles.clear();
        for (int v : polygons[f]) {
            if (v < 0 || v >= int(positions.size()))
                throw InputError(FileLoc{name}, fmt::format("polygon {} uses vertex index {} outside [0, {})", f, v,
                                                            positions.size()),
                                 "fix the polygon's indices");
            handles.push_back(out.vertex_handle(unsigned(v)));
        }
        if (handles.size() < 3 || !out.add_face(handles).is_valid())
            throw InputError(FileLoc{name},
                             fmt::format("polygon {} ({} vertices) cannot join the mesh as a 2-manifold face", f,
                                         handles.size()),
                             "repair the polygons first (repairAndBuild) or drop the face");
    }
    return out;
}

void writePolyMesh(const std::string &path, const PolyMesh &mesh, const MeshExportOptions &options) {
    const std::string format = exportFormat(path);
    if (format.empty())
        throw InputError(FileLoc{path}, "cannot write a mesh with this extension",
                         std::string("use ") + meshExportExtensions());
    const bool directions = !options.vertexDirections.empty();
    if (directions && format == "stl")
        throw InputError(FileLoc{path}, "STL files have no per-vertex data for the field directions",
                         "write .ply, .obj or .off to keep the directions");
    if (directions && options.vertexDirections.size() != mesh.n_vertices())
        throw InputError(FileLoc{path},
                         fmt::format("{} directions for {} vertices", options.vertexDirections.size(),
                                     mesh.n_vertices()),
                         "give one direction per vertex");
    // The writers read normals from the mesh itself, so directions go into a copy.
    PolyMesh copy;
    const PolyMesh *source = &mesh;
    OpenMesh::IO::Options flags = OpenMesh::IO::Options::Default;
    if (directions) {
        copy = mesh;
        copy.request_vertex_normals();
        for (const PolyMesh::VertexHandle vh : copy.vertices())
            copy.set_normal(vh, toOpenMesh(options.vertexDirections[size_t(vh.idx())]));
        source = &copy;
        flags += OpenMesh::IO::Options::VertexNormal;
    }
    // OpenMesh 9's STL writer skips every face that is not a triangle yet counts it
    // in the header, leaving a file no reader accepts: triangulate first.
    if (format == "stl" && std::any_of(mesh.faces_begin(), mesh.faces_end(),
                                       [&](PolyMesh::FaceHandle fh) { return mesh.valence(fh) != 3; })) {
        copy = mesh;
        copy.triangulate();
        source = &copy;
    }
    // OpenMesh logs every file it writes ("[OBJWriter] : write file") on omlog;
    // our commands print only what they were asked to. Its errors (omerr) stay on.
    omlog().disable();
    if (format == "ply" || format == "stl") flags += OpenMesh::IO::Options::Binary;
    if (format == "ply") flags += OpenMesh::IO::Options::LSB;
    writeAtomically(path, [&](const std::string &tmpPath) {
        std::ofstream os(tmpPath, std::ios::binary | std::ios::trunc);
        if (!os) throw IoError(path, "cannot open the temporary file to write the mesh");
        // 9 significant digits: every float coordinate reads back exactly.
        if (!OpenMesh::IO::write_mesh(*source, os, format, flags, 9))
            throw IoError(path, "OpenMesh's " + format + " writer failed (its message is on stderr)");
        os.flush();
        if (!os) throw IoError(path, "writing the mesh failed (disk full?)");
    });
}

} // namespace rosy::field
