#pragma once
/// \file json.h
/// A small streaming JSON writer for reports and timings. Output is
/// deterministic: keys in the order written, numbers with a fixed format
/// (integers exactly, reals with up to 9 significant digits), non-finite reals
/// written as null (JSON has no NaN).

#include <string>
#include <vector>

namespace rosy {

class JsonWriter {
public:
    JsonWriter &beginObject();
    JsonWriter &endObject();
    JsonWriter &beginArray();
    JsonWriter &endArray();
    /// Next member's key (inside an object).
    JsonWriter &key(const std::string &k);
    JsonWriter &value(const std::string &s);
    JsonWriter &value(const char *s) { return value(std::string(s)); }
    JsonWriter &value(double x);
    JsonWriter &value(int x) { return value(static_cast<long long>(x)); }
    JsonWriter &value(long long x);
    JsonWriter &value(bool b);
    JsonWriter &null();
    /// Shorthand for key(k).value(v).
    template <typename T> JsonWriter &field(const std::string &k, const T &v) { return key(k).value(v); }

    /// The document so far (complete once every scope is closed), ending in a newline.
    std::string str() const { return m_out + "\n"; }

private:
    void separator();
    void indent();
    std::string m_out;
    std::vector<bool> m_first; // per open scope: no element written yet
    bool m_afterKey = false;
};

/// JSON string escaping (quotes included).
std::string jsonQuote(const std::string &s);

} // namespace rosy
