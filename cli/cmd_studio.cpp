/// \file cmd_studio.cpp
/// `rosyhatch studio SCENE.yaml [--port P] [--open] [--host ADDR]`: serves the local
/// web page on which the scene's field is designed, edited and previewed
/// (studio/studio.h, studio/server.h, docs/studio.md).

#include "cli/commands.h"

#include "studio/server.h"
#include "studio/studio.h"

#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <iostream>
#include <memory>

extern char **environ;

namespace rosy::cli {
namespace {

struct StudioCliOptions {
    std::string scenePath;
    int port = 0;
    std::string host = "127.0.0.1";
    bool open = false;
    long long maxFaces = 20'000'000;
    int displayAbove = 100000;
};

void openBrowser(const std::string &url) {
    pid_t pid = 0;
    std::string program = "xdg-open";
    char *argv[] = {program.data(), const_cast<char *>(url.c_str()), nullptr};
    if (posix_spawnp(&pid, "xdg-open", nullptr, nullptr, argv, environ) != 0)
        std::cerr << "warning: could not start xdg-open; open the URL above in a browser\n";
}

void runStudio(const StudioCliOptions &opt) {
    if (opt.host != "127.0.0.1" && opt.host != "localhost" && opt.host != "::1")
        std::cerr << "warning: --host " << opt.host
                  << ": the studio will accept connections from other machines on this address; anyone who "
                     "learns the URL's token can edit the field and write scene files beside "
                  << opt.scenePath << "\n";
    studio::StudioOptions so;
    so.load = field::LoadOptions{opt.maxFaces};
    so.displayAbove = opt.displayAbove;
    so.displayFaces = std::max(1, opt.displayAbove / 2);
    studio::Studio st(opt.scenePath, so);
    studio::ServerOptions server;
    server.host = opt.host;
    server.port = opt.port;
    studio::StudioServer srv(st, server);
    srv.bind();
    std::cout << "rosyhatch studio: " << opt.scenePath << "\n" << srv.url() << "\n(Ctrl-C stops it)" << std::endl;
    if (opt.open) openBrowser(srv.url());
    srv.run();
}

} // namespace

void addStudioCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<StudioCliOptions>();
    CLI::App *sub = app.add_subcommand("studio", "design and edit the scene's field on a local web page");
    sub->add_option("scene", opt->scenePath, "scene file (.yaml)")->required();
    sub->add_option("--port", opt->port, "port to listen on (0, the default: any free port)")->check(CLI::Range(0, 65535));
    sub->add_option("--host", opt->host,
                    "address to listen on (default 127.0.0.1; any other address is reachable from other machines)");
    sub->add_flag("--open", opt->open, "open the page in the default browser (xdg-open)");
    sub->add_option("--max-faces", opt->maxFaces, "reject meshes with more faces than this (default 20000000)")
        ->check(CLI::Range(1LL, 2'000'000'000LL));
    sub->add_option("--display-above", opt->displayAbove,
                    "show meshes with more faces than this as a display mesh of at most half as many (default 100000)")
        ->check(CLI::Range(2, 2'000'000'000));
    sub->callback([opt, &action] { action = [opt] { runStudio(*opt); }; });
}

} // namespace rosy::cli
