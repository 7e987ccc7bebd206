#pragma once
/// \file progress.h
/// A progress bar on stderr for long work. It draws only when stderr is a
/// terminal, progress is enabled (the CLI's --quiet disables it) and the work
/// has run for more than about a second, so short runs and logs stay clean.
///
/// Two kinds. Counted work (`Progress(label, total)` + advance()) redraws when
/// units finish. Staged work (`Progress(label, stages)` + beginStage()) names the
/// running stage and redraws by itself four times a second from a thread of its
/// own, so a long stage that reports nothing (hatching a 4096² render, writing a
/// large file) still shows its name, the elapsed time and, once a weighted stage
/// has finished, an estimate of the time left:
///     rendering: hatching      [#############.................]  43%   12.3s, about 16 s left
/// The estimate: the finished stages' seconds per unit of weight, times the weight
/// still to do, the running stage counted as far as its expected duration says
/// (capped at 95 % of it, so the bar never claims a stage done early).
/// The environment variable ROSY_PROGRESS_DELAY_MS (whole milliseconds) replaces
/// the one second of silence; at 0 every stage is drawn as it begins (the CLI
/// tests read the stage names that way through a pseudo-terminal).

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace rosy {

/// Globally enable or disable progress bars (default: enabled).
void setProgressEnabled(bool enabled);

/// One stage of staged work: its name and its expected share of the time (any
/// positive scale; only ratios matter).
struct ProgressStage {
    std::string name;
    double weight = 1.0;
};

class Progress {
public:
    /// \param label short stage name, e.g. "hatching"; \param total work units (> 0).
    Progress(std::string label, int64_t total);
    /// Staged work under `label` (e.g. "rendering"); stage 0 starts now.
    Progress(std::string label, std::vector<ProgressStage> stages);
    ~Progress();
    Progress(const Progress &) = delete;
    Progress &operator=(const Progress &) = delete;

    /// Adds `n` finished units. Thread-safe and cheap; redraws at most ~10 times a second.
    void advance(int64_t n = 1);
    /// Staged work: stage `index` starts now (the ones before it are done).
    void beginStage(size_t index);
    /// Staged work: a stage found to be needed on the way (e.g. one only some inputs
    /// have) put in at `index` (at most the number of stages); the current stage and
    /// the clock are kept, so the estimate goes on from the times measured so far.
    /// Ignored for counted work.
    void insertStage(size_t index, ProgressStage stage);
    /// Marks the work finished and clears the bar.
    void finish();

    /// The estimate of staged work `elapsedSec` seconds in, stage `index` started
    /// `stageStartSec` seconds in: the fraction done and the seconds left (< 0 when
    /// no stage with weight has finished yet, so there is no rate to go by).
    static void estimate(const std::vector<ProgressStage> &stages, size_t index, double stageStartSec,
                         double elapsedSec, double &fraction, double &secondsLeft);

private:
    void draw(int64_t done, bool final);
    void drawStaged(bool final);
    void tick();

    std::string m_label;
    int64_t m_total;
    std::atomic<int64_t> m_done{0};
    std::chrono::steady_clock::time_point m_start;
    std::atomic<int64_t> m_lastDrawMs{-1};
    std::mutex m_drawMutex;
    bool m_active;
    bool m_drawn = false;
    bool m_finished = false;
    // Staged work.
    std::vector<ProgressStage> m_stages;
    size_t m_stage = 0;           ///< guarded by m_drawMutex
    double m_stageStartSec = 0.0; ///< guarded by m_drawMutex
    std::thread m_ticker;
    std::condition_variable m_wake;
    bool m_stop = false; ///< guarded by m_drawMutex
};

} // namespace rosy
