// End-to-end tests of issue 16 ("Reliability II"): what the real executable does
// with hostile or careless output paths, endless inputs, resource bombs and
// extreme numbers. Each test names the catalogue row it covers (tests/README.md,
// "Outputs", "Resource limits", "Numbers at the edge of their ranges").
// Device nodes are scratch copies made with mknod in the test's folder (root only;
// those parts skip otherwise); /dev itself is only ever read (/dev/zero).
// ROSY_CLI_UNDER_TEST=PATH runs the tests against another rosyhatch binary (to
// check that they fail on a build without the fixes).

#include "cli_util.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

namespace fs = std::filesystem;

namespace {

std::string binary() {
    if (const char *env = std::getenv("ROSY_CLI_UNDER_TEST"); env && *env) return env;
    return std::string(ROSY_BINARY_DIR) + "/cli/rosyhatch";
}

fs::path workDir() { return rosy::test::testOutputDir("reliability", true, true); }

using rosy::test::slurp;

using rosy::test::put;

struct CliRun {
    int exitCode;
    std::string out, err;
    double seconds;
};

/// Runs `prefix rosyhatch args` through /bin/sh in `dir`, under `timeout 120` so a
/// hang fails the test (exit 124) instead of stalling the suite.
CliRun run(const fs::path &dir, const std::string &args, const std::string &prefix = "") {
    const fs::path out = dir / "run.stdout", err = dir / "run.stderr";
    const std::string cmd = "cd '" + dir.string() + "' && (" + prefix + " timeout -k 5 120 '" + binary() + "' " +
                            args + ") >'" + out.string() + "' 2>'" + err.string() + "'";
    const auto t0 = std::chrono::steady_clock::now();
    const int status = std::system(cmd.c_str());
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    return {code, slurp(out), slurp(err), s};
}

/// Our temporaries in `dir` (the old naming `.x.tmpPID-N.ext` included).
std::vector<std::string> temporaries(const fs::path &dir) {
    std::vector<std::string> names;
    for (const auto &e : fs::directory_iterator(dir)) {
        const std::string n = e.path().filename().string();
        if (n.rfind(".rosyhatch-", 0) == 0 || n.find(".tmp") != std::string::npos) names.push_back(n);
    }
    return names;
}

bool contains(const std::string &s, const std::string &what) { return s.find(what) != std::string::npos; }

bool isCharDevice(const fs::path &p) {
    struct stat st {};
    return ::lstat(p.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

const std::string kTriangleOff = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
const std::string kTorusScene = "mesh: {primitive: torus}\ncamera: {resolution: [32, 32]}\n";

/// A PNG header claiming width x height 8-bit grey pixels, followed by four rows.
std::string pngBomb(uint32_t width, uint32_t height) {
    auto be = [](uint32_t v) {
        return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    };
    auto chunk = [&](const std::string &type, const std::string &data) {
        std::string body = type + data;
        const uLong crc = crc32(0L, reinterpret_cast<const Bytef *>(body.data()), uInt(body.size()));
        return be(uint32_t(data.size())) + body + be(uint32_t(crc));
    };
    const std::string ihdr = be(width) + be(height) + std::string{8, 0, 0, 0, 0};
    const std::string raw(size_t(width + 1) * 4, '\0');
    std::string packed(compressBound(uLong(raw.size())), '\0');
    uLongf packedSize = uLongf(packed.size());
    compress2(reinterpret_cast<Bytef *>(packed.data()), &packedSize, reinterpret_cast<const Bytef *>(raw.data()),
              uLong(raw.size()), 9);
    packed.resize(packedSize);
    return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", packed) + chunk("IEND", "");
}

/// An OpenEXR header with a size x size data window and the channels `inspect`
/// reads, every chunk pointing at one small ZIP block: about 30 KB on disk.
std::string exrBomb(int size) {
    auto i32 = [](int32_t v) { return std::string(reinterpret_cast<const char *>(&v), 4); };
    auto f32 = [](float v) { return std::string(reinterpret_cast<const char *>(&v), 4); };
    auto attr = [&](const std::string &name, const std::string &type, const std::string &data) {
        return name + '\0' + type + '\0' + i32(int32_t(data.size())) + data;
    };
    const char *names[] = {"field.angle0", "field.angle1", "ink.coverage", "ink.hatch0", "ink.hatch1", "mask",
                           "tone.target"}; // sorted, as the format requires
    std::string channels;
    for (const char *n : names) channels += std::string(n) + '\0' + i32(1) + std::string(4, '\0') + i32(1) + i32(1);
    channels += '\0';
    const std::string box = i32(0) + i32(0) + i32(size - 1) + i32(size - 1);
    std::string header = std::string("\x76\x2f\x31\x01", 4) + i32(2);
    header += attr("channels", "chlist", channels) + attr("compression", "compression", std::string(1, '\3'));
    header += attr("dataWindow", "box2i", box) + attr("displayWindow", "box2i", box);
    header += attr("lineOrder", "lineOrder", std::string(1, '\0')) + attr("pixelAspectRatio", "float", f32(1));
    header += attr("screenWindowCenter", "v2f", f32(0) + f32(0)) + attr("screenWindowWidth", "float", f32(1));
    header += '\0';
    const int chunks = (size + 15) / 16;
    const uint64_t dataAt = header.size() + 8 * uint64_t(chunks);
    std::string table;
    for (int c = 0; c < chunks; ++c) table += std::string(reinterpret_cast<const char *>(&dataAt), 8);
    const std::string raw(size_t(size) * 2 * 7 * 16, '\0');
    std::string packed(compressBound(uLong(raw.size())), '\0');
    uLongf packedSize = uLongf(packed.size());
    compress2(reinterpret_cast<Bytef *>(packed.data()), &packedSize, reinterpret_cast<const Bytef *>(raw.data()),
              uLong(raw.size()), 9);
    packed.resize(packedSize);
    return header + table + i32(0) + i32(int32_t(packed.size())) + packed;
}

} // namespace

// ---------------------------------------------------------------------------
// Outputs
// ---------------------------------------------------------------------------

TEST(ReliabilityCli, DevicesAndPipesAreWrittenInPlaceNeverReplaced) {
    const fs::path dir = workDir();
    put(dir / "tri.off", kTriangleOff);
    put(dir / "s.yaml", kTorusScene);
    // A descriptor alias: through the descriptor, after what the command printed
    // itself. (/dev/fd/1 rather than /dev/stdout, the same code path: a build that
    // replaces outputs would, as root, turn the machine's /dev/stdout into a file;
    // /dev/fd is /proc/self/fd, where no file can be created.)
    CliRun r = run(dir, "field tri.off --json /dev/fd/1 -q");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "\"poincare_hopf\"")) << r.out;
    // A named pipe: written in place, still a pipe afterwards.
    ASSERT_EQ(::mkfifo((dir / "pipe.json").c_str(), 0600), 0);
    r = run(dir, "field tri.off --json pipe.json -q", "(cat pipe.json > got.json &);");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    for (int i = 0; i < 100 && !contains(slurp(dir / "got.json"), "}"); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_TRUE(contains(slurp(dir / "got.json"), "\"poincare_hopf\""));
    struct stat st {};
    ASSERT_EQ(::lstat((dir / "pipe.json").c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode));
    if (::geteuid() != 0 || ::mknod((dir / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0 ||
        ::mknod((dir / "full").c_str(), S_IFCHR | 0666, makedev(1, 7)) != 0)
        GTEST_SKIP() << "device part needs root (scratch mknod copies of /dev/null and /dev/full)";
    // Before: exit 0 and `null` became a regular file holding the JSON.
    r = run(dir, "field tri.off --json null -q");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(isCharDevice(dir / "null"));
    for (const std::string flag : {"--report", "--timings"}) {
        SCOPED_TRACE(flag);
        fs::remove(dir / "x.png");
        r = run(dir, "render s.yaml -o x.png -q " + flag + " full");
        EXPECT_EQ(r.exitCode, 3) << r.err;
        EXPECT_TRUE(contains(r.err, "full: error: write failed: No space left on device")) << r.err;
        EXPECT_TRUE(isCharDevice(dir / "full"));
        EXPECT_FALSE(fs::exists(dir / "x.png")); // the device failed first: nothing published
    }
    EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
}

TEST(ReliabilityCli, LongOutputNamesWorkAndTooLongOnesFailBeforeRendering) {
    const fs::path dir = workDir();
    put(dir / "s.yaml", kTorusScene);
    // 250 bytes: legal; the old temporary (name + ~20 bytes) exceeded NAME_MAX and the
    // run failed with exit 3 after the whole render.
    const std::string name = std::string(246, 'n') + ".png";
    CliRun r = run(dir, "render s.yaml -q -o " + name);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / name));
    const std::string tooLong = std::string(252, 'n') + ".png";
    r = run(dir, "render s.yaml -q --timings t.json -o " + tooLong);
    EXPECT_EQ(r.exitCode, 3) << r.err;
    EXPECT_TRUE(contains(r.err, "more than the file system's limit of 255")) << r.err;
    EXPECT_FALSE(fs::exists(dir / "t.json")); // refused before any work
    EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
}

TEST(ReliabilityCli, DiffAndInspectRefuseToOverwriteTheirInputs) {
    const fs::path dir = workDir();
    put(dir / "s.yaml", kTorusScene);
    ASSERT_EQ(run(dir, "render s.yaml -o a.exr -o a.png -o b.png -q").exitCode, 0);
    const std::string png = slurp(dir / "a.png"), exr = slurp(dir / "a.exr");
    CliRun r = run(dir, "diff a.png b.png -o a.png -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "the output would overwrite the reference image")) << r.err;
    r = run(dir, "diff a.png b.png -o ./b.png -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(slurp(dir / "a.png"), png);
    r = run(dir, "inspect a.exr --json a.exr");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "the output would overwrite the rendering")) << r.err;
    EXPECT_EQ(slurp(dir / "a.exr"), exr);
    EXPECT_TRUE(r.out.empty()) << r.out; // refused before measuring
}

// SIGINT and SIGTERM while an output is being written used to leave the hidden
// temporary behind. The render is stopped at a deterministic point: its --report
// is a FIFO nobody reads, so the run blocks in publishing, with the PNG's
// temporary complete in the folder.
TEST(ReliabilityCli, SignalsDuringTheWriteRemoveTemporaries) {
    for (const int sig : {SIGINT, SIGTERM}) {
        SCOPED_TRACE(sig);
        const fs::path dir = workDir();
        put(dir / "s.yaml", kTorusScene);
        put(dir / "out.png", "previous");
        ASSERT_EQ(::mkfifo((dir / "report.json").c_str(), 0600), 0);
        const std::string exe = binary();
        const pid_t pid = ::fork();
        if (pid == 0) {
            if (::chdir(dir.c_str()) != 0) ::_exit(100);
            const int devnull = ::open("/dev/null", O_WRONLY);
            ::dup2(devnull, 1);
            ::dup2(devnull, 2);
            std::signal(SIGINT, SIG_DFL); // as in an interactive shell, whatever ours inherited
            std::signal(SIGTERM, SIG_DFL);
            ::execl(exe.c_str(), exe.c_str(), "render", "s.yaml", "-o", "out.png", "--report", "report.json", "-q",
                    static_cast<char *>(nullptr));
            ::_exit(101);
        }
        bool sawTemporary = false;
        for (int i = 0; i < 600 && !sawTemporary; ++i) {
            sawTemporary = !temporaries(dir).empty();
            if (!sawTemporary) std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        EXPECT_TRUE(sawTemporary) << "the render never reached its write";
        ::kill(pid, sig);
        int status = 0;
        ::waitpid(pid, &status, 0);
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << "wait status " << status;
        EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
        EXPECT_EQ(slurp(dir / "out.png"), "previous");
    }
}

// A multi-output run that fails on its second file used to have replaced the first.
TEST(ReliabilityCli, MultiOutputRunPublishesEveryFileOrNone) {
    const fs::path dir = workDir();
    put(dir / "s.yaml", kTorusScene);
    put(dir / "a.svg", "old svg");
    put(dir / "b.exr", "old exr");
    // The 32² SVG is about 1.5 KB and the EXR about 21 KB: a 5-10 KiB file size limit
    // (ulimit -f 10: 512-byte blocks in dash, 1 KiB in bash) lets the SVG through.
    CliRun r = run(dir, "render s.yaml -o a.svg -o b.exr -q", "ulimit -f 10;");
    EXPECT_EQ(r.exitCode, 3) << r.err;
    EXPECT_TRUE(contains(r.err, "b.exr: error: ")) << r.err;
    EXPECT_EQ(slurp(dir / "a.svg"), "old svg");
    EXPECT_EQ(slurp(dir / "b.exr"), "old exr");
    EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
    r = run(dir, "render s.yaml -o a.svg -o b.exr -q");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(slurp(dir / "a.svg"), "old svg");
    EXPECT_NE(slurp(dir / "b.exr"), "old exr");
}

TEST(ReliabilityCli, ReRenderingKeepsTheOutputsMode) {
    const fs::path dir = workDir();
    put(dir / "s.yaml", kTorusScene);
    put(dir / "out.png", "x");
    put(dir / "field.json", "x");
    ASSERT_EQ(::chmod((dir / "out.png").c_str(), 0600), 0);
    ASSERT_EQ(::chmod((dir / "field.json").c_str(), 0640), 0);
    ASSERT_EQ(run(dir, "render s.yaml -o out.png -q").exitCode, 0);
    ASSERT_EQ(run(dir, "field s.yaml --json field.json -q").exitCode, 0);
    struct stat st {};
    ASSERT_EQ(::stat((dir / "out.png").c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600u); // was 0644
    ASSERT_EQ(::stat((dir / "field.json").c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0640u);
}

// ---------------------------------------------------------------------------
// Resource limits
// ---------------------------------------------------------------------------

TEST(ReliabilityCli, EndlessAndNonRegularInputsEndQuicklyWithAClearError) {
    const fs::path dir = workDir();
    fs::create_symlink("/dev/zero", dir / "z.off");
    CliRun r = run(dir, "field z.off -q");
    EXPECT_EQ(r.exitCode, 3) << r.err;
    EXPECT_TRUE(contains(r.err, "z.off: error: is a character device, not a regular file")) << r.err;
    put(dir / "zs.yaml", "mesh: z.off\n");
    r = run(dir, "render zs.yaml -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "zs.yaml:1:7: error: mesh '")) << r.err;
    r = run(dir, "render /dev/zero -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "/dev/zero: error: the scene file is larger than the limit of 4194304 bytes")) << r.err;
    r = run(dir, "render /dev/stdin -q", "yes |");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "/dev/stdin: error: the scene file is larger than the limit")) << r.err;
    // A scene on stdin still works.
    put(dir / "s.yaml", kTorusScene);
    r = run(dir, "render /dev/stdin -o piped.png -q", "cat s.yaml |");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    // A style preset found on ROSY_STYLES_PATH that is a link to /dev/zero.
    fs::create_directories(dir / "styles");
    fs::create_symlink("/dev/zero", dir / "styles" / "zero.yaml");
    put(dir / "p.yaml", kTorusScene + "style: {preset: zero}\n");
    r = run(dir, "render p.yaml -o p.png -q", "ROSY_STYLES_PATH=styles");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "zero.yaml: error: the style preset file is larger than the limit")) << r.err;
    for (const char *what : {"field", "render"}) EXPECT_LT(r.seconds, 30.0) << what;
}

TEST(ReliabilityCli, PrimitivesHonourTheFaceLimit) {
    const fs::path dir = workDir();
    put(dir / "big.yaml", "mesh: {primitive: torus, nu: 4096, nv: 4096}\n");
    CliRun r = run(dir, "render big.yaml -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "big.yaml:1:19: error: the torus primitive would have 33554432 faces, more than "
                                "the limit of 20000000"))
        << r.err;
    EXPECT_LT(r.seconds, 20.0);
    put(dir / "s.yaml", kTorusScene); // 64 x 32 x 2 = 4096 faces
    r = run(dir, "render s.yaml -o s.png -q --max-faces 1000");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "more than the limit of 1000")) << r.err;
    EXPECT_EQ(run(dir, "render s.yaml -o s.png -q --max-faces 4096").exitCode, 0);
    EXPECT_EQ(run(dir, "field s.yaml -q --max-faces 4095").exitCode, 2);
}

