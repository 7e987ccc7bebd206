#pragma once
/// \file field_io.h
/// Writing fields and their analysis for other tools.
///
/// Field export (PLY). An ASCII PLY of the mesh whose vertices carry, besides
/// x y z, the field's `symmetry` N as a comment line and per vertex the
/// properties `strength` (|u|) and `m0x m0y m0z … m{N−1}x m{N−1}y m{N−1}z`: the N
/// unit member directions in world coordinates, tangent to the surface
/// (counter-clockwise from m0, seen from outside). Faces are `vertex_indices`.
/// Any PLY reader (Blender, MeshLab, Python's plyfile) can read it.

#include "field/mesh_stats.h"
#include "field/rosy.h"
#include "field/singularities.h"

#include <map>
#include <string>

namespace rosy {
class JsonWriter;
}

namespace rosy::field {

/// Writes the PLY described above, atomically. \throws IoError.
void writeFieldPly(const std::string &path, const TangentFrames &frames, const RosyField &field);

/// Member directions (unit, world) of the field at vertex v.
std::vector<Vec3> memberDirections(const TangentFrames &frames, const RosyField &field, int v);

/// Appends `mesh`, `singularities`, `index_sum`, `boundary_index`,
/// `poincare_hopf` members describing the analysis to an open JSON object.
void writeAnalysisJson(JsonWriter &json, const MeshStats &stats, const SingularityReport &report, int nSym);

} // namespace rosy::field
