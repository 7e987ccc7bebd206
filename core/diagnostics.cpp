#include "core/diagnostics.h"

#include "core/error.h"

#include <cstdio>
#include <mutex>

namespace rosy {
namespace {
std::mutex g_mutex;
std::map<std::string, int> g_counts;
bool g_printed = true;
WarningCapture *g_capture = nullptr;
} // namespace

void warn(const std::string &where, const std::string &kind, const std::string &message) {
    std::lock_guard<std::mutex> lock(g_mutex);
    ++g_counts[kind];
    if (g_capture) {
        g_capture->m_warnings.push_back({where, kind, message});
        return;
    }
    if (g_printed)
        std::fprintf(stderr, "%s: warning: %s\n", printable(where).c_str(), printable(message).c_str());
}

std::map<std::string, int> warningCounts() {
    std::lock_guard<std::mutex> lock(g_mutex);
    return g_counts;
}

void resetWarningCounts() {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_counts.clear();
}

void setWarningsPrinted(bool printed) {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_printed = printed;
}

WarningCapture::WarningCapture() {
    std::lock_guard<std::mutex> lock(g_mutex);
    m_previous = g_capture;
    g_capture = this;
}

WarningCapture::~WarningCapture() {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_capture = m_previous;
}

bool WarningCapture::has(const std::string &kind) const {
    for (const Warning &w : m_warnings)
        if (w.kind == kind) return true;
    return false;
}

} // namespace rosy
