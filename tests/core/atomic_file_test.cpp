// core/atomic_file.h, core/input_file.h and core/error.h's printable(): how outputs
// are written (temporaries, devices, pipes, links, modes, batches, signals) and how
// inputs are read (bounded, regular files only where a size is needed). Device
// nodes are scratch copies made with mknod in the test's own folder (root only; the
// tests skip otherwise), never /dev itself.

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/input_file.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/test_output.h"

namespace fs = std::filesystem;
using namespace rosy;

namespace {

fs::path workDir() { return rosy::test::testOutputDir("atomic_file", /*perTest=*/true, /*fresh=*/true); }

using rosy::test::put;
using rosy::test::slurp;

/// Names in `dir` that are temporaries of ours.
std::vector<std::string> temporaries(const fs::path &dir) {
    std::vector<std::string> names;
    for (const auto &e : fs::directory_iterator(dir)) {
        const std::string n = e.path().filename().string();
        if (n.rfind(kTemporaryPrefix, 0) == 0 || n.find(".tmp") != std::string::npos) names.push_back(n);
    }
    return names;
}

/// A scratch character device with the numbers of /dev/null (1, 3) or /dev/full (1, 7).
bool makeDevice(const fs::path &p, unsigned minor) {
    return ::mknod(p.c_str(), S_IFCHR | 0666, makedev(1, minor)) == 0;
}

bool isCharDevice(const fs::path &p) {
    struct stat st {};
    return ::lstat(p.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

} // namespace

TEST(AtomicOutput, DevicesAreWrittenInPlaceNeverReplaced) {
    const fs::path dir = workDir();
    if (::geteuid() != 0 || !makeDevice(dir / "null", 3) || !makeDevice(dir / "full", 7))
        GTEST_SKIP() << "needs root to create scratch device nodes";
    // Before: the temporary was renamed over the device, which became a regular file.
    EXPECT_NO_THROW(checkWritable((dir / "null").string()));
    EXPECT_NO_THROW(writeTextAtomically((dir / "null").string(), "{}\n"));
    EXPECT_TRUE(isCharDevice(dir / "null"));
    // /dev/full refuses every byte: an IoError naming it, and still a device.
    try {
        writeTextAtomically((dir / "full").string(), "{}\n");
        ADD_FAILURE() << "writing to a full device succeeded";
    } catch (const IoError &e) {
        EXPECT_NE(std::string(e.what()).find("full: error: write failed: No space left on device"), std::string::npos)
            << e.what();
    }
    EXPECT_TRUE(isCharDevice(dir / "full"));
    // Nothing was created next to the devices (their folder would be /dev).
    EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
    // A link to a device is followed to it and writes in place too.
    fs::create_symlink(dir / "null", dir / "link");
    EXPECT_NO_THROW(writeTextAtomically((dir / "link").string(), "x"));
    EXPECT_TRUE(fs::is_symlink(dir / "link"));
    EXPECT_TRUE(isCharDevice(dir / "null"));
}

TEST(AtomicOutput, BlockDevicesSocketsAndFoldersAreRefused) {
    const fs::path dir = workDir();
    fs::create_directories(dir / "folder");
    EXPECT_THROW(checkWritable((dir / "folder").string()), IoError);
    EXPECT_THROW(writeTextAtomically((dir / "folder").string(), "x"), IoError);
    if (::geteuid() == 0 && ::mknod((dir / "blk").c_str(), S_IFBLK | 0600, makedev(7, 200)) == 0) {
        try {
            checkWritable((dir / "blk").string());
            ADD_FAILURE();
        } catch (const IoError &e) {
            EXPECT_NE(std::string(e.what()).find("is a block device"), std::string::npos) << e.what();
        }
        EXPECT_THROW(writeTextAtomically((dir / "blk").string(), "x"), IoError);
        struct stat st {};
        ASSERT_EQ(::lstat((dir / "blk").c_str(), &st), 0);
        EXPECT_TRUE(S_ISBLK(st.st_mode));
    }
    EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
}

TEST(AtomicOutput, FifoIsWrittenInPlace) {
    const fs::path dir = workDir();
    const fs::path fifo = dir / "pipe";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::string received;
    std::thread reader([&] { received = slurp(fifo); });
    EXPECT_NO_THROW(writeTextAtomically(fifo.string(), "through the pipe\n"));
    reader.join();
    EXPECT_EQ(received, "through the pipe\n");
    struct stat st {};
    ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode));
    EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
}