TEST(ReliabilityCli, SetValuesMeetTheSameLimitsAsTheFile) {
    const fs::path dir = workDir();
    put(dir / "s.yaml", kTorusScene);
    // Nine levels of nine aliases: 9^9 values once walked.
    std::string bomb = "{a0: &a0 [x, x, x, x, x, x, x, x, x]";
    for (int i = 1; i <= 9; ++i) {
        const std::string prev = "*a" + std::to_string(i - 1);
        bomb += ", a" + std::to_string(i) + ": &a" + std::to_string(i) + " [" + prev;
        for (int k = 1; k < 9; ++k) bomb += ", " + prev;
        bomb += "]";
    }
    bomb += "}";
    CliRun r = run(dir, "render s.yaml -q --set 'camera.fov=" + bomb + "'");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(r.err.rfind("--set camera.fov=", 0), 0u) << r.err;
    EXPECT_TRUE(contains(r.err, "error: the value expands to more than 10000 values")) << r.err;
    EXPECT_LT(r.seconds, 20.0);
    r = run(dir, "render s.yaml -q --set 'camera.fov=" + std::string(100, '[') + std::string(100, ']') + "'");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "error: nesting deeper than 32 levels")) << r.err;
    r = run(dir, "render s.yaml -q --set 'lights=&a [*a]'");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "an alias refers to a node that contains it")) << r.err;
}

