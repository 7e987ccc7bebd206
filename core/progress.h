#pragma once
/// \file progress.h
/// A progress bar on stderr for long work. It draws only when stderr is a
/// terminal, progress is enabled (the CLI's --quiet disables it) and the work
/// has run for more than about a second, so short runs and logs stay clean.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace rosy {

/// Globally enable or disable progress bars (default: enabled).
void setProgressEnabled(bool enabled);

class Progress {
public:
    /// \param label short stage name, e.g. "hatching"; \param total work units (> 0).
    Progress(std::string label, int64_t total);
    ~Progress();
    Progress(const Progress &) = delete;
    Progress &operator=(const Progress &) = delete;

    /// Adds `n` finished units. Thread-safe and cheap; redraws at most ~10 times a second.
    void advance(int64_t n = 1);
    /// Marks the work finished and clears the bar.
    void finish();

private:
    void draw(int64_t done, bool final);

    std::string m_label;
    int64_t m_total;
    std::atomic<int64_t> m_done{0};
    std::chrono::steady_clock::time_point m_start;
    std::atomic<int64_t> m_lastDrawMs{-1};
    std::mutex m_drawMutex;
    bool m_active;
    bool m_drawn = false;
    bool m_finished = false;
};

} // namespace rosy
