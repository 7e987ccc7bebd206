// core/progress.h: the bar draws only on a terminal, only when enabled, and only
// after the first second; a pseudo-terminal stands in for the user's terminal.

#include "core/progress.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <fcntl.h>
#include <string>
#include <vector>
#include <thread>
#include <unistd.h>

using namespace rosy;

namespace {

/// stderr redirected to a new pseudo-terminal while alive; read() drains what was written.
class StderrOnTerminal {
public:
    StderrOnTerminal() {
        m_master = ::posix_openpt(O_RDWR | O_NOCTTY);
        if (m_master < 0 || ::grantpt(m_master) != 0 || ::unlockpt(m_master) != 0) return;
        m_slave = ::open(::ptsname(m_master), O_RDWR | O_NOCTTY);
        if (m_slave < 0) return;
        std::fflush(stderr);
        m_saved = ::dup(STDERR_FILENO);
        ::dup2(m_slave, STDERR_FILENO);
        ::fcntl(m_master, F_SETFL, O_NONBLOCK);
    }
    ~StderrOnTerminal() {
        std::fflush(stderr);
        if (m_saved >= 0) ::dup2(m_saved, STDERR_FILENO), ::close(m_saved);
        if (m_slave >= 0) ::close(m_slave);
        if (m_master >= 0) ::close(m_master);
    }
    bool ok() const { return m_saved >= 0; }
    std::string read() {
        std::fflush(stderr);
        std::string out;
        char buf[256];
        for (ssize_t n; (n = ::read(m_master, buf, sizeof buf)) > 0;) out.append(buf, size_t(n));
        return out;
    }

private:
    int m_master = -1, m_slave = -1, m_saved = -1;
};

} // namespace

TEST(Progress, SilentWhenStderrIsNoTerminal) {
    testing::internal::CaptureStderr(); // a file, not a terminal
    {
        Progress p("hatching", 10);
        std::this_thread::sleep_for(std::chrono::milliseconds(1100));
        p.advance(5);
        p.finish();
    }
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(Progress, OnATerminalDrawsAfterTheFirstSecondUnlessDisabled) {
    StderrOnTerminal tty;
    if (!tty.ok()) GTEST_SKIP() << "no pseudo-terminal";
    setProgressEnabled(false);
    Progress disabled("disabled", 4);
    setProgressEnabled(true);
    Progress bar("hatching", 4);
    bar.advance(1); // within the first second: nothing
    EXPECT_EQ(tty.read(), "");
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    disabled.advance(2);
    EXPECT_EQ(tty.read(), "");
    bar.advance(1); // 2 of 4 after a second: half the 30-character bar
    const std::string drawn = tty.read();
    EXPECT_EQ(drawn.rfind("\rhatching     [###############...............]  50%", 0), 0u) << drawn;
    EXPECT_EQ(drawn.back(), 's');
    bar.finish(); // redrawn full, then the line cleared
    const std::string finished = tty.read();
    EXPECT_NE(finished.find("[##############################] 100%"), std::string::npos) << finished;
    EXPECT_EQ(finished.substr(finished.size() - 4), "\r\033[K");
    bar.finish(); // only once
    EXPECT_EQ(tty.read(), "");
}

TEST(Progress, StagedEstimateFollowsTheFinishedStagesRate) {
    const std::vector<ProgressStage> stages = {{"a", 1}, {"b", 3}};
    double fraction = 0, left = 0;
    // In the first stage there is no rate yet: nothing done, no time left.
    Progress::estimate(stages, 0, 0.0, 0.5, fraction, left);
    EXPECT_EQ(fraction, 0.0);
    EXPECT_LT(left, 0.0);
    // Stage a (weight 1) took 2 s: b (weight 3) should take 6 s. One second into b:
    // done (1 + 3/6) of 4, left 5 s.
    Progress::estimate(stages, 1, 2.0, 3.0, fraction, left);
    EXPECT_DOUBLE_EQ(fraction, 1.5 / 4.0);
    EXPECT_DOUBLE_EQ(left, 5.0);
    // A stage running late stays at 95 % of its weight and keeps a little time left.
    Progress::estimate(stages, 1, 2.0, 20.0, fraction, left);
    EXPECT_DOUBLE_EQ(fraction, (1.0 + 0.95 * 3.0) / 4.0);
    EXPECT_GT(left, 0.0);
}

TEST(Progress, StagedWorkNamesItsStageWithoutBeingAdvanced) {
    StderrOnTerminal tty;
    if (!tty.ok()) GTEST_SKIP() << "no pseudo-terminal";
    setProgressEnabled(true);
    Progress p("rendering", {{"first", 1}, {"second", 3}});
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    p.beginStage(1);
    EXPECT_EQ(tty.read(), ""); // silent in the first second
    // No advance() at all: the display's own thread redraws with the running stage.
    std::this_thread::sleep_for(std::chrono::milliseconds(1300));
    const std::string drawn = tty.read();
    EXPECT_NE(drawn.find("\rrendering: second"), std::string::npos) << drawn;
    EXPECT_NE(drawn.find("%"), std::string::npos) << drawn; // the first stage gave a rate: a bar
    p.finish();
    const std::string finished = tty.read();
    EXPECT_EQ(finished.substr(finished.size() - 4), "\r\033[K");
}

TEST(Progress, AStageInsertedOnTheWayKeepsTheRunningStageAndTheClock) {
    StderrOnTerminal tty;
    if (!tty.ok()) GTEST_SKIP() << "no pseudo-terminal";
    setProgressEnabled(true);
    Progress p("preparing", {{"a", 1}, {"c", 1}});
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    p.beginStage(1);                // c runs
    p.insertStage(1, {"b", 2});     // before it: c is still the one running, now third
    p.insertStage(9, {"d", 1});     // past the end: appended
    std::this_thread::sleep_for(std::chrono::milliseconds(1200));
    const std::string drawn = tty.read();
    const size_t at = drawn.rfind("\rpreparing: ");
    ASSERT_NE(at, std::string::npos) << drawn;
    EXPECT_EQ(drawn.compare(at + 12, 2, "c "), 0) << drawn;
    // a and b (weights 1 + 2) of 5 are done: at least 60 %, and c (one more) at most 95 % of it.
    const size_t pct = drawn.find('%', at);
    ASSERT_NE(pct, std::string::npos) << drawn;
    const int shown = std::atoi(drawn.substr(pct - 3, 3).c_str());
    EXPECT_GE(shown, 60) << drawn;
    EXPECT_LE(shown, 79) << drawn;
    p.beginStage(3); // d: the last
    p.finish();
    Progress counted("hatching", 4);
    counted.insertStage(0, {"x", 1}); // counted work has no stages: ignored
    counted.finish();
}
