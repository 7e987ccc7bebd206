#include "core/error.h"

#include <sstream>

namespace rosy {

std::string FileLoc::str() const {
    std::ostringstream os;
    os << (path.empty() ? std::string("<input>") : path);
    if (line > 0) {
        os << ":" << line;
        if (col > 0) os << ":" << col;
    }
    return os.str();
}

// Streams rather than operator+ chains: GCC 12 reports a false -Wrestrict on those.
static std::string formatInput(const FileLoc &loc, const std::string &message,
                               const std::string &hint) {
    std::ostringstream os;
    os << loc.str() << ": error: " << message;
    if (!hint.empty()) os << "; " << hint;
    return os.str();
}

InputError::InputError(FileLoc loc, const std::string &message, const std::string &hint)
    : std::runtime_error(formatInput(loc, message, hint)), m_loc(std::move(loc)),
      m_message(message) {}

IoError::IoError(const std::string &path, const std::string &message)
    : std::runtime_error(formatInput(FileLoc{path}, message, {})), m_path(path) {}

namespace detail {
void checkFailed(const char *file, int line, const std::string &what) {
    std::ostringstream os;
    os << file << ":" << line << ": internal check failed: " << what
       << " (this is a bug in rosyhatch; please report it)";
    throw CheckFailure(os.str());
}
} // namespace detail

} // namespace rosy
