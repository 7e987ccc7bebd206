/// \file main.cpp
/// The rosyhatch executable: parses the command line, runs one subcommand and
/// maps its outcome to the documented exit codes. This is the only place that
/// catches errors:
///   0 success, 1 internal error (a bug), 2 rejected input (usage, scene, mesh),
///   3 environment / I/O failure (unreadable input, unwritable output).

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <csignal>
#include <iostream>
#include <new>
#include <string>
#include <vector>

int main(int argc, char **argv) {
    // Past a file size limit (ulimit -f) the kernel would kill us with SIGXFSZ,
    // leaving the temporary output behind; ignored, the write fails with EFBIG,
    // which the writers report as an IoError (exit 3) after removing the temporary.
    std::signal(SIGXFSZ, SIG_IGN);
    // Ctrl-C, kill, a closed terminal or pipe: remove the temporary files of outputs
    // being written, then end with that signal as usual (core/atomic_file.h).
    rosy::installCleanupSignalHandlers();
    CLI::App app{"rosyhatch: pen-and-ink rendering along N-RoSy fields"};
    app.name("rosyhatch");
    app.set_version_flag("-V,--version", [] { return rosy::cli::versionText(); },
                         "print the version, the image I/O module and the style preset folders, and exit");
    app.require_subcommand(1);

    rosy::cli::Action action;
    // One line per subcommand.
    rosy::cli::addRenderCommand(app, action);
    rosy::cli::addFieldCommand(app, action);
    rosy::cli::addInspectCommand(app, action);
    rosy::cli::addStylesCommand(app, action);
    rosy::cli::addDiffCommand(app, action);
    rosy::cli::addCompareCommand(app, action);
    rosy::cli::addHelpCommand(app, action);
    rosy::cli::addStudioCommand(app, action);
    rosy::cli::addRemeshCommand(app, action);

    // The command line as strings, with diff's idiff spellings made ours.
    std::vector<std::string> args(argv, argv + argc);
    rosy::cli::acceptIdiffSpellings(args);
    // No command, or a misspelt one: the help or a suggestion instead of CLI11's
    // "A subcommand is required".
    if (args.size() < 2 || (args[1] != "-V" && args[1] != "--version" && args[1] != "-h" && args[1] != "--help"))
        if (const int code = rosy::cli::checkCommandName(app, args)) return code;
    try {
        std::vector<std::string> reversed(args.rbegin(), args.rend() - 1); // CLI11 takes them reversed, no argv[0]
        app.parse(reversed);
    } catch (const CLI::ParseError &e) {
        // --help and --version arrive here as "successful" parse errors.
        int code = app.exit(e);
        if (code != 0) rosy::cli::suggestOptions(app, args, std::cerr);
        return code == 0 ? 0 : 2;
    }

    try {
        if (action) action();
        return 0;
    } catch (const rosy::cli::ExitWith &e) {
        return e.code;
    } catch (const rosy::InputError &e) {
        std::cerr << e.what() << "\n";
        return 2;
    } catch (const rosy::IoError &e) {
        std::cerr << e.what() << "\n";
        return 3;
    } catch (const std::bad_alloc &) {
        // The machine, not the input or the program: an environment failure. The
        // render refuses what cannot fit before it starts (cli/cmd_render.cpp); this
        // is what is left (other programs took the memory meanwhile).
        std::cerr << "rosyhatch: error: out of memory; close other programs or lower camera.resolution\n";
        return 3;
    } catch (const std::exception &e) {
        std::cerr << "internal error: " << e.what() << "\n";
        return 1;
    } catch (...) {
        std::cerr << "internal error: unknown exception\n";
        return 1;
    }
}
