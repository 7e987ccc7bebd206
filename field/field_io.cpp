#include "field/field_io.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json.h"
#include "field/frames.h"

#include <cmath>
#include <cstdio>
#include <fstream>

namespace rosy::field {

std::vector<Vec3> memberDirections(const TangentFrames &frames, const RosyField &field, int v) {
    std::vector<Vec3> out;
    for (double a : memberAngles(field.u[v], field.nSym)) out.push_back(frames.tangentOfAngle(v, a));
    return out;
}

void writeFieldPly(const std::string &path, const TangentFrames &frames, const RosyField &field) {
    const Mesh &mesh = frames.mesh();
    checkWritable(path);
    writeAtomically(path, [&](const std::string &tmp) {
        std::ofstream os(tmp, std::ios::binary);
        if (!os) throw IoError(path, "cannot open for writing");
        os << "ply\nformat ascii 1.0\ncomment rosyhatch N-RoSy field\ncomment symmetry " << field.nSym
           << "\nelement vertex " << mesh.nVertices()
           << "\nproperty double x\nproperty double y\nproperty double z\nproperty double strength\n";
        for (int k = 0; k < field.nSym; ++k)
            os << "property double m" << k << "x\nproperty double m" << k << "y\nproperty double m" << k << "z\n";
        os << "element face " << mesh.nFaces() << "\nproperty list uchar int vertex_indices\nend_header\n";
        char buf[64];
        auto num = [&](double x) {
            std::snprintf(buf, sizeof buf, "%.9g", x == 0 ? 0.0 : x);
            os << buf;
        };
        for (int v = 0; v < mesh.nVertices(); ++v) {
            const Vec3 &p = mesh.position(v);
            num(p.x()), os << ' ', num(p.y()), os << ' ', num(p.z()), os << ' ';
            num(std::abs(field.u[v]));
            for (const Vec3 &d : memberDirections(frames, field, v)) {
                os << ' ', num(d.x()), os << ' ', num(d.y()), os << ' ', num(d.z());
            }
            os << '\n';
        }
        for (int f = 0; f < mesh.nFaces(); ++f) {
            const Face &t = mesh.face(f);
            os << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
        }
        os.flush();
        if (!os) throw IoError(path, "write failed (disk full?)");
    });
}

void writeAnalysisJson(JsonWriter &json, const MeshStats &stats, const SingularityReport &report, int nSym) {
    json.key("mesh").beginObject();
    json.field("vertices", stats.vertices).field("edges", stats.edges).field("faces", stats.faces);
    json.field("euler_characteristic", stats.eulerCharacteristic);
    json.field("boundary_loops", stats.boundaryLoops).field("components", stats.components);
    json.field("genus", stats.genus);
    json.endObject();
    json.key("singularities").beginArray();
    for (size_t i = 0; i < report.singularities.size(); ++i) {
        const Singularity &s = report.singularities[i];
        json.beginObject();
        json.field("id", int(i)).field("face", s.face);
        json.key("position").beginArray().value(s.position.x()).value(s.position.y()).value(s.position.z()).endArray();
        json.field("index", s.index()).field("index_numerator", s.indexNumerator);
        json.endObject();
    }
    json.endArray();
    json.field("index_sum", double(report.indexNumeratorSum) / nSym);
    json.field("boundary_index", report.boundaryIndex);
    const double total = report.totalIndex(nSym);
    json.key("poincare_hopf").beginObject();
    json.field("euler_characteristic", stats.eulerCharacteristic).field("total_index", total);
    json.field("holds", std::abs(total - stats.eulerCharacteristic) < 1e-6);
    json.endObject();
}

} // namespace rosy::field
