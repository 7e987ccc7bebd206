#pragma once
/// \file error.h
/// The error contract of rosyhatch. Libraries throw; only cli/ catches, prints
/// and maps the error kind to an exit code:
///   InputError  -> exit 2 (rejected input: usage, scene, mesh, field, limits)
///   IoError     -> exit 3 (environment or I/O: unreadable input, unwritable output)
///   anything else (including CheckFailure) -> exit 1 (a bug)

#include <sstream>
#include <stdexcept>
#include <string>

namespace rosy {

/// `text` safe to print on a terminal: control bytes (C0, DEL, the C1 range) and
/// bytes that are not valid UTF-8 become `\xNN` escapes (newline `\n`, tab `\t`,
/// carriage return `\r`); valid UTF-8 text is kept. Error and warning lines pass
/// everything they echo from input files through it, so a file cannot move the
/// cursor or recolour the terminal. `keepNewlines` leaves `\n` as a line break.
std::string printable(const std::string &text, bool keepNewlines = false);

/// A place in a user's file. line and col are 1-based; 0 means "unknown".
struct FileLoc {
    std::string path;
    int line = 0;
    int col = 0;

    /// "path:line:col", "path:line" or "path", whichever parts are known.
    std::string str() const;
};

/// Input the user can fix: a bad scene, mesh, flag or parameter.
/// what() is the full diagnostic line: `path:line:col: error: message; hint`, one
/// line, with whatever it echoes passed through printable().
class InputError : public std::runtime_error {
public:
    InputError(FileLoc loc, const std::string &message, const std::string &hint = {});
    const FileLoc &loc() const { return m_loc; }
    const std::string &message() const { return m_message; }

private:
    FileLoc m_loc;
    std::string m_message;
};

/// The environment failed us: a file could not be read or written. what() is
/// `path: error: message` through printable() (the message may span lines).
class IoError : public std::runtime_error {
public:
    IoError(const std::string &path, const std::string &message);
    const std::string &path() const { return m_path; }

private:
    std::string m_path;
};

/// An internal invariant was violated: always a bug in rosyhatch.
class CheckFailure : public std::logic_error {
public:
    using std::logic_error::logic_error;
};

namespace detail {
[[noreturn]] void checkFailed(const char *file, int line, const std::string &what);

template <typename A, typename B>
[[noreturn]] void checkCompareFailed(const char *file, int line, const char *expr, const A &a,
                                     const B &b) {
    std::ostringstream os;
    os << expr << " with values " << a << " and " << b;
    checkFailed(file, line, os.str());
}
} // namespace detail

} // namespace rosy

/// Always-on invariant checks (never for data the user controls: throw InputError there).
#define ROSY_CHECK(cond)                                                                  \
    do {                                                                                  \
        if (!(cond)) ::rosy::detail::checkFailed(__FILE__, __LINE__, #cond);              \
    } while (0)
#define ROSY_CHECK_OP(a, op, b)                                                           \
    do {                                                                                  \
        const auto &rosyCheckA_ = (a);                                                    \
        const auto &rosyCheckB_ = (b);                                                    \
        if (!(rosyCheckA_ op rosyCheckB_))                                                \
            ::rosy::detail::checkCompareFailed(__FILE__, __LINE__, #a " " #op " " #b,     \
                                               rosyCheckA_, rosyCheckB_);                 \
    } while (0)
#define ROSY_CHECK_EQ(a, b) ROSY_CHECK_OP(a, ==, b)
#define ROSY_CHECK_LT(a, b) ROSY_CHECK_OP(a, <, b)
#define ROSY_CHECK_LE(a, b) ROSY_CHECK_OP(a, <=, b)
#define ROSY_CHECK_GE(a, b) ROSY_CHECK_OP(a, >=, b)
