#pragma once
/// \file style_block.h
/// Internal to scenes/: reading a scene's `style:` block (style_presets.cpp).

#include "scenes/scene.h"
#include "scenes/yaml_reader.h"

namespace rosy::scenes::detail {

/// Resolves a `style:` block into `sd`: the Style defaults, then the preset (a name
/// looked up in styleSearchDirs() or a path relative to the scene file), then the
/// block's own keys, then the checks between values (checkStyle).
/// \throws InputError at the offending key or value; IoError for an unreadable preset.
void parseStyle(const Parser &p, const YAML::Node &node, StyleDesc &sd);

} // namespace rosy::scenes::detail
