/// \file fuzz_scene.cpp
/// libFuzzer harness for the scene loader: the input is a scene file's text.
/// scenes::parseScene (YAML syntax, keys, types, ranges, style presets) runs on it as
/// if it were <scratch>/scene.yaml, a folder that also holds small meshes `tetra.off`,
/// `quad.obj` and `tri.stl` so relative mesh paths can resolve. When the scene parses and
/// its mesh is small (a file from that folder, or a primitive of at most kMaxFaces
/// faces), scenes::buildScene loads the mesh and builds camera and lights. Nothing is
/// rendered.
///
/// Oracle: InputError / IoError, or a scene whose numbers are all finite: camera
/// position and unit axes, light directions, and a mesh passing checkMesh().

#include "fuzz_common.h"

#include "scenes/scene.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>

using namespace rosy;

namespace {

constexpr double kMaxFaces = 20'000;

void writeText(const std::string &name, const char *text) {
    fuzz::writeScratch(name, reinterpret_cast<const uint8_t *>(text), std::strlen(text));
}

bool unit(const Eigen::Vector3d &v) { return v.allFinite() && std::abs(v.norm() - 1) < 1e-6; }

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fuzz::initOnce();
    static const std::string dir = [] {
        writeText("tetra.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
        writeText("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
        writeText("tri.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                             "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n");
        return fuzz::scratchDir();
    }();
    const std::string text(reinterpret_cast<const char *>(data), size);

    scenes::SceneDesc desc;
    try {
        desc = scenes::parseScene(text, dir + "/scene.yaml");
    } catch (const InputError &e) {
        ROSY_FUZZ_ASSERT(std::strstr(e.what(), "error:") != nullptr, std::string("diagnostic format: ") + e.what());
        return 0;
    } catch (const IoError &) {
        return 0;
    }
    ROSY_FUZZ_ASSERT(desc.camera.resolution.value[0] >= 1 && desc.camera.resolution.value[1] >= 1, "resolution");
    ROSY_FUZZ_ASSERT(desc.field.spec.nSym >= 1 && desc.field.spec.nSym <= field::kMaxSymmetry, "symmetry");
    ROSY_FUZZ_ASSERT(std::isfinite(desc.field.spec.smoothingLength), "smoothing length");
    for (const auto &e : desc.field.spec.elements)
        ROSY_FUZZ_ASSERT(e.position.allFinite() && std::isfinite(e.strength) && e.strength > 0, "design element");

    // Build only what stays small and inside the scratch folder: a mesh path elsewhere
    // could name a huge file or a device.
    if (desc.mesh.file) {
        const std::string parent = std::filesystem::path(desc.mesh.file->value).lexically_normal().parent_path();
        if (parent != std::filesystem::path(dir).lexically_normal().string()) return 0;
    } else if (!desc.mesh.primitive || !(scenes::primitiveFaceCount(desc.mesh) <= kMaxFaces)) {
        return 0;
    }
    scenes::Scene scene;
    try {
        scene = scenes::buildScene(desc);
    } catch (const InputError &e) {
        ROSY_FUZZ_ASSERT(std::strstr(e.what(), "error:") != nullptr, std::string("diagnostic format: ") + e.what());
        return 0;
    } catch (const IoError &) {
        return 0;
    }
    fuzz::checkMesh(scene.mesh);
    const renderer::Camera &cam = scene.camera;
    ROSY_FUZZ_ASSERT(cam.position().allFinite(), "camera position");
    ROSY_FUZZ_ASSERT(unit(cam.forward()) && unit(cam.right()) && unit(cam.up()), "camera axes");
    ROSY_FUZZ_ASSERT(!scene.lights.empty(), "at least one light");
    for (const auto &l : scene.lights) {
        ROSY_FUZZ_ASSERT(l.direction.allFinite() && l.direction.norm() > 0, "light direction");
        ROSY_FUZZ_ASSERT(l.position.allFinite() && std::isfinite(l.intensity) && l.intensity >= 0, "light");
    }
    return 0;
}
