#include "core/progress.h"

#include <cstdio>
#include <unistd.h>

namespace rosy {
namespace {
std::atomic<bool> g_enabled{true};
}

void setProgressEnabled(bool enabled) { g_enabled = enabled; }

Progress::Progress(std::string label, int64_t total)
    : m_label(std::move(label)), m_total(total > 0 ? total : 1),
      m_start(std::chrono::steady_clock::now()),
      m_active(g_enabled && isatty(STDERR_FILENO) == 1) {}

Progress::~Progress() { finish(); }

void Progress::advance(int64_t n) {
    int64_t done = m_done.fetch_add(n) + n;
    if (!m_active) return;
    auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                  std::chrono::steady_clock::now() - m_start)
                  .count();
    // Stay silent for the first second; then redraw at most every 100 ms.
    if (ms < 1000) return;
    int64_t last = m_lastDrawMs.load();
    if (last >= 0 && ms - last < 100) return;
    if (!m_lastDrawMs.compare_exchange_strong(last, ms)) return;
    draw(done, false);
}

void Progress::finish() {
    if (m_finished) return;
    m_finished = true;
    if (m_active && m_drawn) draw(m_total, true);
}

void Progress::draw(int64_t done, bool final) {
    std::lock_guard<std::mutex> lock(m_drawMutex);
    double frac = double(done) / double(m_total);
    if (frac > 1) frac = 1;
    constexpr int width = 30;
    int filled = int(frac * width);
    char bar[width + 1];
    for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
    bar[width] = 0;
    double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    std::fprintf(stderr, "\r%-12s [%s] %3d%% %6.1fs", m_label.c_str(), bar, int(frac * 100), secs);
    if (final) std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
    m_drawn = true;
}

} // namespace rosy