TEST(ReliabilityCli, ImageBombsAreRefusedBeforeAllocating) {
    const fs::path dir = workDir();
    put(dir / "bomb.png", pngBomb(32000, 32000)); // about 200 bytes
    CliRun r = run(dir, "diff bomb.png bomb.png -q");
    EXPECT_EQ(r.exitCode, 4) << r.err; // diff: a file it cannot read is idiff's file error

    EXPECT_TRUE(contains(r.err, "bomb.png: error: the image is 32000 x 32000 pixels of 1 channel(s): more than the "
                                "limit of 16777216 pixels"))
        << r.err;
    EXPECT_TRUE(r.out.empty());
    put(dir / "bomb.exr", exrBomb(50000)); // about 30 KB, every channel inspect reads
    r = run(dir, "inspect bomb.exr");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "bomb.exr: error: the image is 50000 x 50000 pixels of 7 channel(s)")) << r.err;
    r = run(dir, "inspect bomb.png");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_LT(r.seconds, 20.0);
}

// A render the machine cannot hold is refused after the mesh is loaded, before the
// field, the G-buffer or the strokes (README, "Limits"). `ulimit -v` stands in for a
// small machine. ASan reserves terabytes of address space, so not under sanitizers.
TEST(ReliabilityCli, RenderThatCannotFitIsRefusedBeforeRendering) {
#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "ASan's shadow memory needs more address space than ulimit -v allows";
#endif
    const fs::path dir = workDir();
    put(dir / "dense.yaml", "mesh: {primitive: torus}\ncamera: {resolution: [4096, 4096]}\n"
                            "style: {hatch: {min_spacing_px: 0.5, max_spacing_px: 0.5, highlight_density: 0}}\n");
    CliRun r = run(dir, "render dense.yaml -o d.png -q", "ulimit -v 3000000;");
    EXPECT_EQ(r.exitCode, 3) << r.err;
    EXPECT_TRUE(contains(r.err, "dense.yaml: error: the render needs about 7.")) << r.err;
    EXPECT_TRUE(contains(r.err, "the address space limit (ulimit -v)")) << r.err;
    EXPECT_LT(r.seconds, 20.0);
    EXPECT_FALSE(fs::exists(dir / "d.png"));
    // The same limit holds a small render.
    put(dir / "small.yaml", kTorusScene);
    r = run(dir, "render small.yaml -o s.png -q", "ulimit -v 3000000;");
    EXPECT_EQ(r.exitCode, 0) << r.err;
}

