#pragma once
/// \file crease_normals.h
/// Shading normals that respect creases: one normal per face corner, averaged only
/// over the faces around the corner's vertex that are reached from the corner's own
/// face without crossing a crease (an edge whose faces meet at more than the crease
/// angle) or the boundary. Interpolated across a face with the hit's barycentrics,
/// they are smooth where the surface is smooth and stay the faces' own normals on
/// both sides of a sharp edge (a CAD part's rim), where the vertex normal
/// (Mesh::vertexNormal) averages the two sides and tilts every face that touches it.

#include "field/mesh.h"

#include <vector>

namespace rosy::renderer {

using Vec3 = Eigen::Vector3d;

/// Dihedral angle (between the two faces' normals) above which an edge is a crease.
/// Scanned and subdivided surfaces bend by a few degrees per edge, coarse ones like
/// CGAL's nefertiti.off by up to 60° (its nose); CAD parts by 70-90° at their rims
/// (fandisk.off: 693 of its 19,419 edges). docs/hatching.md has the figures.
constexpr double kCreaseAngleDeg = 65.0;

/// Unit normal of every face corner, indexed by halfedge: entry 3 f + k is the normal
/// at corner k of face f (the tail of halfedge 3 f + k). The faces around that
/// vertex are walked both ways from f, each step across an edge, stopping before a
/// crease (face normals more than `creaseAngleRad` apart) or the boundary; the faces
/// reached (f included) are summed weighted by their angle at the vertex. Zero-area
/// faces neither contribute nor stop the walk. Where the sum vanishes the entry is
/// face f's normal (zero for a zero-area face).
/// \param vertexNormals if not null, receives every vertex's normal over its whole
///   fan, equal to Mesh::vertexNormal (the same sums, computed in the same pass).
std::vector<Vec3> creaseAwareCornerNormals(const field::Mesh &mesh, double creaseAngleRad,
                                           std::vector<Vec3> *vertexNormals = nullptr);

} // namespace rosy::renderer
