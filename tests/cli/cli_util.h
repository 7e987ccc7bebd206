#pragma once
/// \file cli_util.h
/// Running the rosyhatch binary from the end-to-end tests in this folder.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <sys/wait.h>

#include "tests/test_output.h" // testOutputDir(), slurp(), put()

namespace rosy::test {

/// Width and height of a PNG from its IHDR chunk (big-endian at bytes 16..23);
/// {0, 0} when the bytes are too short to hold one.
inline std::pair<unsigned, unsigned> pngSize(const std::string &png) {
    if (png.size() < 24) return {0, 0};
    auto be32 = [&](size_t at) {
        return (unsigned(uint8_t(png[at])) << 24) | (unsigned(uint8_t(png[at + 1])) << 16) |
               (unsigned(uint8_t(png[at + 2])) << 8) | unsigned(uint8_t(png[at + 3]));
    };
    return {be32(16), be32(20)};
}

/// Number of <path> elements in the SVG layer labelled `label` (inkscape:label),
/// or -1 when the document has no such layer.
inline int svgLayerPaths(const std::string &svg, const std::string &label) {
    const size_t at = svg.find("inkscape:label=\"" + label + "\"");
    if (at == std::string::npos) return -1;
    const size_t end = svg.find("</g>", at);
    int n = 0;
    for (size_t p = svg.find("<path ", at); p != std::string::npos && p < end; p = svg.find("<path ", p + 1)) ++n;
    return n;
}

/// Exit code (-1 if killed by a signal) and both output streams of one run.
struct CliRun {
    int exitCode;
    std::string out, err;
};

/// Runs the rosyhatch binary of this build with `args` (already shell-quoted)
/// from `dir`; stdout and stderr are kept there as TAG.stdout and TAG.stderr.
inline CliRun runRosyhatch(const std::filesystem::path &dir, const std::string &args, const std::string &tag) {
    const std::string binary = std::string(ROSY_BINARY_DIR) + "/cli/rosyhatch";
    const std::filesystem::path out = dir / (tag + ".stdout"), err = dir / (tag + ".stderr");
    const std::string cmd = "cd '" + dir.string() + "' && '" + binary + "' " + args + " >'" + out.string() + "' 2>'" +
                            err.string() + "'";
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

} // namespace rosy::test