// ---------------------------------------------------------------------------
// Numbers at the edge of their ranges, messages
// ---------------------------------------------------------------------------

TEST(ReliabilityCli, GlobalSmoothingNeverHatchesAZeroField) {
    const fs::path dir = workDir();
    put(dir / "ico.yaml", "mesh: {primitive: icosphere, subdivisions: 1}\nfield: {source: smoothest}\n"
                          "camera: {resolution: [32, 32]}\n");
    // 20,000 full-strength steps: the field shrank by the holonomy at every step and
    // reached exactly zero, so every face looked singular (exit 0, no warning).
    CliRun r = run(dir, "field ico.yaml --global-smoothing 20000:1 --json long.json -q");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    r = run(dir, "field ico.yaml --global-smoothing 20:1 --json short.json -q");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    // Read by a parser: the old text search stopped at the first ']' (the first
    // singularity's position), so it counted at most one singularity per side.
    auto count = [](const std::string &json) { return nlohmann::json::parse(json).at("singularities").size(); };
    const std::string longJson = slurp(dir / "long.json"), shortJson = slurp(dir / "short.json");
    EXPECT_EQ(count(longJson), count(shortJson)) << longJson;
    r = run(dir, "render ico.yaml -o ico.png -q --report rep.json --set field.global_smoothing.iterations=20000 "
                 "--set field.global_smoothing.strength=1");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_FALSE(contains(slurp(dir / "rep.json"), "\"hatch_strokes\": 0,")) << slurp(dir / "rep.json");
}

