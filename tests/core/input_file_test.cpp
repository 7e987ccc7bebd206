// core/input_file.h: bounded whole-file reads. The limit is inclusive; what is
// refused and with which error kind (InputError: exit 2, IoError: exit 3) follows
// the header.

#include "core/error.h"
#include "core/input_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <sys/stat.h>

#include "tests/test_output.h"

namespace fs = std::filesystem;
using namespace rosy;

namespace {
fs::path freshDir() { return rosy::test::testOutputDir("input_file", /*perTest=*/true, /*fresh=*/true); }

std::string messageOf(const std::string &path, const InputFileRules &rules) {
    try {
        readInputFile(path, rules);
    } catch (const std::exception &e) {
        return e.what();
    }
    return "no error";
}
} // namespace

TEST(ReadInputFile, ReturnsTheBytesUpToAndIncludingTheLimit) {
    const fs::path dir = freshDir();
    const InputFileRules rules{"scene file", 10, false};
    const std::string exact("0123456789", 10), binary("a\0b\r\n\xff", 6);
    std::ofstream(dir / "exact.yaml", std::ios::binary) << exact;
    std::ofstream(dir / "binary.yaml", std::ios::binary).write(binary.data(), std::streamsize(binary.size()));
    std::ofstream(dir / "empty.yaml", std::ios::binary);
    std::ofstream(dir / "over.yaml", std::ios::binary) << exact << "x";
    EXPECT_EQ(readInputFile((dir / "exact.yaml").string(), rules), exact);
    EXPECT_EQ(readInputFile((dir / "binary.yaml").string(), rules), binary);
    EXPECT_EQ(readInputFile((dir / "empty.yaml").string(), rules), "");
    try {
        readInputFile((dir / "over.yaml").string(), rules);
        ADD_FAILURE() << "11 bytes accepted under a limit of 10";
    } catch (const InputError &e) {
        EXPECT_EQ(e.loc().path, (dir / "over.yaml").string());
        EXPECT_EQ(e.message(), "the scene file is larger than the limit of 10 bytes"); // a regular file: no stream hint
    }
    // Links are followed.
    fs::create_symlink("exact.yaml", dir / "link.yaml");
    EXPECT_EQ(readInputFile((dir / "link.yaml").string(), rules), exact);
}

TEST(ReadInputFile, MissingFoldersAndPipesAreIoErrorsNamingTheFile) {
    const fs::path dir = freshDir();
    const InputFileRules mesh{"mesh file", 1 << 20, false};
    const std::string missing = (dir / "missing.off").string();
    EXPECT_EQ(messageOf(missing, mesh), missing + ": error: no such file");
    EXPECT_THROW(readInputFile(missing, mesh), IoError);
    fs::create_directories(dir / "folder.off");
    EXPECT_EQ(messageOf((dir / "folder.off").string(), mesh), (dir / "folder.off").string() + ": error: is a folder, not a mesh file");
    // A pipe is refused when the rules want a regular file (no blocking open: stat decides).
    const fs::path fifo = dir / "pipe.off";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_EQ(messageOf(fifo.string(), mesh),
              fifo.string() + ": error: is a pipe, not a regular file; the mesh file must be a file on disk");
    EXPECT_THROW(readInputFile(fifo.string(), mesh), IoError);
}
