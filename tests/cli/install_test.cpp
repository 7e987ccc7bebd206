// The command line as a user meets it: `rosyhatch help`, -V, suggestions for
// misspelt commands and options, help text that matches the files written, and
// `cmake --install` into a fresh prefix with the installed program run from
// there (its module and presets found beside it, the man page valid roff, the
// bash completion completing).

#include "cli_util.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

fs::path workDir() { return rosy::test::testOutputDir("install-cli"); }

using rosy::test::CliRun;
using rosy::test::slurp;

CliRun run(const std::string &args, const std::string &tag) { return rosy::test::runRosyhatch(workDir(), args, tag); }

bool contains(const std::string &s, const std::string &what) { return s.find(what) != std::string::npos; }

/// Runs a shell command in workDir(); exit code and stdout + stderr together.
std::pair<int, std::string> shell(const std::string &cmd, const std::string &tag) {
    const fs::path out = workDir() / (tag + ".log");
    const std::string full = "cd '" + workDir().string() + "' && (" + cmd + ") >'" + out.string() + "' 2>&1";
    const int status = std::system(full.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out)};
}

} // namespace

TEST(CommandLine, HelpVersionAndSuggestions) {
    const CliRun help = run("help", "help");
    EXPECT_EQ(help.exitCode, 0);
    for (const char *cmd : {"render", "field", "inspect", "styles", "diff", "compare", "help"})
        EXPECT_TRUE(contains(help.out, cmd)) << cmd;
    const CliRun helpDiff = run("help diff", "help-diff");
    EXPECT_EQ(helpDiff.exitCode, 0);
    EXPECT_TRUE(contains(helpDiff.out, "rosyhatch diff")) << helpDiff.out;
    EXPECT_TRUE(contains(helpDiff.out, "--warnpercent")) << helpDiff.out;

    const CliRun v = run("-V", "V");
    EXPECT_EQ(v.exitCode, 0);
    EXPECT_EQ(v.out.rfind("rosyhatch ", 0), 0u) << v.out;
    EXPECT_TRUE(contains(v.out, "image I/O module: ")) << v.out;

    const CliRun none = run("", "none");
    EXPECT_EQ(none.exitCode, 2);
    EXPECT_TRUE(contains(none.err, "render")) << none.err; // the list of commands, not only "required"
    const CliRun typo = run("rendr x.yaml", "typo");
    EXPECT_EQ(typo.exitCode, 2);
    EXPECT_TRUE(contains(typo.err, "unknown command 'rendr'; did you mean 'render'?")) << typo.err;
    const CliRun far = run("paint x.yaml", "far");
    EXPECT_EQ(far.exitCode, 2);
    EXPECT_TRUE(contains(far.err, "unknown command 'paint'")) << far.err;
    EXPECT_FALSE(contains(far.err, "did you mean")) << far.err; // nothing close: no guess
    const CliRun helpTypo = run("help dif", "help-typo");
    EXPECT_EQ(helpTypo.exitCode, 2);
    EXPECT_TRUE(contains(helpTypo.err, "did you mean 'diff'?")) << helpTypo.err;

    const CliRun option = run("render x.yaml --thread 2", "option");
    EXPECT_EQ(option.exitCode, 2);
    EXPECT_TRUE(contains(option.err, "unknown option '--thread'; did you mean '--threads'?")) << option.err;
    const CliRun idiffTypo = run("diff a.png b.png -fial 0.1", "option-idiff");
    EXPECT_EQ(idiffTypo.exitCode, 2);
    EXPECT_TRUE(contains(idiffTypo.err, "unknown option '-fial'; did you mean '--fail'?")) << idiffTypo.err;
    // Another command's option is no suggestion for this one.
    const CliRun other = run("styles --symetry 2", "option-other");
    EXPECT_EQ(other.exitCode, 2);
    EXPECT_FALSE(contains(other.err, "--symmetry")) << other.err;
}

TEST(CommandLine, TimingsHelpSaysMillisecondsAsTheFileHolds) {
    const CliRun help = run("render --help", "render-help");
    EXPECT_TRUE(contains(help.out, "milliseconds")) << help.out;
    EXPECT_FALSE(contains(help.out, "seconds as JSON")) << help.out;
    std::ofstream(workDir() / "t.yaml") << "mesh: {primitive: icosphere, subdivisions: 1}\ncamera: {resolution: [32, 24]}\n";
    ASSERT_EQ(run("render t.yaml -o t.svg --timings t.json -q", "timings").exitCode, 0);
    const nlohmann::json t = nlohmann::json::parse(slurp(workDir() / "t.json"));
    // The whole command takes well over a millisecond and well under 1000 s: a value
    // in seconds would be below 1 for this tiny scene only if it were not milliseconds.
    EXPECT_GT(t.at("total").get<double>(), 1.0);
}

