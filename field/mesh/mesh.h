#pragma once
/// \file mesh.h
/// The triangle mesh every field algorithm works on: an oriented 2-manifold
/// (possibly with boundary, possibly several components) with implicit halfedges.
///
/// Halfedge h = 3 f + k belongs to face f and runs from corner k to corner k+1
/// (mod 3) of that face. Faces are counter-clockwise seen from outside, so the
/// face normal is (p1 - p0) x (p2 - p0). twin(h) is the opposite halfedge in the
/// neighbouring face, or -1 on a boundary edge.
///
/// Mesh::fromTriangles() only accepts clean input (manifold, consistently
/// oriented, no repeated vertex in a face, no isolated vertex); the loaders in
/// mesh_io.h repair raw files into that form and warn about each repair.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace rosy::field {

/// Smallest bounding-box diagonal a mesh with faces may have (see Mesh::fromTriangles).
constexpr double kMinMeshSize = 1e-15;

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Face = std::array<int, 3>;

class Mesh {
public:
    Mesh() = default;

    /// Builds connectivity for a clean triangle list.
    /// \param positions #V points (world units). \param faces #F CCW vertex triples.
    /// \throws InputError (with `name` as the file) if a face repeats a vertex or
    ///   uses an index outside [0, #V), an edge is shared by more than two faces or
    ///   traversed twice in the same direction (inconsistent orientation), a vertex
    ///   is isolated or non-manifold (two fans), a coordinate is not finite, or the
    ///   mesh has faces and its bounding-box diagonal is below kMinMeshSize.
    static Mesh fromTriangles(std::vector<Vec3> positions, std::vector<Face> faces,
                              const std::string &name = "<mesh>");

    int nVertices() const { return int(m_positions.size()); }
    int nFaces() const { return int(m_faces.size()); }
    int nHalfedges() const { return 3 * nFaces(); }
    int nEdges() const { return int(m_edgeHalfedge.size()); }
    const std::string &name() const { return m_name; }

    const std::vector<Vec3> &positions() const { return m_positions; }
    const std::vector<Face> &faces() const { return m_faces; }
    const Vec3 &position(int v) const { return m_positions[v]; }
    const Face &face(int f) const { return m_faces[f]; }

    // --- halfedges ----------------------------------------------------------
    static int faceOf(int h) { return h / 3; }
    static int next(int h) { return h - h % 3 + (h % 3 + 1) % 3; }
    static int prev(int h) { return h - h % 3 + (h % 3 + 2) % 3; }
    int tail(int h) const { return m_faces[h / 3][h % 3]; }
    int head(int h) const { return m_faces[h / 3][(h % 3 + 1) % 3]; }
    int twin(int h) const { return m_twin[h]; }
    bool isBoundaryHalfedge(int h) const { return m_twin[h] < 0; }
    /// Edge id of halfedge h, in [0, nEdges()).
    int edgeOf(int h) const { return m_halfedgeEdge[h]; }
    /// The canonical halfedge of edge e (the one with the smaller index of the pair,
    /// or the only one on a boundary edge).
    int edgeHalfedge(int e) const { return m_edgeHalfedge[e]; }
    Vec3 vector(int h) const { return position(head(h)) - position(tail(h)); }

    // --- vertex one-rings -----------------------------------------------------
    /// Outgoing halfedges of v in counter-clockwise order (seen from outside).
    /// For a boundary vertex the first one is the boundary halfedge leaving v
    /// (the face on its left is the most clockwise face around v).
    /// Shape: a contiguous span of the CSR arrays.
    const int *outgoingBegin(int v) const { return m_ring.data() + m_ringOffset[v]; }
    const int *outgoingEnd(int v) const { return m_ring.data() + m_ringOffset[v + 1]; }
    int degree(int v) const { return m_ringOffset[v + 1] - m_ringOffset[v]; }
    bool isBoundaryVertex(int v) const { return m_boundaryVertex[v] != 0; }
    /// Number of neighbour vertices: degree(v) + 1 on the boundary, degree(v) inside.
    int valence(int v) const { return degree(v) + (isBoundaryVertex(v) ? 1 : 0); }

    // --- geometry -------------------------------------------------------------
    /// Unnormalized face normal (p1-p0)x(p2-p0); its length is twice the area.
    Vec3 faceNormalArea(int f) const;
    /// Unit face normal; zero vector for a zero-area face.
    Vec3 faceNormal(int f) const;
    double faceArea(int f) const { return 0.5 * faceNormalArea(f).norm(); }
    /// Interior angle of face(h/3) at tail(h) in radians, in [0, pi].
    double cornerAngle(int h) const;
    /// Angle-weighted vertex normal (unit; zero only for isolated fans of zero area).
    Vec3 vertexNormal(int v) const;

    /// cornerAngle(h) for every halfedge h and faceNormal(f) for every face f, computed
    /// on first use (in parallel, the same values) and kept: the frames, the Laplacian,
    /// the crease normals, the contours and the screen field all read them. Copies of a
    /// mesh share them (a mesh never changes). Safe to call from several threads.
    const std::vector<double> &cornerAngles() const;
    const std::vector<Vec3> &faceNormals() const;
    /// Axis-aligned bounding box of all positions.
    void bounds(Vec3 &lo, Vec3 &hi) const;
    /// Mean edge length (0 for an empty mesh).
    double meanEdgeLength() const;

private:
    /// What cornerAngles() and faceNormals() compute once.
    struct Derived {
        std::once_flag anglesOnce, normalsOnce;
        std::vector<double> cornerAngles;
        std::vector<Vec3> faceNormals;
    };
    std::shared_ptr<Derived> m_derived = std::make_shared<Derived>();
    std::string m_name;
    std::vector<Vec3> m_positions;
    std::vector<Face> m_faces;
    std::vector<int> m_twin;          // #3F
    std::vector<int> m_halfedgeEdge;  // #3F
    std::vector<int> m_edgeHalfedge;  // #E
    std::vector<int> m_ringOffset;    // #V+1
    std::vector<int> m_ring;          // #3F, outgoing halfedges grouped by vertex
    std::vector<uint8_t> m_boundaryVertex; // #V
};

} // namespace rosy::field
