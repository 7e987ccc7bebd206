#pragma once
/// \file style_presets.h
/// Style presets: YAML files of `style:` keys with a one-line description
/// (styles/presets/*.yaml), found by name in a search path, and the list of keys a
/// `style:` block or preset may set. A scene's `style: {preset: NAME}` starts from
/// the preset, then its own keys win.

#include "core/error.h"
#include "styles/style.h"

#include <map>
#include <string>
#include <vector>

namespace rosy::scenes {

/// One style preset found on disk.
struct StylePreset {
    std::string name;        ///< file stem, used as `preset: NAME`
    std::string description; ///< the file's one-line `description`
    std::string path;        ///< the file
};

/// Folders searched for `preset: NAME`, in order: $ROSY_STYLES_PATH (colon-separated),
/// the source tree's styles/presets (fixed at build time), and
/// <executable>/../share/rosyhatch/styles. Folders that do not exist are left out.
std::vector<std::string> styleSearchDirs();

/// Every preset (`*.yaml` in styleSearchDirs()), sorted by name; a name found in
/// several folders is taken from the first. Each file is parsed and validated.
/// 	hrows InputError `FILE:LINE:COL` for an invalid preset file; IoError if unreadable.
std::vector<StylePreset> listStylePresets();

/// Reads and validates one preset file (the keys of a `style:` block except
/// `preset`, plus a required one-line `description`) on top of the Style defaults.
/// \param setAt  if given, receives the dotted key -> location of each value set.
/// 	hrows IoError if the file cannot be read; InputError `FILE:LINE:COL` for bad content.
styles::Style loadStylePreset(const std::string &path, std::string *description = nullptr,
                              std::map<std::string, FileLoc> *setAt = nullptr);

/// Every dotted key a `style:` block or preset file accepts (besides `preset` and
/// `description`), e.g. "ambient", "hatch.taper", "contour.width_px".
std::vector<std::string> styleKeys();

} // namespace rosy::scenes
