/// \file fuzz_mesh.cpp
/// libFuzzer harness for one mesh format (ROSY_FUZZ_EXT: ".off", ".obj", ".ply", ".stl";
/// one executable per format, see CMakeLists.txt). The input is the whole file: it is
/// written to a scratch file with that extension and read by field::loadMesh (our checked
/// reader for the format plus validation and repairs), first with repairs, then strictly.
///
/// Oracle: loadMesh returns a mesh that passes checkMesh() (valid halfedges, χ = V − E + F
/// per component, Gauss–Bonnet through the frames) or throws InputError / IoError. The
/// strict load (repair = false) must agree: it succeeds only when the repairing load made
/// no repair, and then yields the same counts.

#include "fuzz_common.h"

#include "field/mesh_io.h"

#include <cstdint>
#include <cstring>

#ifndef ROSY_FUZZ_EXT
#error "compile with -DROSY_FUZZ_EXT=\".off\" (or .obj, .ply, .stl)"
#endif

using namespace rosy;

namespace {

/// Below libFuzzer's default 2 GB -rss_limit_mb with room to spare: 1e5 faces is a few
/// tens of MB through our reader and repair, and keeps one execution well under a second.
constexpr int64_t kMaxFaces = 100'000;

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fuzz::initOnce();
    const std::string path = fuzz::writeScratch(std::string("input") + ROSY_FUZZ_EXT, data, size);

    field::LoadOptions options;
    options.maxFaces = kMaxFaces;
    field::LoadReport report;
    field::Mesh mesh;
    try {
        mesh = field::loadMesh(path, options, &report);
    } catch (const InputError &e) {
        ROSY_FUZZ_ASSERT(std::strstr(e.what(), "error:") != nullptr, std::string("diagnostic format: ") + e.what());
        return 0;
    } catch (const IoError &) {
        return 0;
    }
    ROSY_FUZZ_ASSERT(mesh.nFaces() <= 2 * kMaxFaces, "face limit (polygons may triangulate into more)");
    const field::MeshStats stats = fuzz::checkMesh(mesh);

    // The strict load sees the same file: it may only fail if something was repaired.
    options.repair = false;
    try {
        field::LoadReport strictReport;
        const field::Mesh strict = field::loadMesh(path, options, &strictReport);
        ROSY_FUZZ_ASSERT(!report.anyRepair(), "strict load accepted a file that needed repairs");
        ROSY_FUZZ_ASSERT(strict.nVertices() == stats.vertices && strict.nFaces() == stats.faces,
                         "strict and repairing loads disagree");
    } catch (const InputError &) {
        ROSY_FUZZ_ASSERT(report.anyRepair(), "strict load rejected a file that needed no repair");
    }
    return 0;
}
