#pragma once
/// \file commands.h
/// Subcommands of the rosyhatch executable. Each one lives in its own
/// cmd_<name>.cpp and registers itself with one call in main.cpp.

#include <CLI/CLI.hpp>

#include <chrono>
#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace rosy::cli {

/// The work of the subcommand the user chose. Set while parsing, run by main()
/// inside the program's only try block, so every error maps to an exit code.
using Action = std::function<void()>;

/// Adds `rosyhatch render SCENE.yaml [-o OUT]` and the common options to `app`.
void addRenderCommand(CLI::App &app, Action &action);

/// Adds `rosyhatch field SCENE_OR_MESH` (field report, singularities, export).
void addFieldCommand(CLI::App &app, Action &action);

/// Adds `rosyhatch inspect RENDER.exr [--json OUT]` (quality measures of a rendering).
void addInspectCommand(CLI::App &app, Action &action);

/// Adds `rosyhatch styles` (the style presets with their descriptions).
void addStylesCommand(CLI::App &app, Action &action);

/// Adds `rosyhatch compare SCENE.yaml` (labeled side-by-side panels of several fields).
void addCompareCommand(CLI::App &app, Action &action);

/// Adds `rosyhatch studio SCENE.yaml` (the local web page for field design, docs/studio.md).
void addStudioCommand(CLI::App &app, Action &action);

/// Adds `rosyhatch remesh SCENE_OR_MESH -o OUT` (field-aligned quad / triangle remeshing).
void addRemeshCommand(CLI::App &app, Action &action);

/// Adds the repeatable `--set dotted.key=VALUE` scene override (see scenes::parseSceneFile).
void addSetOption(CLI::App &sub, std::vector<std::string> &overrides);

/// Adds `rosyhatch diff A B` (image comparison with idiff's thresholds and exit codes).
void addDiffCommand(CLI::App &app, Action &action);

/// For `rosyhatch diff` (args[1] == "diff", args[0] the program): rewrites idiff's
/// single-dash spellings -fail, -failpercent, -hardfail, -warn and -warnpercent to
/// ours (--fail, ...) before parsing, up to a `--`. Other command lines are untouched.
void acceptIdiffSpellings(std::vector<std::string> &args);

/// Adds `rosyhatch help [COMMAND] [--man | --bash-completion]` (cmd_help.cpp).
void addHelpCommand(CLI::App &app, Action &action);

/// The closest of `candidates` to `word` if it is close enough to be a slip (a
/// prefix, or within a third of its length in edits), else "".
std::string suggestName(const std::string &word, const std::vector<std::string> &candidates);

/// `rosyhatch --version`: the version, the image I/O module found and the style
/// preset folders searched.
std::string versionText();

/// Before parsing: no command at all, or an unknown command word (args[1]): prints
/// the help or the error with a suggestion on stderr and returns 2; else 0.
int checkCommandName(const CLI::App &app, const std::vector<std::string> &args);

/// After a parse error: one line per unknown option word in `args` with the
/// closest option of the command (`did you mean '--threads'?`).
void suggestOptions(const CLI::App &app, const std::vector<std::string> &args, std::ostream &out);

/// The man page (roff) and the bash completion script, from the same definitions as --help.
std::string manPage(const CLI::App &app);
std::string bashCompletion(const CLI::App &app);

/// Thrown by a subcommand whose outcome is not an error but still a nonzero exit
/// status (diff: 1 warning, 2 failure, 4 file error, as idiff); main() returns `code`
/// (the message, if any, is already printed).
struct ExitWith {
    int code;
};

/// Options every working subcommand shares.
struct CommonOptions {
    int threads = 0;         ///< 0 = all cores
    bool quiet = false;      ///< no progress bars, no informational lines
    std::string timingsPath; ///< empty = no timings file
    /// --max-faces: mesh files with more faces are rejected before allocating.
    long long maxFaces = 20'000'000;
};

/// True if `path` ends in `dotExt` (e.g. ".svg"), ignoring case.
bool hasExtension(const std::string &path, const char *dotExt);
/// True for a path ending in ".svg" (any case, as hasExtension).
bool isSvgPath(const std::string &path);

/// Adds --threads, --quiet, --timings and --max-faces to a subcommand.
void addCommonOptions(CLI::App &sub, CommonOptions &options);

/// Wall-clock seconds per named stage, in the order the stages ran.
class Timings {
public:
    /// Runs `work` and records how long it took under `stage`.
    template <typename F>
    auto time(const std::string &stage, F &&work) {
        auto start = std::chrono::steady_clock::now();
        struct Record {
            Timings *t;
            std::string stage;
            std::chrono::steady_clock::time_point start;
            ~Record() {
                t->m_stages.emplace_back(
                    stage, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
            }
        } record{this, stage, start};
        return work();
    }
    /// Records a stage measured elsewhere (milliseconds).
    void add(const std::string &stage, double ms) { m_stages.emplace_back(stage, ms / 1000.0); }
    /// Writes {"stage": milliseconds, ..., "total": milliseconds} atomically to
    /// `path`, stages in the order they ran; total is the whole command's wall time
    /// when given (> 0), else the sum of the stages.
    void write(const std::string &path, double totalMs = 0) const;

private:
    std::vector<std::pair<std::string, double>> m_stages;
};

} // namespace rosy::cli
