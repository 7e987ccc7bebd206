// core/json.h: the report writer. Expected documents are written out by hand from
// the header's contract (keys in order, two-space indentation, integers exact, reals
// with 9 significant digits, non-finite as null, no "-0"), and every document is
// also read back by a real JSON parser (nlohmann-json), so a syntax slip fails even
// where the text comparison would not look.

#include "core/json.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>
#include <string>

using namespace rosy;
using nlohmann::json;

TEST(JsonWriter, NestedDocumentHasTheDocumentedLayout) {
    JsonWriter w;
    w.beginObject()
        .field("name", "bunny")
        .field("faces", 75408)
        .field("ok", true)
        .key("position")
        .beginArray()
        .value(1)
        .value(2.5)
        .value(-3)
        .endArray()
        .key("none")
        .null()
        .endObject();
    EXPECT_EQ(w.str(), "{\n"
                       "  \"name\": \"bunny\",\n"
                       "  \"faces\": 75408,\n"
                       "  \"ok\": true,\n"
                       "  \"position\": [\n"
                       "    1,\n"
                       "    2.5,\n"
                       "    -3\n"
                       "  ],\n"
                       "  \"none\": null\n"
                       "}\n");
    const json doc = json::parse(w.str());
    EXPECT_EQ(doc["name"], "bunny");
    EXPECT_EQ(doc["faces"], 75408);
    EXPECT_EQ(doc["position"][1], 2.5);
    EXPECT_TRUE(doc["none"].is_null());
    // Keys keep the order written (nlohmann's ordered_json keeps insertion order).
    const nlohmann::ordered_json ordered = nlohmann::ordered_json::parse(w.str());
    std::string keys;
    for (const auto &item : ordered.items()) keys += item.key() + " ";
    EXPECT_EQ(keys, "name faces ok position none ");
}

TEST(JsonWriter, EmptyScopesStayOnOneLine) {
    JsonWriter w;
    w.beginObject().key("a").beginArray().endArray().key("o").beginObject().endObject().endObject();
    EXPECT_EQ(w.str(), "{\n  \"a\": [],\n  \"o\": {}\n}\n");
    EXPECT_TRUE(json::parse(w.str())["a"].empty());
}

TEST(JsonWriter, RealsUseNineSignificantDigitsAndNonFiniteIsNull) {
    auto one = [](double x) {
        JsonWriter w;
        w.beginArray().value(x).endArray();
        const std::string s = w.str();
        // "[\n  X\n]\n": the value alone.
        return s.substr(4, s.size() - 4 - 3);
    };
    EXPECT_EQ(one(0.1), "0.1");
    EXPECT_EQ(one(1.0 / 3.0), "0.333333333");
    EXPECT_EQ(one(2.0 / 3.0), "0.666666667");
    EXPECT_EQ(one(123456789012.0), "1.23456789e+11");
    EXPECT_EQ(one(1e-9), "1e-09");
    EXPECT_EQ(one(-0.0), "0"); // no "-0"
    EXPECT_EQ(one(std::numeric_limits<double>::quiet_NaN()), "null");
    EXPECT_EQ(one(std::numeric_limits<double>::infinity()), "null");
    EXPECT_EQ(one(-std::numeric_limits<double>::infinity()), "null");
    // Integers are exact whatever their size.
    JsonWriter w;
    w.beginArray().value(9007199254740993LL).value(std::numeric_limits<long long>::min()).endArray();
    const json doc = json::parse(w.str());
    EXPECT_EQ(doc[0].get<long long>(), 9007199254740993LL);
    EXPECT_EQ(doc[1].get<long long>(), std::numeric_limits<long long>::min());
}

TEST(JsonQuote, EscapesWhatJsonRequiresAndKeepsUtf8) {
    EXPECT_EQ(jsonQuote("plain"), "\"plain\"");
    EXPECT_EQ(jsonQuote("say \"hi\""), "\"say \\\"hi\\\"\"");
    EXPECT_EQ(jsonQuote("C:\\dir"), "\"C:\\\\dir\"");
    EXPECT_EQ(jsonQuote("a\nb\tc\rd"), "\"a\\nb\\tc\\rd\"");
    EXPECT_EQ(jsonQuote(std::string("\x01\x1f", 2)), "\"\\u0001\\u001f\"");
    EXPECT_EQ(jsonQuote(std::string("nul\0x", 5)), "\"nul\\u0000x\"");
    EXPECT_EQ(jsonQuote("caf\xc3\xa9"), "\"caf\xc3\xa9\"");
    // Every byte below 0x20 and the two specials, read back by a real parser.
    std::string all;
    for (int c = 1; c < 0x80; ++c) all += char(c);
    EXPECT_EQ(json::parse(jsonQuote(all)).get<std::string>(), all);
}
