#pragma once
/// \file primitives.h
/// Procedural meshes for scenes and tests. All are closed, oriented outward and
/// centred at the origin unless said otherwise; flat faces stay exactly flat.

#include "field/mesh.h"

namespace rosy::field {

/// Icosahedron subdivided `subdivisions` times (4^s × 20 faces), projected to a sphere.
Mesh makeIcosphere(int subdivisions, double radius = 1.0);
/// Icosphere scaled by (a, b, c): an ellipsoid with semi-axes a, b, c along x, y, z.
Mesh makeEllipsoid(int subdivisions, double a, double b, double c);
/// Torus around the z axis: major radius R, minor radius r, nU × nV quads split in two.
Mesh makeTorus(double majorRadius, double minorRadius, int nU, int nV);
/// A closed genus-2 surface (χ = −2): the boundary of a voxelized plate with two
/// holes, `resolution` voxels along its long side (>= 16, else InputError),
/// triangulated and rounded by Taubin λ/μ smoothing; x spans about [−1, 1].
Mesh makeGenus2(int resolution = 48);
/// Faces makeGenus2(resolution) has, counted without building it (for face limits).
long long genus2FaceCount(int resolution);
/// Axis-aligned cube [−1, 1]³ with each face an n × n grid of quads split in two.
Mesh makeCube(int n = 1);
/// Two cubes with rounded corners joined (Palacios & Zhang 2007, Figure 4): a cube
/// of half-side 1 (edges rounded with radius 0.25) with a smaller one (half-side
/// 0.6, radius 0.2) standing on the middle of its top face, the joint filleted
/// (smooth union, blend radius 0.15); z from -1 to 2.1. The vertices of a cube
/// sphere (six n × n grids, normalised) are moved along their directions from a
/// centre inside both cubes onto the surface (the union of two convex solids
/// that both contain the centre is star-shaped about it), so the mesh is closed,
/// oriented outward, genus 0, with 12 n² triangles; flat parts stay flat.
Mesh makeRoundedCubePair(int n = 32);

enum class Platonic { Tetrahedron, Cube, Octahedron, Dodecahedron, Icosahedron };
/// A Platonic solid inscribed in the unit sphere; each face is split into triangles
/// (pentagons by a centre fan) and then loop-free midpoint subdivided `subdivisions`
/// times in its own plane, so faces stay flat.
Mesh makePlatonic(Platonic solid, int subdivisions = 0);

/// Open meshes, for tests and analytic cases.
/// Flat disk of radius 1 in the z = 0 plane, normal +z, `rings` concentric rings.
Mesh makeDisk(int rings = 16);
/// Flat square [−1, 1]² in z = 0, n × n quads split in two, normal +z.
Mesh makeGrid(int n = 16);
/// Open cylinder of radius r around z from z = −h/2 to h/2, nAround × nAlong quads split in two.
Mesh makeCylinder(double radius, double height, int nAround, int nAlong);

/// Loop-free 1-to-4 midpoint subdivision (positions not smoothed): for scaling tests.
Mesh subdivideMidpoint(const Mesh &mesh);

} // namespace rosy::field
