/// \file cmd_styles.cpp
/// `rosyhatch styles [--paths]`: the style presets a scene can name with
/// `style: {preset: NAME}`, each with its one-line description.

#include "cli/commands.h"

#include "scenes/scene.h"

#include <algorithm>
#include <iostream>
#include <memory>

namespace rosy::cli {
namespace {

void runStyles(bool showPaths) {
    const std::vector<scenes::StylePreset> presets = scenes::listStylePresets();
    if (presets.empty()) {
        std::cout << "no style presets found; searched:";
        for (const std::string &d : scenes::styleSearchDirs()) std::cout << " " << d;
        std::cout << "\n(set ROSY_STYLES_PATH to a folder of preset .yaml files)\n";
        return;
    }
    size_t width = 0;
    for (const auto &p : presets) width = std::max(width, p.name.size());
    for (const auto &p : presets) {
        std::cout << p.name << std::string(width - p.name.size() + 2, ' ') << p.description << "\n";
        if (showPaths) std::cout << std::string(width + 2, ' ') << p.path << "\n";
    }
}

} // namespace

void addStylesCommand(CLI::App &app, Action &action) {
    auto showPaths = std::make_shared<bool>(false);
    CLI::App *sub = app.add_subcommand("styles", "list the style presets a scene can use (style: {preset: NAME})");
    sub->add_flag("--paths", *showPaths, "also print the file each preset is read from");
    sub->callback([showPaths, &action] { action = [showPaths] { runStyles(*showPaths); }; });
}

} // namespace rosy::cli
