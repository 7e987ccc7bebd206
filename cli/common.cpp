#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <cstdio>
#include <fstream>

namespace rosy::cli {

void addCommonOptions(CLI::App &sub, CommonOptions &options) {
    sub.add_option("--threads", options.threads, "worker threads (0 = all cores); results do not depend on it")
        ->check(CLI::Range(0, 4096));
    sub.add_flag("-q,--quiet", options.quiet, "no progress bars or informational output");
    sub.add_option("--timings", options.timingsPath, "write per-stage wall-clock seconds as JSON to FILE");
}

void Timings::write(const std::string &path) const {
    writeAtomically(path, [&](const std::string &tmp) {
        std::ofstream out(tmp);
        if (!out) throw IoError(path, "cannot open the timings file for writing");
        double total = 0.0;
        out << "{\n  \"stages\": {";
        for (size_t i = 0; i < m_stages.size(); ++i) {
            char buf[64];
            std::snprintf(buf, sizeof buf, "%.6f", m_stages[i].second);
            out << (i ? ",\n" : "\n") << "    \"" << m_stages[i].first << "\": " << buf;
            total += m_stages[i].second;
        }
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.6f", total);
        out << "\n  },\n  \"total\": " << buf << "\n}\n";
        out.close();
        if (!out) throw IoError(path, "error while writing the timings file");
    });
}

} // namespace rosy::cli
