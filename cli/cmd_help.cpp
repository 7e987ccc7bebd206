/// \file cmd_help.cpp
/// `rosyhatch help [COMMAND]`, the version text, suggestions for misspelt
/// commands and options, and the man page and bash completion, both generated
/// from the same CLI11 definitions `--help` prints (so they cannot drift from
/// the code): the build runs `rosyhatch help --man` and `--bash-completion`
/// (cli/CMakeLists.txt) and `cmake --install` installs their output.

#include "cli/commands.h"

#include "renderer/output/image_io.h"
#include "scenes/style_presets.h"
#include "studio/server.h"

#include <algorithm>
#include <cctype>
#include <iostream>
#include <memory>
#include <sstream>

namespace rosy::cli {

namespace {

/// Optimal string alignment distance (Levenshtein plus adjacent swaps).
size_t editDistance(const std::string &a, const std::string &b) {
    const size_t n = a.size(), m = b.size();
    std::vector<std::vector<size_t>> d(n + 1, std::vector<size_t>(m + 1, 0));
    for (size_t i = 0; i <= n; ++i) d[i][0] = i;
    for (size_t j = 0; j <= m; ++j) d[0][j] = j;
    for (size_t i = 1; i <= n; ++i)
        for (size_t j = 1; j <= m; ++j) {
            const size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[n][m];
}

/// Every spelling of the options of `app` ("--threads", "-q", ...) and its subcommands' names.
std::vector<std::string> optionSpellings(const CLI::App &app) {
    std::vector<std::string> names;
    for (const CLI::Option *o : app.get_options()) {
        for (const std::string &l : o->get_lnames()) names.push_back("--" + l);
        for (const std::string &s : o->get_snames()) names.push_back("-" + s);
    }
    return names;
}

std::vector<std::string> commandNames(const CLI::App &app) {
    std::vector<std::string> names;
    for (const CLI::App *sub : app.get_subcommands([](const CLI::App *) { return true; }))
        names.push_back(sub->get_name());
    return names;
}

const CLI::App *findCommand(const CLI::App &app, const std::string &name) {
    for (const CLI::App *sub : app.get_subcommands([](const CLI::App *) { return true; }))
        if (sub->get_name() == name) return sub;
    return nullptr;
}

/// roff text: backslashes escaped, a leading dot or quote neutralised.
std::string roff(const std::string &text) {
    std::string out;
    for (char c : text) {
        if (c == '\\')
            out += "\\e";
        else if (c == '-')
            out += "\\-";
        else
            out += c;
    }
    if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out = "\\&" + out;
    return out;
}

/// "-o, --output FILE" style: every name of the option and its value type.
std::string optionSynopsis(const CLI::Option *o) {
    std::string names;
    for (const std::string &s : o->get_snames()) {
        names += names.empty() ? "-" : ", -";
        names += s;
    }
    for (const std::string &l : o->get_lnames()) {
        names += names.empty() ? "--" : ", --";
        names += l;
    }
    if (o->get_positional()) names = o->get_name();
    const std::string type = o->get_type_name();
    if (!o->get_positional() && o->get_expected_min() > 0 && !type.empty()) names += " " + type;
    return names;
}

struct HelpOptions {
    std::string command;
    bool man = false;
    bool bashCompletion = false;
};

} // namespace

std::string suggestName(const std::string &word, const std::vector<std::string> &candidates) {
    std::string best;
    size_t bestDistance = std::string::npos;
    for (const std::string &c : candidates) {
        // A prefix of exactly one name is that name ("rend" -> "render").
        const size_t d = c.rfind(word, 0) == 0 && word.size() >= 2 ? 1 : editDistance(word, c);
        if (d < bestDistance) bestDistance = d, best = c;
    }
    // Close enough to be a slip: a third of the word, at least one edit.
    const size_t allowed = std::max<size_t>(1, word.size() / 3);
    return bestDistance <= allowed ? best : std::string();
}

std::string versionText() {
    std::ostringstream os;
    os << "rosyhatch " << ROSY_VERSION << "\n";
    const std::string module = renderer::imageIoModulePath();
    os << "image I/O module: " << (module.empty() ? "not found" : module) << "\n";
    os << "style presets:";
    for (const std::string &dir : scenes::styleSearchDirs()) os << " " << dir;
    os << "\n";
    os << "studio page: " << studio::defaultWebDir() << "\n";
    return os.str();
}

int checkCommandName(const CLI::App &app, const std::vector<std::string> &args) {
    if (args.size() < 2) {
        std::cerr << app.help() << "\nrosyhatch: error: a command is required; `rosyhatch help COMMAND` shows one in detail\n";
        return 2;
    }
    const std::string &word = args[1];
    if (word.empty() || word[0] == '-' || findCommand(app, word)) return 0;
    std::cerr << "rosyhatch: error: unknown command '" << word << "'";
    const std::string guess = suggestName(word, commandNames(app));
    if (!guess.empty()) std::cerr << "; did you mean '" << guess << "'?";
    std::cerr << "\nthe commands are:";
    for (const std::string &name : commandNames(app)) std::cerr << " " << name;
    std::cerr << " (rosyhatch help COMMAND for one)\n";
    return 2;
}

void suggestOptions(const CLI::App &app, const std::vector<std::string> &args, std::ostream &out) {
    const CLI::App *sub = args.size() >= 2 ? findCommand(app, args[1]) : nullptr;
    std::vector<std::string> known = optionSpellings(app);
    if (sub) {
        const std::vector<std::string> own = optionSpellings(*sub);
        known.insert(known.end(), own.begin(), own.end());
    }
    for (size_t i = 1; i < args.size(); ++i) {
        const std::string &a = args[i];
        if (a == "--") break;
        // An option word: a dash and a letter (not a negative number such as -1).
        if (a.size() < 2 || a[0] != '-' || !(std::isalpha(static_cast<unsigned char>(a[1])) || a[1] == '-')) continue;
        const std::string name = a.substr(0, a.find('='));
        if (name == "--" || std::find(known.begin(), known.end(), name) != known.end()) continue;
        // Compared without their dashes, so -fial finds --fail.
        auto bare = [](const std::string &o) { return o.substr(o.find_first_not_of('-')); };
        std::vector<std::string> bareKnown;
        for (const std::string &k : known) bareKnown.push_back(bare(k));
        const std::string bareGuess = name.find_first_not_of('-') == std::string::npos ? std::string()
                                                                                          : suggestName(bare(name), bareKnown);
        std::string guess;
        for (const std::string &k : known)
            if (!bareGuess.empty() && bare(k) == bareGuess && (guess.empty() || k.size() > guess.size())) guess = k;
        out << "rosyhatch: unknown option '" << name << "'";
        if (!guess.empty()) out << "; did you mean '" << guess << "'?";
        out << "\n";
    }
}

std::string manPage(const CLI::App &app) {
    std::ostringstream os;
    os << ".TH ROSYHATCH 1 \"\" \"rosyhatch " << ROSY_VERSION << "\" \"User Commands\"\n";
    os << ".SH NAME\nrosyhatch \\- " << roff("pen-and-ink rendering along N-RoSy fields") << "\n";
    os << ".SH SYNOPSIS\n.B rosyhatch\n\\fICOMMAND\\fR [\\fIOPTIONS\\fR] [\\fIARGUMENTS\\fR]\n.br\n"
          ".B rosyhatch help\n[\\fICOMMAND\\fR]\n.br\n.B rosyhatch\n\\-V | \\-\\-version\n";
    os << ".SH DESCRIPTION\n" << roff(app.get_description()) << ".\n"
       << roff("Generated from the program's own --help text (rosyhatch help --man); "
               "README.md in the source tree has the details.")
       << "\n";
    os << ".SH COMMANDS\n";
    for (const CLI::App *sub : app.get_subcommands([](const CLI::App *) { return true; })) {
        os << ".SS \"rosyhatch " << sub->get_name() << "\"\n" << roff(sub->get_description()) << "\n";
        for (const CLI::Option *o : sub->get_options()) {
            os << ".TP\n.B " << roff(optionSynopsis(o)) << "\n" << roff(o->get_description()) << "\n";
        }
    }
    os << ".SH EXIT STATUS\n"
          ".TP\n.B 0\nsuccess\n"
          ".TP\n.B 1\ninternal error (a bug); for diff: WARNING\n"
          ".TP\n.B 2\nrejected input: usage, scene, mesh, parameters, limits; for diff also FAILURE\n"
          ".TP\n.B 3\nenvironment or I/O: unreadable input, unwritable output, out of memory\n"
          ".TP\n.B 4\ndiff only: a file that cannot be read or written (idiff's code)\n";
    os << ".SH ENVIRONMENT\n"
          ".TP\n.B ROSY_IMAGE_IO_MODULE\npath of librosy_image_io.so, the OpenImageIO module\n"
          ".TP\n.B ROSY_STYLES_PATH\ncolon\\-separated folders searched first for style presets\n"
          ".TP\n.B ROSY_MEMORY_CHECK\n" << roff("off: render even when the estimate does not fit in memory") << "\n";
    os << ".SH FILES\n.TP\n.I share/rosyhatch/styles/*.yaml\n" << roff("style presets, beside the installed program")
       << "\n.TP\n.I lib/rosyhatch/librosy_image_io.so\n" << roff("the image I/O module") << "\n";
    os << ".SH SEE ALSO\n.BR idiff (1),\n.BR oiiotool (1)\n";
    return os.str();
}

std::string bashCompletion(const CLI::App &app) {
    std::ostringstream os;
    os << "# bash completion for rosyhatch, generated by `rosyhatch help --bash-completion`\n"
          "_rosyhatch() {\n"
          "    local cur=\"${COMP_WORDS[COMP_CWORD]}\" cmd=\"${COMP_WORDS[1]}\" words\n"
          "    if [ \"$COMP_CWORD\" -eq 1 ]; then\n"
          "        words=\"";
    for (const std::string &name : commandNames(app)) os << name << " ";
    os << "--help --version -V\"\n"
          "    else\n"
          "        case \"$cmd\" in\n";
    for (const CLI::App *sub : app.get_subcommands([](const CLI::App *) { return true; })) {
        os << "        " << sub->get_name() << ") words=\"";
        if (sub->get_name() == "help")
            for (const std::string &name : commandNames(app)) os << name << " ";
        for (const std::string &o : optionSpellings(*sub)) os << o << " ";
        os << "\" ;;\n";
    }
    os << "        *) words=\"\" ;;\n"
          "        esac\n"
          "        if [[ \"$cur\" != -* && \"$cmd\" != help ]]; then\n"
          "            COMPREPLY=($(compgen -f -- \"$cur\"))\n"
          "            return\n"
          "        fi\n"
          "    fi\n"
          "    COMPREPLY=($(compgen -W \"$words\" -- \"$cur\"))\n"
          "}\n"
          "complete -o filenames -o bashdefault -F _rosyhatch rosyhatch\n";
    return os.str();
}

void addHelpCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<HelpOptions>();
    CLI::App *sub = app.add_subcommand("help", "show the help of rosyhatch or of one command (rosyhatch help render)");
    sub->add_option("command", opt->command, "the command to explain");
    sub->add_flag("--man", opt->man, "print the man page (roff), generated from this help");
    sub->add_flag("--bash-completion", opt->bashCompletion, "print the bash completion script");
    const CLI::App *root = &app;
    sub->callback([opt, root, &action] {
        action = [opt, root] {
            if (opt->man) {
                std::cout << manPage(*root);
            } else if (opt->bashCompletion) {
                std::cout << bashCompletion(*root);
            } else if (opt->command.empty()) {
                // Not root->help(): once `help` is parsed, CLI11 would describe that subcommand.
                std::cout << root->get_formatter()->make_help(root, "", CLI::AppFormatMode::Normal);
            } else if (const CLI::App *cmd = findCommand(*root, opt->command)) {
                std::cout << cmd->help("rosyhatch");
            } else {
                std::cerr << "rosyhatch help: error: unknown command '" << opt->command << "'";
                const std::string guess = suggestName(opt->command, commandNames(*root));
                if (!guess.empty()) std::cerr << "; did you mean '" << guess << "'?";
                std::cerr << "\n";
                throw ExitWith{2};
            }
        };
    });
}

} // namespace rosy::cli
