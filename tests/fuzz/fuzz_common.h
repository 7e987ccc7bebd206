#pragma once
/// \file fuzz_common.h
/// Shared pieces of the libFuzzer harnesses (tests/fuzz/README in tests/README.md,
/// "Fuzzing and sanitizers"): a private scratch folder, quiet warnings, one thread,
/// and the invariant checks every harness applies to a mesh that loaded.
///
/// A finding is anything but a clean return or a rosy::InputError / rosy::IoError:
/// a sanitizer report, another exception (CheckFailure, std::bad_alloc, ...), or a
/// violated invariant, which calls fuzzFail() and aborts with a message.

#include "core/diagnostics.h"
#include "core/error.h"
#include "field/frames.h"
#include "field/mesh.h"
#include "field/mesh_stats.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <cfenv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <unistd.h>

namespace rosy::fuzz {

/// Prints the broken invariant and aborts, which libFuzzer records as a crash.
[[noreturn]] inline void fuzzFail(const std::string &what) {
    std::fprintf(stderr, "FUZZ INVARIANT VIOLATED: %s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

#define ROSY_FUZZ_ASSERT(cond, what)                                                       \
    do {                                                                                   \
        if (!(cond)) ::rosy::fuzz::fuzzFail(std::string(#cond) + ": " + (what));            \
    } while (0)

/// Process-wide set-up, done once: warnings silenced (they would flood the log) and
/// TBB limited to one thread (libFuzzer runs one input at a time; workers would only
/// add noise to the coverage and to -rss_limit_mb).
/// With ROSY_FUZZ_FPTRAP=1 in the environment, invalid operations and divisions by zero
/// trap (SIGFPE at the faulting line): for finding where a NaN of a finding comes from.
inline void initOnce() {
    static bool done = [] {
        rosy::setWarningsPrinted(false);
        if (const char *trap = std::getenv("ROSY_FUZZ_FPTRAP"); trap && std::strcmp(trap, "1") == 0)
            feenableexcept(FE_INVALID | FE_DIVBYZERO);
        static tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
        return true;
    }();
    (void)done;
}

/// A private folder for this process's temporary files, in /dev/shm when it exists
/// (the loaders read paths, and a RAM-backed file keeps the executions fast).
inline const std::string &scratchDir() {
    static const std::string dir = [] {
        std::string base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
        std::string templ = base + "/rosy-fuzz-XXXXXX";
        if (!mkdtemp(templ.data())) fuzzFail("cannot create a scratch folder in " + base);
        // Removed at exit; a killed fuzzer leaves one small folder behind.
        static std::string toRemove = templ;
        std::atexit([] { std::string cmd = "rm -rf '" + toRemove + "'"; (void)!std::system(cmd.c_str()); });
        return templ;
    }();
    return dir;
}

/// Writes bytes to scratchDir()/name and returns the path.
inline std::string writeScratch(const std::string &name, const uint8_t *data, size_t size) {
    std::string path = scratchDir() + "/" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char *>(data), std::streamsize(size));
    out.close();
    if (!out) fuzzFail("cannot write " + path);
    return path;
}

/// True if some face has zero area by the loaders' scale-free test (twice the area
/// <= 1e-12 × longest edge², docs/meshes.md). Such faces only reach the field code through
/// Mesh::fromTriangles; loadMesh() and repairAndBuild() drop them.
inline bool hasZeroAreaFace(const field::Mesh &mesh) {
    for (int f = 0; f < mesh.nFaces(); ++f) {
        const auto &c = mesh.face(f);
        const field::Vec3 &a = mesh.position(c[0]), &b = mesh.position(c[1]), &d = mesh.position(c[2]);
        const double longest2 = std::max({(b - a).squaredNorm(), (d - b).squaredNorm(), (a - d).squaredNorm()});
        if (!(mesh.faceNormalArea(f).norm() > 1e-12 * longest2)) return true;
    }
    return false;
}

/// Invariants of any Mesh the library hands out (mesh.h, docs/meshes.md), independent of
/// how it was made: finite coordinates, valid halfedge structure, V − E + F summed
/// per component, and discrete Gauss–Bonnet through the tangent frames
/// (Σ_f K_f + Σ_boundary (π − Θ_v) = 2πχ). Gauss–Bonnet is only required on meshes without
/// zero-area faces (a vertex whose faces all have zero area has no angle to rescale);
/// `frameTotal` receives the frames' own total / 2π either way, the value Poincaré–Hopf
/// of the singularity detector must match. Returns the stats for further checks.
inline field::MeshStats checkMesh(const field::Mesh &mesh, double *frameTotal = nullptr) {
    using field::Mesh;
    ROSY_FUZZ_ASSERT(mesh.nFaces() > 0, "a loaded mesh has faces");
    for (int v = 0; v < mesh.nVertices(); ++v) {
        ROSY_FUZZ_ASSERT(mesh.position(v).allFinite(), "vertex " + std::to_string(v));
        ROSY_FUZZ_ASSERT(mesh.degree(v) > 0, "isolated vertex " + std::to_string(v));
    }
    int boundaryHalfedges = 0;
    for (int h = 0; h < mesh.nHalfedges(); ++h) {
        const int t = mesh.twin(h);
        if (t < 0) {
            ++boundaryHalfedges;
            continue;
        }
        ROSY_FUZZ_ASSERT(t < mesh.nHalfedges() && mesh.twin(t) == h, "twin of twin, halfedge " + std::to_string(h));
        ROSY_FUZZ_ASSERT(mesh.tail(t) == mesh.head(h) && mesh.head(t) == mesh.tail(h),
                         "twins run opposite ways, halfedge " + std::to_string(h));
    }
    for (int f = 0; f < mesh.nFaces(); ++f) {
        const auto &c = mesh.face(f);
        ROSY_FUZZ_ASSERT(c[0] != c[1] && c[1] != c[2] && c[0] != c[2], "repeated corner in face " + std::to_string(f));
    }
    const field::MeshStats s = field::computeStats(mesh);
    ROSY_FUZZ_ASSERT(s.vertices == mesh.nVertices() && s.faces == mesh.nFaces() && s.edges == mesh.nEdges(),
                     "stats counts");
    ROSY_FUZZ_ASSERT(s.eulerCharacteristic == s.vertices - s.edges + s.faces, "chi = V - E + F");
    ROSY_FUZZ_ASSERT(2 * s.edges == 3 * s.faces + boundaryHalfedges, "2E = 3F + boundary edges");
    int chiSum = 0;
    for (int c : field::componentEulerCharacteristics(mesh)) chiSum += c;
    ROSY_FUZZ_ASSERT(chiSum == s.eulerCharacteristic, "per-component chi adds up");
    ROSY_FUZZ_ASSERT(s.genus >= 0 && s.components >= 1 && s.components <= s.faces, "genus, components");
    ROSY_FUZZ_ASSERT((boundaryHalfedges == 0) == (s.boundaryLoops == 0), "boundary loops iff boundary edges");

    const field::TangentFrames frames(mesh);
    double total = 0; // Σ K_f + boundary turning, compensated enough for ≤ 1e5 faces
    for (int f = 0; f < mesh.nFaces(); ++f) {
        ROSY_FUZZ_ASSERT(std::isfinite(frames.faceHolonomy(f)), "holonomy of face " + std::to_string(f));
        total += frames.faceHolonomy(f);
    }
    for (int v = 0; v < mesh.nVertices(); ++v)
        if (mesh.isBoundaryVertex(v)) total += M_PI - frames.angleTotal(v);
    const double expected = 2 * M_PI * s.eulerCharacteristic;
    if (!hasZeroAreaFace(mesh))
        ROSY_FUZZ_ASSERT(std::abs(total - expected) <= 1e-7 * (mesh.nFaces() + mesh.nVertices() + 1),
                         "Gauss-Bonnet: " + std::to_string(total) + " vs 2 pi chi = " + std::to_string(expected));
    if (frameTotal) *frameTotal = total / (2 * M_PI);
    return s;
}

} // namespace rosy::fuzz
