#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json.h"

#include <cctype>
#include <cstdio>

namespace rosy::cli {

bool hasExtension(const std::string &path, const char *dotExt) {
    const std::string want(dotExt);
    std::string ext = path.size() >= want.size() ? path.substr(path.size() - want.size()) : "";
    for (char &ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return ext == want;
}

bool isSvgPath(const std::string &path) { return hasExtension(path, ".svg"); }

void addCommonOptions(CLI::App &sub, CommonOptions &options) {
    sub.add_option("--threads", options.threads, "worker threads (0 = all cores; render and compare: overrides the scene's threads); "
                   "results do not depend on it")
        ->check(CLI::Range(0, 4096));
    sub.add_flag("-q,--quiet", options.quiet, "no progress bars or informational output");
    sub.add_option("--timings", options.timingsPath, "write per-stage wall-clock times as JSON to FILE: {\"stage\": milliseconds, ..., \"total\": milliseconds}");
    sub.add_option("--max-faces", options.maxFaces,
                   "reject mesh files with more faces than this, before reading them (default 20000000)")
        ->check(CLI::Range(1LL, 2'000'000'000LL));
}

void addSetOption(CLI::App &sub, std::vector<std::string> &overrides) {
    sub.add_option("--set", overrides,
                   "override a scene key by its dotted path before validation, VALUE parsed as YAML: "
                   "--set field.symmetry=2 --set 'camera.resolution=[512,512]'; repeatable, applied in order")
        ->allow_extra_args(false)
        ->type_name("KEY=VALUE");
}

void Timings::write(const std::string &path, double totalMs) const {
    JsonWriter json;
    json.beginObject();
    double sum = 0.0;
    for (const auto &[stage, seconds] : m_stages) {
        json.field(stage, seconds * 1000.0);
        sum += seconds * 1000.0;
    }
    json.field("total", totalMs > 0 ? totalMs : sum);
    json.endObject();
    writeTextAtomically(path, json.str());
}

} // namespace rosy::cli
