#include "core/progress.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>

namespace rosy {
namespace {
std::atomic<bool> g_enabled{true};

/// Milliseconds of silence before a bar first draws: 1000, or ROSY_PROGRESS_DELAY_MS
/// (a whole number of ms; anything else keeps the default).
int64_t delayMs() {
    static const int64_t ms = [] {
        const char *v = std::getenv("ROSY_PROGRESS_DELAY_MS");
        if (!v || !*v) return int64_t(1000);
        char *end = nullptr;
        const long long n = std::strtoll(v, &end, 10);
        return (*end == 0 && n >= 0 && n <= 3600000) ? int64_t(n) : int64_t(1000);
    }();
    return ms;
}
} // namespace

void setProgressEnabled(bool enabled) { g_enabled = enabled; }

Progress::Progress(std::string label, int64_t total)
    : m_label(std::move(label)), m_total(total > 0 ? total : 1),
      m_start(std::chrono::steady_clock::now()),
      m_active(g_enabled && isatty(STDERR_FILENO) == 1) {}

Progress::Progress(std::string label, std::vector<ProgressStage> stages)
    : m_label(std::move(label)), m_total(1), m_start(std::chrono::steady_clock::now()),
      m_active(g_enabled && isatty(STDERR_FILENO) == 1 && !stages.empty()), m_stages(std::move(stages)) {
    if (m_active && delayMs() == 0) drawStaged(false); // named from the start
    if (m_active) m_ticker = std::thread([this] { tick(); });
}

Progress::~Progress() { finish(); }

void Progress::estimate(const std::vector<ProgressStage> &stages, size_t index, double stageStartSec,
                        double elapsedSec, double &fraction, double &secondsLeft) {
    double total = 0.0, done = 0.0;
    for (size_t i = 0; i < stages.size(); ++i) {
        const double w = std::max(stages[i].weight, 0.0);
        total += w;
        if (i < index) done += w;
    }
    fraction = 0.0;
    secondsLeft = -1.0;
    if (!(total > 0.0) || index >= stages.size()) return;
    const double w = std::max(stages[index].weight, 0.0);
    double inStage = 0.0;
    if (done > 0.0 && stageStartSec > 0.0) {
        const double secondsPerWeight = stageStartSec / done;
        const double expected = w * secondsPerWeight;
        inStage = expected > 0.0 ? std::min(0.95, (elapsedSec - stageStartSec) / expected) : 0.0;
        // Left: the rest of this stage as expected (at least what the cap leaves), then the others.
        const double restOfStage = std::max(expected - (elapsedSec - stageStartSec), 0.05 * expected);
        secondsLeft = restOfStage + (total - done - w) * secondsPerWeight;
    }
    fraction = std::clamp((done + w * std::max(inStage, 0.0)) / total, 0.0, 1.0);
}

void Progress::beginStage(size_t index) {
    bool show = false;
    {
        std::lock_guard<std::mutex> lock(m_drawMutex);
        m_stage = std::min(index, m_stages.empty() ? size_t(0) : m_stages.size() - 1);
        m_stageStartSec = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
        // Once the bar shows, a new stage is named at once, not at the next tick.
        show = m_active && !m_stop && !m_stages.empty() && m_stageStartSec * 1000.0 >= double(delayMs());
    }
    if (show) drawStaged(false);
}

void Progress::insertStage(size_t index, ProgressStage stage) {
    std::lock_guard<std::mutex> lock(m_drawMutex);
    if (m_stages.empty()) return; // counted work
    index = std::min(index, m_stages.size());
    m_stages.insert(m_stages.begin() + std::ptrdiff_t(index), std::move(stage));
    if (index <= m_stage) ++m_stage;
}

void Progress::tick() {
    std::unique_lock<std::mutex> lock(m_drawMutex);
    // Silent for the first second (delayMs()), then four redraws a second until finish().
    if (m_wake.wait_for(lock, std::chrono::milliseconds(delayMs()), [this] { return m_stop; })) return;
    while (!m_stop) {
        lock.unlock();
        drawStaged(false);
        lock.lock();
        m_wake.wait_for(lock, std::chrono::milliseconds(250), [this] { return m_stop; });
    }
}

void Progress::drawStaged(bool final) {
    std::lock_guard<std::mutex> lock(m_drawMutex);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    if (final) {
        if (m_drawn) std::fprintf(stderr, "\r\033[K");
        std::fflush(stderr);
        return;
    }
    double fraction = 0.0, left = -1.0;
    estimate(m_stages, m_stage, m_stageStartSec, secs, fraction, left);
    constexpr int width = 30;
    const int filled = int(fraction * width);
    char bar[width + 1];
    for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
    bar[width] = 0;
    const std::string &stage = m_stages[m_stage].name;
    if (left < 0.0 && fraction <= 0.0) // nothing to go by yet: the stage and the time
        std::fprintf(stderr, "\r%s: %-13s %6.1fs", m_label.c_str(), stage.c_str(), secs);
    else
        std::fprintf(stderr, "\r%s: %-13s [%s] %3d%% %6.1fs", m_label.c_str(), stage.c_str(), bar,
                     int(fraction * 100), secs);
    // Time left only on long work (beyond a few seconds) and once there is a rate.
    if (left >= 0.0 && secs >= 3.0) std::fprintf(stderr, ", about %.0f s left", std::max(left, 1.0));
    std::fprintf(stderr, "\033[K");
    std::fflush(stderr);
    m_drawn = true;
}

void Progress::advance(int64_t n) {
    int64_t done = m_done.fetch_add(n) + n;
    if (!m_active || !m_stages.empty()) return;
    auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                  std::chrono::steady_clock::now() - m_start)
                  .count();
    // Stay silent for the first second (delayMs()); then redraw at most every 100 ms.
    if (ms < delayMs()) return;
    int64_t last = m_lastDrawMs.load();
    if (last >= 0 && ms - last < 100) return;
    if (!m_lastDrawMs.compare_exchange_strong(last, ms)) return;
    draw(done, false);
}

void Progress::finish() {
    if (m_finished) return;
    m_finished = true;
    if (!m_stages.empty()) {
        if (!m_active) return;
        {
            std::lock_guard<std::mutex> lock(m_drawMutex);
            m_stop = true;
        }
        m_wake.notify_all();
        if (m_ticker.joinable()) m_ticker.join();
        drawStaged(true);
        return;
    }
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