TEST(AtomicOutput, DescriptorAliasesWriteToTheDescriptor) {
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0);
    const std::string alias = "/dev/fd/" + std::to_string(fds[1]);
    EXPECT_NO_THROW(checkWritable(alias));
    EXPECT_NO_THROW(writeTextAtomically(alias, "via the descriptor"));
    ::close(fds[1]);
    char buf[64] = {};
    const ssize_t n = ::read(fds[0], buf, sizeof buf - 1);
    ::close(fds[0]);
    EXPECT_EQ(std::string(buf, size_t(std::max<ssize_t>(n, 0))), "via the descriptor");
    // A descriptor that is not open is an IoError, before any work.
    EXPECT_THROW(checkWritable("/dev/fd/987"), IoError);
}

TEST(AtomicOutput, LinksAreFollowedAndTheirTargetReplacedAtomically) {
    const fs::path dir = workDir();
    fs::create_directories(dir / "real");
    put(dir / "real" / "target.json", "old");
    fs::create_symlink("real/target.json", dir / "link.json");
    writeTextAtomically((dir / "link.json").string(), "new");
    EXPECT_TRUE(fs::is_symlink(dir / "link.json")); // the link stays a link
    EXPECT_EQ(slurp(dir / "real" / "target.json"), "new");
    EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
    EXPECT_EQ(temporaries(dir / "real"), std::vector<std::string>{});
    // A link to nothing is refused (and left alone).
    fs::create_symlink("nowhere/x.json", dir / "dangling.json");
    try {
        checkWritable((dir / "dangling.json").string());
        ADD_FAILURE();
    } catch (const IoError &e) {
        EXPECT_NE(std::string(e.what()).find("is a link to 'nowhere/x.json', which does not exist"), std::string::npos)
            << e.what();
    }
    EXPECT_THROW(writeTextAtomically((dir / "dangling.json").string(), "x"), IoError);
    EXPECT_TRUE(fs::is_symlink(dir / "dangling.json"));
}

// The temporary used to be `.<stem>.tmp<PID>-<n>.<ext>`, opened without O_EXCL or
// O_NOFOLLOW: a link planted under that name made the write land in another file.
TEST(AtomicOutput, TemporaryIsExclusiveUnpredictableAndReachedThroughItsDescriptor) {
    const fs::path dir = workDir();
    put(dir / "victim.txt", "precious");
    for (int n = 0; n < 200; ++n)
        fs::create_symlink(dir / "victim.txt", dir / (".out.tmp" + std::to_string(::getpid()) + "-" +
                                                      std::to_string(n) + ".json"));
    std::string seenPath;
    std::vector<std::string> during;
    writeAtomically((dir / "out.json").string(), [&](const std::string &tmp) {
        seenPath = tmp;
        during = temporaries(dir);
        std::ofstream(tmp, std::ios::binary) << "output";
    });
    EXPECT_EQ(slurp(dir / "victim.txt"), "precious");
    EXPECT_EQ(slurp(dir / "out.json"), "output");
    // Writers get the open descriptor, not a name someone could swap.
    EXPECT_EQ(seenPath.rfind("/proc/self/fd/", 0), 0u) << seenPath;
    // One new temporary was there while writing: .rosyhatch- + 10 random characters + .tmp.
    std::vector<std::string> ours;
    for (const std::string &n : during)
        if (n.rfind(kTemporaryPrefix, 0) == 0) ours.push_back(n);
    ASSERT_EQ(ours.size(), 1u);
    EXPECT_EQ(ours[0].size(), std::string(kTemporaryPrefix).size() + 10 + 4) << ours[0];
    // Two writes use different names.
    std::string second;
    writeAtomically((dir / "out.json").string(), [&](const std::string &tmp) {
        for (const std::string &n : temporaries(dir))
            if (n.rfind(kTemporaryPrefix, 0) == 0) second = n;
        std::ofstream(tmp, std::ios::binary) << "again";
    });
    EXPECT_NE(second, ours[0]);
    for (const auto &e : fs::directory_iterator(dir))
        EXPECT_NE(e.path().filename().string().rfind(kTemporaryPrefix, 0), 0u) << e.path();
}

