/// \file cmd_render.cpp
/// `rosyhatch render SCENE.yaml`: the Lambert preview of a scene.

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "renderer/embree_scene.h"
#include "renderer/gbuffer.h"
#include "renderer/image.h"
#include "renderer/shading.h"
#include "scenes/scene.h"

#include <tbb/global_control.h>

#include <iostream>
#include <memory>
#include <optional>

namespace rosy::cli {

namespace {

struct RenderOptions {
    std::string scenePath;
    std::string outputPath; ///< -o; overrides the scene's output
    CommonOptions common;
};

void runRender(const RenderOptions &opt) {
    std::optional<tbb::global_control> threadLimit;
    if (opt.common.threads > 0)
        threadLimit.emplace(tbb::global_control::max_allowed_parallelism, size_t(opt.common.threads));
    setProgressEnabled(!opt.common.quiet);

    Timings timings;
    scenes::SceneDesc desc = timings.time("parse", [&] { return scenes::parseSceneFile(opt.scenePath); });
    std::string output = desc.output.value;
    if (!opt.outputPath.empty()) {
        if (!renderer::isSupportedImagePath(opt.outputPath))
            throw InputError(FileLoc{opt.outputPath}, "-o: unsupported image extension",
                             std::string("use one of ") + renderer::supportedImageExtensions());
        output = opt.outputPath;
    }
    // Fail on an unwritable destination before spending time on the render.
    checkWritable(output);
    if (!opt.common.timingsPath.empty()) checkWritable(opt.common.timingsPath);

    scenes::Scene scene = timings.time("load", [&] { return scenes::buildScene(desc); });
    auto rayScene = timings.time("bvh", [&] { return std::make_unique<renderer::RayScene>(scene.mesh); });
    renderer::GBuffer gbuffer =
        timings.time("gbuffer", [&] { return renderer::renderGBuffer(*rayScene, scene.mesh, scene.camera); });
    renderer::Image image = timings.time("shade", [&] {
        std::vector<double> tone = renderer::shadeLambert(gbuffer, *rayScene, scene.mesh, scene.camera,
                                                          scene.lights, scene.shading);
        return renderer::toneImage(tone, gbuffer.width, gbuffer.height, scene.style);
    });
    timings.time("write", [&] { renderer::writeImage(image, output); });
    if (!opt.common.timingsPath.empty()) timings.write(opt.common.timingsPath);
    std::cout << output << "\n";
}

} // namespace

void addRenderCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<RenderOptions>();
    CLI::App *sub = app.add_subcommand("render", "render the Lambert preview of a scene to an image");
    sub->add_option("scene", opt->scenePath, "scene file (YAML, see scenes/README.md)")->required();
    sub->add_option("-o,--output", opt->outputPath,
                    "output image (.png .exr .tif .tiff .jpg .jpeg); overrides the scene's output");
    addCommonOptions(*sub, opt->common);
    sub->callback([opt, &action] { action = [opt] { runRender(*opt); }; });
}

} // namespace rosy::cli
