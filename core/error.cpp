#include "core/error.h"

namespace rosy {

std::string FileLoc::str() const {
    std::string s = path.empty() ? std::string("<input>") : path;
    if (line > 0) {
        s += ":" + std::to_string(line);
        if (col > 0) s += ":" + std::to_string(col);
    }
    return s;
}

static std::string formatInput(const FileLoc &loc, const std::string &message,
                               const std::string &hint) {
    std::string s = loc.str() + ": error: " + message;
    if (!hint.empty()) s += "; " + hint;
    return s;
}

InputError::InputError(FileLoc loc, const std::string &message, const std::string &hint)
    : std::runtime_error(formatInput(loc, message, hint)), m_loc(std::move(loc)),
      m_message(message) {}

IoError::IoError(const std::string &path, const std::string &message)
    : std::runtime_error(path + ": error: " + message), m_path(path) {}

namespace detail {
void checkFailed(const char *file, int line, const std::string &what) {
    throw CheckFailure(std::string(file) + ":" + std::to_string(line) +
                       ": internal check failed: " + what +
                       " (this is a bug in rosyhatch; please report it)");
}
} // namespace detail

} // namespace rosy