TEST(ReliabilityCli, TinySmoothingLengthsAndHugePapersAreRejectedNamingTheSetting) {
    const fs::path dir = workDir();
    put(dir / "s.yaml", kTorusScene);
    CliRun r = run(dir, "field s.yaml --smoothing-length 1e-200 -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(r.err.rfind("--smoothing-length: error: --smoothing-length must be 0 (raw curvature directions) or in "
                          "[1e-06, 10], got 1e-200",
                          0),
              0u)
        << r.err;
    put(dir / "sl.yaml", kTorusScene + "field: {smoothing_length: 1e-200}\n");
    r = run(dir, "render sl.yaml -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(r.err.rfind("sl.yaml:3:27: error: field.smoothing_length must be 0", 0), 0u) << r.err;
    r = run(dir, "render s.yaml -o p.svg -q --paper 1e308x1e308");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(r.err.rfind("--paper: error: paper size '1e308x1e308' is out of range: each side must be in [1, 100000] mm",
                          0),
              0u)
        << r.err;
    EXPECT_FALSE(fs::exists(dir / "p.svg"));
    put(dir / "page.yaml", kTorusScene + "style: {page: {size: 1e308x1e308}}\n");
    r = run(dir, "render page.yaml -o p.svg -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(r.err.rfind("page.yaml:3:22: error: style.page.size: paper size '1e308x1e308' is out of range", 0), 0u)
        << r.err;
    // The largest page is written with every number intact.
    r = run(dir, "render s.yaml -o big.svg -q --paper 100000x100000");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(contains(slurp(dir / "big.svg"), "width=\"100000mm\" height=\"100000mm\" viewBox=\"0 0 100000 100000\""));
}

TEST(ReliabilityCli, MessagesEscapeControlBytesAndSayWhatIsWrong) {
    const fs::path dir = workDir();
    // A terminal escape in a scene value is echoed escaped, never raw.
    put(dir / "esc.yaml", "mesh: {primitive: torus}\ncamera: {projection: \"\x1b[2J\x1b]0;owned\x07\"}\n");
    CliRun r = run(dir, "render esc.yaml -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(r.err.find('\x1b'), std::string::npos) << r.err;
    EXPECT_TRUE(contains(r.err, "unknown projection '\\x1b[2J\\x1b]0;owned\\x07'")) << r.err;
    // And in a mesh file.
    put(dir / "esc.off", "OFF\n3 1 0\n0 0 0\n1 \x1b[31m 0\n0 1 0\n3 0 1 2\n");
    r = run(dir, "field esc.off -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(r.err.find('\x1b'), std::string::npos) << r.err;
    // 128.0 is a whole number.
    put(dir / "point.yaml", "mesh: {primitive: torus}\ncamera: {resolution: [32.0, 3.2e1]}\n");
    r = run(dir, "render point.yaml -o point.png -q");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    put(dir / "half.yaml", "mesh: {primitive: torus}\ncamera: {resolution: [32.5, 32]}\n");
    r = run(dir, "render half.yaml -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "camera.resolution width must be a whole number, got 32.5")) << r.err;
    // A preset path that is a folder is a folder, not "does not exist".
    fs::create_directories(dir / "looks.yaml");
    put(dir / "preset.yaml", kTorusScene + "style: {preset: looks.yaml}\n");
    r = run(dir, "render preset.yaml -q");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "is a folder, not a file")) << r.err;
    EXPECT_FALSE(contains(r.err, "does not exist")) << r.err;
}
