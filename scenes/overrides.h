#pragma once
/// \file overrides.h
/// Internal to scenes/: `--set dotted.key=VALUE` (and the flags that stand for a
/// key, scenes::FlagOverride) applied to a scene's YAML tree before it is parsed,
/// so an overridden value is checked exactly like the file's own.

#include "scenes/yaml_reader.h"

#include <string>

namespace rosy::scenes::detail {

/// Applies one `--set dotted.path=VALUE` to the scene's YAML tree, before any
/// validation: VALUE is parsed as YAML, maps on the way are created, and every node
/// the override brings (value, new keys, new maps) is located at the override, so
/// a bad value is reported as `--set KEY=VALUE: error: ...`. A list element is
/// addressed by its 0-based position (`lights.0.intensity=0.5`).
/// Every node the override brings is located at `where` ("--set KEY=VALUE" or the
/// flag), so errors in it name the override, not the file.
void applyOverride(Parser &p, YAML::Node &root, const std::string &text, const FileLoc &where);

} // namespace rosy::scenes::detail