// NAME_MAX is 255: the old temporary added about 20 bytes to the output's name and
// failed after the whole render for names of 244-255 bytes.
TEST(AtomicOutput, NamesUpToTheFileSystemLimitWorkLongerOnesAreRefusedUpFront) {
    const fs::path dir = workDir();
    const long nameMax = ::pathconf(dir.c_str(), _PC_NAME_MAX);
    ASSERT_GT(nameMax, 20);
    const std::string longest = std::string(size_t(nameMax) - 5, 'n') + ".json";
    EXPECT_NO_THROW(checkWritable((dir / longest).string()));
    EXPECT_NO_THROW(writeTextAtomically((dir / longest).string(), "fits"));
    EXPECT_EQ(slurp(dir / longest), "fits");
    const std::string tooLong = std::string(size_t(nameMax) - 4, 'n') + ".json";
    try {
        checkWritable((dir / tooLong).string());
        ADD_FAILURE();
    } catch (const IoError &e) {
        EXPECT_NE(std::string(e.what()).find("more than the file system's limit of"), std::string::npos) << e.what();
    }
}

TEST(AtomicOutput, ExistingModeAndOwnerAreKeptNewFilesFollowTheUmask) {
    const fs::path dir = workDir();
    put(dir / "private.json", "old");
    ASSERT_EQ(::chmod((dir / "private.json").c_str(), 0600), 0);
    const bool root = ::geteuid() == 0;
    if (root) {
        ASSERT_EQ(::chown((dir / "private.json").c_str(), 4321, 4322), 0);
    }
    writeTextAtomically((dir / "private.json").string(), "new");
    struct stat st {};
    ASSERT_EQ(::stat((dir / "private.json").c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600u); // was 0644 (umask) before
    if (root) {
        EXPECT_EQ(st.st_uid, 4321u);
        EXPECT_EQ(st.st_gid, 4322u);
    }
    EXPECT_EQ(slurp(dir / "private.json"), "new");
    const mode_t mask = ::umask(022);
    ::umask(mask);
    writeTextAtomically((dir / "fresh.json").string(), "x");
    ASSERT_EQ(::stat((dir / "fresh.json").c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0666u & ~mask);
}

TEST(AtomicOutput, BatchPublishesEveryOutputOrNone) {
    const fs::path dir = workDir();
    put(dir / "a.txt", "old a");
    put(dir / "b.txt", "old b");
    {
        // The second output fails: the first, already written, must not be published.
        OutputBatch batch;
        writeTextAtomically((dir / "a.txt").string(), "new a");
        EXPECT_EQ(batch.pending(), 1u);
        EXPECT_EQ(slurp(dir / "a.txt"), "old a");
        EXPECT_THROW(writeAtomically((dir / "b.txt").string(),
                                     [&](const std::string &) { throw IoError("b.txt", "simulated disk full"); }),
                     IoError);
        // The command ends here with its error; the batch goes without commit().
    }
    EXPECT_EQ(slurp(dir / "a.txt"), "old a");
    EXPECT_EQ(slurp(dir / "b.txt"), "old b");
    EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
    {
        OutputBatch batch;
        writeTextAtomically((dir / "a.txt").string(), "new a");
        writeTextAtomically((dir / "b.txt").string(), "new b");
        EXPECT_EQ(slurp(dir / "a.txt"), "old a");
        batch.commit();
    }
    EXPECT_EQ(slurp(dir / "a.txt"), "new a");
    EXPECT_EQ(slurp(dir / "b.txt"), "new b");
    EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
    // A device that fails stops the commit before any file is replaced.
    if (::geteuid() == 0 && makeDevice(dir / "full", 7)) {
        OutputBatch batch;
        writeTextAtomically((dir / "a.txt").string(), "newer a");
        writeTextAtomically((dir / "full").string(), "report");
        EXPECT_THROW(batch.commit(), IoError);
    }
    EXPECT_EQ(slurp(dir / "a.txt"), "new a");
    EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
}

namespace {

/// Runs writeAtomically() in a child with the cleanup handlers; the write raises
/// `sig` half way. Returns the child's wait status.
int writeInterruptedBy(const fs::path &dir, int sig) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        for (const int s : {SIGINT, SIGTERM, SIGHUP}) std::signal(s, SIG_DFL); // whatever the test runner set
        installCleanupSignalHandlers();
        try {
            writeAtomically((dir / "out.json").string(), [&](const std::string &tmp) {
                std::ofstream os(tmp, std::ios::binary);
                os << "half of the content";
                os.flush();
                ::raise(sig);
                os << " and the rest";
            });
        } catch (...) {
        }
        ::_exit(0); // not reached when the handler works
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return status;
}

} // namespace

TEST(AtomicOutput, SignalsRemoveTemporariesAndStillEndTheProcess) {
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
        SCOPED_TRACE(sig);
        const fs::path dir = workDir();
        put(dir / "out.json", "previous");
        const int status = writeInterruptedBy(dir, sig);
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
        EXPECT_EQ(temporaries(dir), std::vector<std::string>{});
        EXPECT_EQ(slurp(dir / "out.json"), "previous");
    }
}

