#include "core/error.h"

#include <cstdint>
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

/// Length of the valid UTF-8 sequence starting at s[i] (a code point that is
/// neither a surrogate, overlong, beyond U+10FFFF nor a C1 control), else 0.
static size_t utf8Length(const std::string &s, size_t i) {
    const auto byte = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = byte(i);
    size_t n;
    uint32_t cp;
    if (c >= 0xC2 && c <= 0xDF) n = 2, cp = c & 0x1F;
    else if (c >= 0xE0 && c <= 0xEF) n = 3, cp = c & 0x0F;
    else if (c >= 0xF0 && c <= 0xF4) n = 4, cp = c & 0x07;
    else return 0;
    if (i + n > s.size()) return 0;
    for (size_t k = 1; k < n; ++k) {
        if ((byte(i + k) & 0xC0) != 0x80) return 0;
        cp = (cp << 6) | (byte(i + k) & 0x3F);
    }
    const uint32_t smallest[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < smallest[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
    if (cp >= 0x80 && cp <= 0x9F) return 0; // C1 controls (CSI is U+009B)
    return n;
}

std::string printable(const std::string &text, bool keepNewlines) {
    std::string out;
    out.reserve(text.size());
    static const char kHex[] = "0123456789abcdef";
    for (size_t i = 0; i < text.size();) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (c >= 0x20 && c < 0x7F) {
            out += char(c);
            ++i;
        } else if (c == '\n' && keepNewlines) {
            out += '\n';
            ++i;
        } else if (c == '\n' || c == '\t' || c == '\r') {
            out += c == '\n' ? "\\n" : c == '\t' ? "\\t" : "\\r";
            ++i;
        } else if (const size_t n = c >= 0x80 ? utf8Length(text, i) : 0; n > 0) {
            out.append(text, i, n);
            i += n;
        } else {
            out += "\\x";
            out += kHex[c >> 4];
            out += kHex[c & 15];
            ++i;
        }
    }
    return out;
}

// Streams rather than operator+ chains: GCC 12 reports a false -Wrestrict on those.
static std::string formatInput(const FileLoc &loc, const std::string &message,
                               const std::string &hint, bool keepNewlines) {
    std::ostringstream os;
    os << printable(loc.str()) << ": error: " << printable(message, keepNewlines);
    if (!hint.empty()) os << "; " << printable(hint, keepNewlines);
    return os.str();
}

InputError::InputError(FileLoc loc, const std::string &message, const std::string &hint)
    : std::runtime_error(formatInput(loc, message, hint, false)), m_loc(std::move(loc)),
      m_message(message) {}

IoError::IoError(const std::string &path, const std::string &message)
    : std::runtime_error(formatInput(FileLoc{path}, message, {}, true)), m_path(path) {}

namespace detail {
void checkFailed(const char *file, int line, const std::string &what) {
    std::ostringstream os;
    os << file << ":" << line << ": internal check failed: " << what
       << " (this is a bug in rosyhatch; please report it)";
    throw CheckFailure(os.str());
}
} // namespace detail

} // namespace rosy
