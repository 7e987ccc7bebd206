/// \file fuzz_set.cpp
/// libFuzzer harness for `--set KEY=VALUE` overrides (render, field and compare take
/// them; scenes::parseScene applies them). The input is a list of overrides, one a
/// line; a line that starts with a space or a tab continues the previous override's
/// value on a new line, so block-style YAML values are reached too. At most eight
/// overrides are applied, in order, to a fixed scene that uses every top-level block
/// (<scratch>/scene.yaml, beside a small tetra.off), exactly as the CLI does.
///
/// Oracle (anything else is a finding): an InputError whose what() is one line with
/// `: error: ` and no control byte (printable()), or an IoError; otherwise a scene
/// whose numbers are in range, and, when its mesh is a primitive of at most
/// kMaxFaces faces by scenes::primitiveFaceCount() or the scratch mesh, buildScene()
/// builds exactly that many faces and passes the mesh checks. The budget that keeps
/// alias bombs and deep nesting out (10,000 values per value, 32 levels) is what makes
/// every input cheap: the harness's -timeout and -rss_limit_mb catch any gap.

#include "fuzz_common.h"

#include "scenes/scene.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

using namespace rosy;

namespace {

constexpr long long kMaxFaces = 20'000;
constexpr size_t kMaxOverrides = 8;

const char *kScene = "mesh: {primitive: torus, nu: 16, nv: 8}\n"
                     "camera: {resolution: [32, 32], fov: 30}\n"
                     "lights:\n  - {type: directional, direction: [1, 1, 1], intensity: 0.8}\n"
                     "style: {hatch: {stroke_width_px: 1.5}, page: {size: a4}}\n"
                     "field: {symmetry: 4, smoothing_length: 0.08}\n"
                     "picture: {kind: hatching}\n"
                     "output: out.png\n";

/// The overrides of one input: lines, indented lines continuing the previous value.
std::vector<std::string> overridesOf(const std::string &text) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= text.size() && out.size() <= kMaxOverrides) {
        size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        const std::string line = text.substr(start, end - start);
        if (!out.empty() && !line.empty() && (line[0] == ' ' || line[0] == '\t'))
            out.back() += "\n" + line;
        else if (!line.empty())
            out.push_back(line);
        start = end + 1;
    }
    if (out.size() > kMaxOverrides) out.resize(kMaxOverrides);
    return out;
}

void checkDiagnostic(const std::exception &e) {
    const std::string what = e.what();
    ROSY_FUZZ_ASSERT(what.find(": error: ") != std::string::npos, "diagnostic format: " + what);
    ROSY_FUZZ_ASSERT(what.find('\n') == std::string::npos, "an error line spans lines: " + what);
    ROSY_FUZZ_ASSERT(printable(what) == what, "raw control bytes in an error line: " + printable(what));
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fuzz::initOnce();
    static const std::string dir = [] {
        const char *tetra = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
        fuzz::writeScratch("tetra.off", reinterpret_cast<const uint8_t *>(tetra), std::strlen(tetra));
        return fuzz::scratchDir();
    }();
    const std::vector<std::string> overrides = overridesOf(std::string(reinterpret_cast<const char *>(data), size));

    scenes::SceneDesc desc;
    try {
        desc = scenes::parseScene(kScene, dir + "/scene.yaml", overrides);
    } catch (const InputError &e) {
        checkDiagnostic(e);
        return 0;
    } catch (const IoError &) {
        return 0;
    }
    const auto &res = desc.camera.resolution.value;
    ROSY_FUZZ_ASSERT(res[0] >= 1 && res[1] >= 1 && 1LL * res[0] * res[1] <= 4096LL * 4096LL, "resolution");
    ROSY_FUZZ_ASSERT(desc.field.spec.nSym >= 1 && desc.field.spec.nSym <= field::kMaxSymmetry, "symmetry");
    const double ell = desc.field.spec.smoothingLength;
    ROSY_FUZZ_ASSERT(ell == 0 || (ell >= 1e-6 && ell <= 10), "smoothing length");
    ROSY_FUZZ_ASSERT(std::isfinite(desc.camera.fov.value) && desc.camera.fov.value >= 1, "fov");
    const styles::PageStyle &page = desc.style.style.page;
    ROSY_FUZZ_ASSERT(page.widthMm >= 1 && page.widthMm <= 100000 && page.heightMm >= 1 && page.heightMm <= 100000,
                     "page size");
    ROSY_FUZZ_ASSERT(!desc.outputs.empty() && desc.outputs.size() <= 16, "outputs");

    // Build only what stays small and inside the scratch folder.
    long long faces = -1;
    if (desc.mesh.primitive) {
        faces = scenes::primitiveFaceCount(desc.mesh);
        ROSY_FUZZ_ASSERT(faces > 0, "primitive face count");
        if (faces > kMaxFaces) {
            // The limit must refuse it before building anything.
            try {
                scenes::buildScene(desc, field::LoadOptions{kMaxFaces});
                fuzz::fuzzFail("a primitive above the face limit was built");
            } catch (const InputError &e) {
                checkDiagnostic(e);
            }
            return 0;
        }
    } else if (!desc.mesh.file || desc.mesh.file->value != dir + "/tetra.off") {
        return 0;
    }
    scenes::Scene scene;
    try {
        scene = scenes::buildScene(desc, field::LoadOptions{kMaxFaces});
    } catch (const InputError &e) {
        checkDiagnostic(e);
        return 0;
    } catch (const IoError &) {
        return 0;
    }
    if (faces >= 0) ROSY_FUZZ_ASSERT(scene.mesh.nFaces() == faces, "primitiveFaceCount() is not the built count");
    fuzz::checkMesh(scene.mesh);
    ROSY_FUZZ_ASSERT(scene.camera.position().allFinite(), "camera position");
    return 0;
}