TEST(AtomicOutput, CheckNotAnInputComparesRegularFilesOnly) {
    const fs::path dir = workDir();
    put(dir / "in.off", "mesh");
    fs::create_symlink("in.off", dir / "alias.off");
    EXPECT_THROW(checkNotAnInput((dir / "alias.off").string(), (dir / "in.off").string(), "input mesh"), InputError);
    EXPECT_NO_THROW(checkNotAnInput((dir / "other.off").string(), (dir / "in.off").string(), "input mesh"));
    // A terminal or pipe that is both stdin and stdout is not "overwritten".
    EXPECT_NO_THROW(checkNotAnInput("/dev/stdout", "/dev/stdin", "scene file"));
}

TEST(InputFile, EndlessStreamsStopAtTheLimitNonRegularMeshesAreRefused) {
    const fs::path dir = workDir();
    const InputFileRules scene{"scene file", 4096, true};
    const InputFileRules mesh{"mesh file", 1 << 20, false};
    put(dir / "small.yaml", "mesh: x.off\n");
    EXPECT_EQ(readInputFile((dir / "small.yaml").string(), scene), "mesh: x.off\n");
    put(dir / "large.yaml", std::string(5000, '#'));
    EXPECT_THROW(readInputFile((dir / "large.yaml").string(), scene), InputError);
    EXPECT_THROW(readInputFile((dir / "missing.yaml").string(), scene), IoError);
    fs::create_directories(dir / "folder.yaml");
    EXPECT_THROW(readInputFile((dir / "folder.yaml").string(), scene), IoError);
    // An endless pipe (`yes | rosyhatch render /dev/stdin`): stopped at the limit.
    const fs::path fifo = dir / "endless";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::thread writer([&] {
        const int fd = ::open(fifo.c_str(), O_WRONLY);
        std::signal(SIGPIPE, SIG_IGN);
        const std::string chunk(1024, 'y');
        while (::write(fd, chunk.data(), chunk.size()) > 0) {
        }
        ::close(fd);
    });
    try {
        readInputFile(fifo.string(), scene);
        ADD_FAILURE();
    } catch (const InputError &e) {
        EXPECT_NE(std::string(e.what()).find("larger than the limit of 4096 bytes"), std::string::npos) << e.what();
    }
    // The reader closed the pipe: the writer stops on EPIPE.
    writer.join();
    // A mesh must be a regular file: a link to a device is refused at once.
    if (::geteuid() == 0 && ::mknod((dir / "zero").c_str(), S_IFCHR | 0666, makedev(1, 5)) == 0) {
        fs::create_symlink("zero", dir / "z.off");
        EXPECT_THROW(readInputFile((dir / "z.off").string(), mesh), IoError);
        EXPECT_THROW(readInputFile((dir / "zero").string(), scene), InputError); // read through the bound
    }
}

TEST(Printable, ControlBytesAreEscapedUtf8IsKept) {
    EXPECT_EQ(printable("plain text"), "plain text");
    EXPECT_EQ(printable("\x1b[31mred\x1b[0m"), "\\x1b[31mred\\x1b[0m");
    EXPECT_EQ(printable("a\tb\nc\r"), "a\\tb\\nc\\r");
    EXPECT_EQ(printable("a\nb", true), "a\nb");
    EXPECT_EQ(printable("caf\xc3\xa9 \xe2\x86\x92"), "caf\xc3\xa9 \xe2\x86\x92"); // café →
    EXPECT_EQ(printable("\xc2\x9b"), "\\xc2\\x9b");                               // C1 CSI
    EXPECT_EQ(printable("\xff\xfe"), "\\xff\\xfe");                               // not UTF-8
    EXPECT_EQ(printable("\x7f"), "\\x7f");
    const InputError e(FileLoc{"s\x1b.yaml", 2, 3}, "unknown key 'x\x1b]0;owned\x07'");
    EXPECT_STREQ(e.what(), "s\\x1b.yaml:2:3: error: unknown key 'x\\x1b]0;owned\\x07'");
}
