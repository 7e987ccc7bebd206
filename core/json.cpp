#include "core/json.h"

#include <cmath>
#include <cstdio>

namespace rosy {

std::string jsonQuote(const std::string &s) {
    std::string out = "\"";
    for (unsigned char c : s) {
        switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\r': out += "\\r"; break;
        case '\t': out += "\\t"; break;
        default:
            if (c < 0x20) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\u%04x", c);
                out += buf;
            } else {
                out += char(c);
            }
        }
    }
    return out + "\"";
}

void JsonWriter::indent() {
    m_out += "\n";
    m_out.append(2 * m_first.size(), ' ');
}

void JsonWriter::separator() {
    if (m_afterKey) {
        m_afterKey = false;
        return;
    }
    if (!m_first.empty()) {
        if (!m_first.back()) m_out += ",";
        m_first.back() = false;
        indent();
    }
}

JsonWriter &JsonWriter::beginObject() {
    separator();
    m_out += "{";
    m_first.push_back(true);
    return *this;
}

JsonWriter &JsonWriter::endObject() {
    bool empty = m_first.back();
    m_first.pop_back();
    if (!empty) indent();
    m_out += "}";
    return *this;
}

JsonWriter &JsonWriter::beginArray() {
    separator();
    m_out += "[";
    m_first.push_back(true);
    return *this;
}

JsonWriter &JsonWriter::endArray() {
    bool empty = m_first.back();
    m_first.pop_back();
    if (!empty) indent();
    m_out += "]";
    return *this;
}

JsonWriter &JsonWriter::key(const std::string &k) {
    separator();
    m_out += jsonQuote(k) + ": ";
    m_afterKey = true;
    return *this;
}

JsonWriter &JsonWriter::value(const std::string &s) {
    separator();
    m_out += jsonQuote(s);
    return *this;
}

JsonWriter &JsonWriter::value(double x) {
    separator();
    if (!std::isfinite(x)) {
        m_out += "null";
        return *this;
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", x == 0 ? 0.0 : x); // no "-0"
    m_out += buf;
    return *this;
}

JsonWriter &JsonWriter::value(long long x) {
    separator();
    m_out += std::to_string(x);
    return *this;
}

JsonWriter &JsonWriter::value(bool b) {
    separator();
    m_out += b ? "true" : "false";
    return *this;
}

JsonWriter &JsonWriter::null() {
    separator();
    m_out += "null";
    return *this;
}

} // namespace rosy