TEST(CommandLine, CmakeInstallGivesAWorkingProgram) {
    const fs::path prefix = workDir() / "prefix";
    fs::remove_all(prefix);
    const auto [code, log] = shell("'" + std::string(ROSY_CMAKE_COMMAND) + "' --install '" + ROSY_BINARY_DIR +
                                       "' --prefix '" + prefix.string() + "'",
                                   "install");
    ASSERT_EQ(code, 0) << log;
    const fs::path bin = prefix / "bin" / "rosyhatch";
    for (const fs::path &p : {bin, prefix / "lib/rosyhatch/librosy_image_io.so",
                              prefix / "share/rosyhatch/styles/fine-pen.yaml", prefix / "share/man/man1/rosyhatch.1",
                              prefix / "share/bash-completion/completions/rosyhatch",
                              prefix / "share/rosyhatch/studio/index.html", prefix / "share/rosyhatch/studio/app.js"})
        EXPECT_TRUE(fs::exists(p)) << p;

    // The installed program finds its module and presets beside it.
    const auto [vcode, version] = shell("'" + bin.string() + "' -V", "installed-version");
    EXPECT_EQ(vcode, 0) << version;
    EXPECT_TRUE(contains(version, "image I/O module: " + (prefix / "lib/rosyhatch/librosy_image_io.so").string()))
        << version;
    EXPECT_TRUE(contains(version, (prefix / "share/rosyhatch/styles").string())) << version;
    // ... and the studio's page (ROSY_STUDIO_WEB_DIR unset: the installed copy, not the source tree's).
    const auto [scode, sversion] = shell("ROSY_STUDIO_WEB_DIR= '" + bin.string() + "' -V", "installed-version-studio");
    EXPECT_EQ(scode, 0) << sversion;
    EXPECT_TRUE(contains(sversion, "studio page: " + (prefix / "share/rosyhatch/studio").string())) << sversion;
    std::ofstream(workDir() / "i.yaml") << "mesh: {primitive: icosphere, subdivisions: 1}\n"
                                           "camera: {resolution: [32, 24]}\nstyle: {preset: engraving}\n";
    fs::remove(workDir() / "i.png");
    const auto [rcode, rlog] =
        shell("ROSY_STYLES_PATH= '" + bin.string() + "' render i.yaml -o i.png -q", "installed-render");
    EXPECT_EQ(rcode, 0) << rlog;
    EXPECT_GT(fs::file_size(workDir() / "i.png"), 8u);

    // The man page is roff that groff reads without a warning, and documents the options.
    const std::string man = slurp(prefix / "share/man/man1/rosyhatch.1");
    EXPECT_EQ(man.rfind(".TH ROSYHATCH 1", 0), 0u);
    for (const char *what : {"rosyhatch render", "rosyhatch diff", "\\-\\-timings", "\\-\\-warnpercent", "EXIT STATUS"})
        EXPECT_TRUE(contains(man, what)) << what;
    if (std::system("command -v groff >/dev/null 2>&1") == 0) {
        const auto [gcode, glog] = shell("groff -man -Tutf8 -ww -z '" + (prefix / "share/man/man1/rosyhatch.1").string() + "'",
                                         "groff");
        EXPECT_EQ(gcode, 0) << glog;
        EXPECT_EQ(glog, "") << glog;
    }

    // The completion completes commands and a command's options.
    const std::string completion = (prefix / "share/bash-completion/completions/rosyhatch").string();
    auto complete = [&](const std::string &words, int cword, const std::string &tag) {
        return shell("bash -c 'source \"" + completion + "\"; COMP_WORDS=(" + words + "); COMP_CWORD=" +
                         std::to_string(cword) + "; _rosyhatch; printf \"%s\\n\" \"${COMPREPLY[@]}\"'",
                     tag)
            .second;
    };
    EXPECT_EQ(complete("rosyhatch ren", 1, "complete-command"), "render\n");
    EXPECT_EQ(complete("rosyhatch render x.yaml --thr", 3, "complete-option"), "--threads\n");
    EXPECT_EQ(complete("rosyhatch diff -q --warnp", 3, "complete-diff"), "--warnpercent\n");
}
