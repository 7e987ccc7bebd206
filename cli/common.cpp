#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json.h"

#include <cstdio>

namespace rosy::cli {

void addCommonOptions(CLI::App &sub, CommonOptions &options) {
    sub.add_option("--threads", options.threads, "worker threads (0 = all cores); results do not depend on it")
        ->check(CLI::Range(0, 4096));
    sub.add_flag("-q,--quiet", options.quiet, "no progress bars or informational output");
    sub.add_option("--timings", options.timingsPath, "write per-stage wall-clock seconds as JSON to FILE");
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
