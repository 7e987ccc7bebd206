// core/error.h: the error contract (README, "Exit codes"): locations, the one-line
// diagnostic format and the always-on checks. Expected strings follow the header's
// documented format, written out by hand.

#include "core/error.h"

#include <gtest/gtest.h>

#include <string>

using namespace rosy;

TEST(FileLoc, PrintsTheKnownPartsOnly) {
    EXPECT_EQ((FileLoc{"scene.yaml", 12, 7}).str(), "scene.yaml:12:7");
    EXPECT_EQ((FileLoc{"scene.yaml", 12, 0}).str(), "scene.yaml:12");
    EXPECT_EQ((FileLoc{"scene.yaml", 0, 7}).str(), "scene.yaml"); // a column without a line means nothing
    EXPECT_EQ((FileLoc{"scene.yaml"}).str(), "scene.yaml");
    EXPECT_EQ((FileLoc{}).str(), "<input>");
}

TEST(InputError, IsOneLineWithLocationMessageAndHint) {
    const InputError e(FileLoc{"s.yaml", 3, 5}, "unknown key 'colour'", "did you mean 'color'?");
    EXPECT_STREQ(e.what(), "s.yaml:3:5: error: unknown key 'colour'; did you mean 'color'?");
    EXPECT_EQ(e.loc().line, 3);
    EXPECT_EQ(e.loc().col, 5);
    EXPECT_EQ(e.message(), "unknown key 'colour'"); // the raw message, without location or hint
    const InputError noHint(FileLoc{"m.off"}, "no faces");
    EXPECT_STREQ(noHint.what(), "m.off: error: no faces");
    // A newline in the message cannot start a second line.
    const InputError twoLines(FileLoc{"a", 1, 1}, "x\ny", "p\nq");
    EXPECT_STREQ(twoLines.what(), "a:1:1: error: x\\ny; p\\nq");
    EXPECT_EQ(std::string(twoLines.what()).find('\n'), std::string::npos);
}

TEST(IoError, NamesThePathAndKeepsMultiLineMessages) {
    const IoError e("out/x.png", "cannot write\nsecond line\x1b");
    EXPECT_STREQ(e.what(), "out/x.png: error: cannot write\nsecond line\\x1b");
    EXPECT_EQ(e.path(), "out/x.png");
    // The two kinds the CLI maps to exit codes 2 and 3 are distinct types.
    bool caughtAsInput = false;
    try {
        throw IoError("p", "m");
    } catch (const InputError &) {
        caughtAsInput = true;
    } catch (const IoError &) {
    }
    EXPECT_FALSE(caughtAsInput);
}

TEST(Check, FailureNamesTheExpressionBothValuesAndIsALogicError) {
    const int nFaces = 4;
    try {
        ROSY_CHECK_EQ(nFaces, 2 + 3);
        FAIL() << "no throw";
    } catch (const CheckFailure &e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("error_test.cpp:"), std::string::npos) << what;
        EXPECT_NE(what.find("internal check failed: nFaces == 2 + 3 with values 4 and 5"), std::string::npos) << what;
        EXPECT_NE(what.find("this is a bug in rosyhatch"), std::string::npos) << what;
    }
    try {
        ROSY_CHECK(nFaces < 0);
        FAIL() << "no throw";
    } catch (const std::logic_error &e) { // CheckFailure is a logic_error: exit code 1
        EXPECT_NE(std::string(e.what()).find("internal check failed: nFaces < 0 ("), std::string::npos) << e.what();
    }
    // Passing checks do nothing, and each operand is evaluated once.
    int calls = 0;
    auto next = [&] { return ++calls; };
    EXPECT_NO_THROW(ROSY_CHECK_LT(next(), 2));
    EXPECT_NO_THROW(ROSY_CHECK_LE(2, 2));
    EXPECT_NO_THROW(ROSY_CHECK_GE(3, 2));
    EXPECT_EQ(calls, 1);
    EXPECT_THROW(ROSY_CHECK_GE(1, 2), CheckFailure);
    EXPECT_THROW(ROSY_CHECK_LT(2, 2), CheckFailure);
}
