#pragma once
/// \file server.h
/// The local HTTP server of `rosyhatch studio` (cpp-httplib): the page's assets,
/// three.js from Debian's libjs-three, and the JSON/binary API over one Studio.
///
/// Security of a server on the user's machine:
///  - binds 127.0.0.1 unless told otherwise (the CLI warns for any other address),
///    without SO_REUSEPORT (no other process can share the port);
///  - every request carries the random token of the printed URL (query `token=`,
///    header `X-Rosy-Token`, or the cookie the page's first load sets), compared in
///    constant time; otherwise 403;
///  - the Host header must name the server (127.0.0.1, localhost or [::1] with its
///    port, or the bound address) and an Origin header, when sent, the same:
///    a DNS-rebinding page under another name gets 403;
///  - only a fixed list of files is served (the page's own and two of three.js);
///    a request target with `..`, `//`, a backslash, percent-encoded dots, slashes
///    or NUL, or not starting with `/`, is 400 before any routing;
///  - request bodies over ServerOptions::maxBodyBytes are refused (413);
///  - malformed requests and refused edits get 400 with a message; a handler that
///    fails answers 500 and the server keeps running.
/// Edits are serialized by the Studio's mutex (studio.h).

#include "studio/studio.h"

#include <cstddef>
#include <memory>
#include <string>
#include <thread>

namespace rosy::studio {

struct ServerOptions {
    std::string host = "127.0.0.1";
    int port = 0;           ///< 0: any free port
    std::string token;      ///< empty: 32 random hex digits
    std::string webDir;     ///< empty: $ROSY_STUDIO_WEB_DIR, else the installed studio/web
    std::string threeDir;   ///< empty: $ROSY_THREE_DIR, else /usr/share/javascript/three
    size_t maxBodyBytes = 64 * 1024;
};

/// Where the page's files are when ServerOptions::webDir is empty: $ROSY_STUDIO_WEB_DIR,
/// else <executable>/../share/rosyhatch/studio when it holds index.html (installed),
/// else the source tree's studio/web.
std::string defaultWebDir();

class StudioServer {
public:
    StudioServer(Studio &studio, ServerOptions options);
    ~StudioServer();

    /// Binds the socket. \returns the port. \throws IoError if the address cannot be bound
    /// or a served file is missing.
    int bind();
    /// Serves until stop() (blocking).
    void run();
    /// Serves on a background thread (tests, benchmarks).
    void start();
    void stop();

    int port() const { return m_port; }
    const std::string &token() const { return m_options.token; }
    /// http://HOST:PORT/?token=TOKEN
    std::string url() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    ServerOptions m_options;
    int m_port = 0;
    std::thread m_thread;
};

} // namespace rosy::studio
