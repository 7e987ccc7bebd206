/// \file image_io.cpp
/// Finding and loading the image I/O module (see image_io.h).

#include "renderer/output/image_io.h"

#include "core/error.h"
#include "core/parallel.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <thread>

namespace rosy::renderer {
namespace {

constexpr const char *kModuleFileName = "librosy_image_io.so";

struct LoadResult {
    const ImageIo *io = nullptr;
    std::string error; ///< why not, when io is null
};

/// The candidates of image_io.h, in order.
std::vector<std::string> modulePaths() {
    std::vector<std::string> paths;
    if (const char *env = std::getenv("ROSY_IMAGE_IO_MODULE"); env && *env) {
        paths.emplace_back(env); // an explicit choice: no fallback behind it
        return paths;
    }
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        paths.push_back((exe.parent_path() / kModuleFileName).string());
        // Installed (cmake --install): PREFIX/bin/rosyhatch, PREFIX/lib/rosyhatch/the module.
        paths.push_back((exe.parent_path().parent_path() / "lib" / "rosyhatch" / kModuleFileName).string());
    }
#ifdef ROSY_IMAGE_IO_MODULE_PATH
    paths.emplace_back(ROSY_IMAGE_IO_MODULE_PATH);
#endif
    return paths;
}

LoadResult loadModule() {
    LoadResult result;
    std::string tried;
    for (const std::string &path : modulePaths()) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
            tried += "\n  " + path + ": no such file";
            continue;
        }
        // Never unloaded: OpenImageIO keeps threads and plugin state until exit.
        void *handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char *why = dlerror();
            tried += "\n  " + path + ": " + (why ? why : "dlopen failed");
            continue;
        }
        using Entry = const ImageIo *(*)(int);
        auto entry = reinterpret_cast<Entry>(dlsym(handle, kImageIoEntryPoint));
        const ImageIo *io = entry ? entry(kImageIoInterfaceVersion) : nullptr;
        if (!io) {
            tried += "\n  " + path + ": not a rosyhatch image I/O module of interface version " +
                     std::to_string(kImageIoInterfaceVersion);
            continue;
        }
        result.io = io;
        return result;
    }
    result.error = "cannot load the image I/O module (" + std::string(kModuleFileName) +
                   ", OpenImageIO's reader and writer); tried:" + tried +
                   "\nrebuild it (ninja rosy_image_io), keep it next to the rosyhatch executable, "
                   "or set ROSY_IMAGE_IO_MODULE to its path";
    return result;
}

/// The one load, started by preloadImageIo() or by the first imageIo().
class ModuleLoader {
public:
    void start() {
        std::lock_guard lock(m_mutex);
        if (m_started) return;
        m_started = true;
        m_thread = std::thread([this] { m_result = loadModule(); });
    }
    const LoadResult &wait() {
        start();
        std::call_once(m_joined, [this] { m_thread.join(); });
        return m_result;
    }
    /// Joins a load still in flight when the program ends (an early error exit),
    /// so no thread runs dlopen() while the process tears down.
    ~ModuleLoader() {
        if (m_thread.joinable()) m_thread.join();
    }

private:
    std::mutex m_mutex;
    bool m_started = false;
    std::thread m_thread;
    std::once_flag m_joined;
    LoadResult m_result; ///< written by the thread, read only after the join
};

ModuleLoader &loader() {
    static ModuleLoader instance;
    return instance;
}

/// The module's services with the read budget of image_io.h in front of open():
/// a header is judged before any pixel is allocated.
class BudgetedImageIo final : public ImageIo {
public:
    explicit BudgetedImageIo(const ImageIo &module) : m_module(module) {}
    bool write(const std::string &path, const ImageFileSpec &spec, PixelType dataType, const void *pixels,
               std::string &error) const override {
        return m_module.write(path, spec, dataType, pixels, error);
    }
    std::unique_ptr<ImageFileReader> open(const std::string &path, std::string &error) const override {
        std::unique_ptr<ImageFileReader> in = m_module.open(path, error);
        if (in) checkReadBudget(path, in->header());
        return in;
    }

private:
    const ImageIo &m_module;
};

} // namespace

void checkReadBudget(const std::string &path, const ImageFileHeader &h) {
    const double pixels = double(std::max(h.width, 0)) * double(std::max(h.height, 0)) * double(std::max(h.depth, 1));
    const double values = pixels * double(std::max(h.nChannels, 0));
    auto size = [&] {
        return std::to_string(h.width) + " x " + std::to_string(h.height) +
               (h.depth > 1 ? " x " + std::to_string(h.depth) : std::string()) + " pixels of " +
               std::to_string(h.nChannels) + " channel(s)";
    };
    const std::string hint = "rosyhatch reads images of at most 4096 x 4096 pixels and " +
                             std::to_string(kMaxReadValues) + " channel values (the largest render it writes)";
    if (pixels > double(kMaxReadPixels))
        throw InputError(FileLoc{path},
                         "the image is " + size() + ": more than the limit of " + std::to_string(kMaxReadPixels) +
                             " pixels",
                         hint);
    if (values > double(kMaxReadValues))
        throw InputError(FileLoc{path},
                         "the image is " + size() + ": " + std::to_string((long long)values) +
                             " values, more than the limit of " + std::to_string(kMaxReadValues) + " (" +
                             std::to_string(kMaxReadValues * 4 / (1 << 20)) + " MiB as float)",
                         hint);
}

std::string imageIoModulePath() {
    for (const std::string &path : modulePaths()) {
        std::error_code ec;
        if (std::filesystem::exists(path, ec)) return path;
    }
    return {};
}

void preloadImageIo() {
    startWorkerThreads(); // before dlopen() holds the loader lock (core/parallel.h)
    loader().start();
}

const ImageIo &imageIo() {
    const LoadResult &r = loader().wait();
    if (!r.io) throw IoError(kModuleFileName, r.error);
    static const BudgetedImageIo budgeted(*r.io);
    return budgeted;
}

} // namespace rosy::renderer
