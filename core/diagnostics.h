#pragma once
/// \file diagnostics.h
/// Warnings about repaired input. Libraries report each repair once per kind
/// through warn(); the CLI prints them as `warning:` lines and the render report
/// counts them. A thread-safe global sink keeps the plumbing out of every API;
/// tests install a WarningCapture to read them.

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace rosy {

struct Warning {
    std::string where; ///< file or element the warning is about, e.g. "bunny.off"
    std::string kind;  ///< short stable key, e.g. "degenerate-faces"
    std::string message;
};

/// Report a warning. Thread-safe. By default it is printed to stderr as
/// `where: warning: message`.
void warn(const std::string &where, const std::string &kind, const std::string &message);

/// Counts of every warning kind reported since the process started (or since
/// the last resetWarningCounts()), sorted by kind for deterministic reports.
std::map<std::string, int> warningCounts();
void resetWarningCounts();

/// Silence stderr printing (the CLI's --quiet keeps warnings, tests capture them).
void setWarningsPrinted(bool printed);

/// RAII capture: while alive, warnings are collected here instead of printed.
class WarningCapture {
public:
    WarningCapture();
    ~WarningCapture();
    WarningCapture(const WarningCapture &) = delete;
    WarningCapture &operator=(const WarningCapture &) = delete;
    const std::vector<Warning> &warnings() const { return m_warnings; }
    bool has(const std::string &kind) const;

private:
    friend void warn(const std::string &, const std::string &, const std::string &);
    std::vector<Warning> m_warnings;
    WarningCapture *m_previous;
};

} // namespace rosy
