/// \file server.cpp
/// The studio's HTTP server (server.h).

#include "studio/server.h"

#include "core/error.h"

#include <httplib.h>

#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <chrono>
#include <random>

#ifndef ROSY_STUDIO_WEB_DIR
#define ROSY_STUDIO_WEB_DIR "studio/web"
#endif

namespace rosy::studio {
namespace {

/// /api/mesh is sent in pieces of this size (chunked transfer encoding).
constexpr size_t kMeshChunkBytes = 256 * 1024;

std::string randomToken() {
    std::random_device rd; // getrandom() on Linux
    static const char *hex = "0123456789abcdef";
    std::string t;
    for (int i = 0; i < 32; ++i) t += hex[rd() & 15u];
    return t;
}

std::string envOr(const char *name, const std::string &fallback) {
    const char *v = std::getenv(name);
    return v && *v ? std::string(v) : fallback;
}

bool sameSecret(const std::string &a, const std::string &b) {
    if (a.size() != b.size()) return false;
    unsigned char diff = 0;
    for (size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
    return diff == 0;
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

/// Why a request target is refused before routing (empty: acceptable).
std::string targetProblem(const std::string &target, const std::string &path) {
    if (target.empty() || target[0] != '/') return "the request target must be a path starting with /";
    const std::string t = lower(target.substr(0, target.find('?')));
    for (const char *bad : {"..", "//", "\\", "%2e", "%2f", "%5c", "%00", "%25"})
        if (t.find(bad) != std::string::npos) return std::string("the path may not contain ") + bad;
    if (path.find('\0') != std::string::npos || path.find("..") != std::string::npos) return "the path may not contain ..";
    return {};
}

struct Asset {
    std::string file;
    std::string type;
};

/// httplib's route patterns are regular expressions: match the path literally.
std::string regexEscape(const std::string &s) {
    std::string out;
    for (char c : s) {
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '/' && c != '_' && c != '-') out += '\\';
        out += c;
    }
    return out;
}

void sendText(httplib::Response &res, int status, const std::string &message) {
    res.status = status;
    res.set_content(message + "\n", "text/plain; charset=utf-8");
}

} // namespace

std::string defaultWebDir() {
    // $ROSY_STUDIO_WEB_DIR, else installed beside the program
    // (<executable>/../share/rosyhatch/studio, `cmake --install`), else the source tree's.
    if (const char *v = std::getenv("ROSY_STUDIO_WEB_DIR"); v && *v) return v;
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "rosyhatch" / "studio";
        if (std::filesystem::is_regular_file(installed / "index.html", ec)) return installed.string();
    }
    return ROSY_STUDIO_WEB_DIR;
}

struct StudioServer::Impl {
    httplib::Server server;
    std::map<std::string, Asset> assets; ///< URL path -> file
};

StudioServer::StudioServer(Studio &studio, ServerOptions options)
    : m_impl(std::make_unique<Impl>()), m_options(std::move(options)) {
    if (m_options.token.empty()) m_options.token = randomToken();
    const std::string web = m_options.webDir.empty() ? defaultWebDir() : m_options.webDir;
    const std::string three = m_options.threeDir.empty() ? envOr("ROSY_THREE_DIR", "/usr/share/javascript/three")
                                                         : m_options.threeDir;
    auto &assets = m_impl->assets;
    assets["/"] = {web + "/index.html", "text/html; charset=utf-8"};
    assets["/app.js"] = {web + "/app.js", "text/javascript; charset=utf-8"};
    assets["/studio.css"] = {web + "/studio.css", "text/css; charset=utf-8"};
    // OrbitControls imports "../../../build/three.module.js": both keep their layout.
    assets["/three/build/three.module.js"] = {three + "/build/three.module.js", "text/javascript; charset=utf-8"};
    assets["/three/examples/jsm/controls/OrbitControls.js"] = {three + "/examples/jsm/controls/OrbitControls.js",
                                                               "text/javascript; charset=utf-8"};

    httplib::Server &srv = m_impl->server;
    srv.set_payload_max_length(m_options.maxBodyBytes);
    // httplib's default sets SO_REUSEPORT, which lets another process of the same user
    // bind the same port and take part of the connections (and a second studio on a
    // taken --port start silently). SO_REUSEADDR alone only allows a restart while
    // old connections linger in TIME_WAIT.
    srv.set_socket_options([](socket_t sock) {
        int yes = 1;
        setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    srv.set_read_timeout(10, 0);
    srv.set_write_timeout(10, 0);
    srv.set_keep_alive_max_count(1000);
    srv.set_default_headers({{"X-Content-Type-Options", "nosniff"},
                             {"Cache-Control", "no-store"},
                             {"Referrer-Policy", "no-referrer"},
                             {"X-Frame-Options", "DENY"},
                             {"Content-Security-Policy",
                              "default-src 'self'; img-src 'self' blob: data:; style-src 'self'; frame-ancestors 'none'"}});

    const std::string cookieName = "rosyhatch_studio_token";
    srv.set_pre_routing_handler([this, cookieName](const httplib::Request &req, httplib::Response &res) {
        using R = httplib::Server::HandlerResponse;
        if (const std::string why = targetProblem(req.target, req.path); !why.empty()) {
            sendText(res, 400, "error: refused path: " + why);
            return R::Handled;
        }
        // Host and Origin against DNS rebinding.
        const std::string port = std::to_string(m_port);
        std::vector<std::string> hosts = {"127.0.0.1:" + port, "localhost:" + port, "[::1]:" + port};
        if (m_options.host != "127.0.0.1" && m_options.host != "localhost") {
            const bool v6 = m_options.host.find(':') != std::string::npos;
            hosts.push_back((v6 ? "[" + m_options.host + "]" : m_options.host) + ":" + port);
        }
        const std::string host = lower(req.get_header_value("Host"));
        if (std::find(hosts.begin(), hosts.end(), host) == hosts.end()) {
            sendText(res, 403, "error: Host header '" + host + "' is not this server's (DNS rebinding protection); open " +
                                   url());
            return R::Handled;
        }
        if (req.has_header("Origin")) {
            const std::string origin = lower(req.get_header_value("Origin"));
            bool ok = false;
            for (const std::string &h : hosts) ok = ok || origin == "http://" + h;
            if (!ok) {
                sendText(res, 403, "error: cross-origin request from '" + origin + "' refused");
                return R::Handled;
            }
        }
        // The token: query, header or cookie.
        std::string given = req.get_param_value("token");
        if (given.empty()) given = req.get_header_value("X-Rosy-Token");
        if (given.empty()) {
            const std::string cookies = req.get_header_value("Cookie");
            const std::string key = cookieName + "_" + port + "=";
            size_t at = 0;
            while ((at = cookies.find(key, at)) != std::string::npos) {
                if (at == 0 || cookies[at - 1] == ' ' || cookies[at - 1] == ';') {
                    const size_t start = at + key.size();
                    given = cookies.substr(start, cookies.find(';', start) - start);
                    break;
                }
                at += key.size();
            }
        }
        if (!sameSecret(given, m_options.token)) {
            sendText(res, 403, "error: missing or wrong token; open the URL rosyhatch studio printed (with ?token=...)");
            return R::Handled;
        }
        return R::Unhandled;
    });

    // Assets: the fixed list only.
    for (const auto &[urlPath, asset] : assets) {
        const Asset a = asset;
        const std::string p = urlPath;
        srv.Get(regexEscape(p), [this, a, p, cookieName](const httplib::Request &req,
                                                                                           httplib::Response &res) {
            std::ifstream in(a.file, std::ios::binary);
            if (!in) return sendText(res, 500, "error: cannot read " + a.file);
            res.set_content(std::string(std::istreambuf_iterator<char>(in), {}), a.type.c_str());
            if (p == "/" && req.has_param("token"))
                res.set_header("Set-Cookie", cookieName + "_" + std::to_string(m_port) + "=" + m_options.token +
                                                 "; Path=/; HttpOnly; SameSite=Strict");
        });
    }

    // The API. Errors: InputError 400, IoError 500 with the message.
    auto guarded = [](auto work) {
        return [work](const httplib::Request &req, httplib::Response &res) {
            try {
                work(req, res);
            } catch (const InputError &e) {
                sendText(res, 400, e.what());
            } catch (const IoError &e) {
                sendText(res, 500, e.what());
            } catch (const std::bad_alloc &) {
                sendText(res, 500, "error: out of memory");
            } catch (const std::exception &e) {
                sendText(res, 500, std::string("internal error: ") + e.what());
            }
        };
    };
    Studio *st = &studio;
    const char *bin = "application/octet-stream";
    const char *js = "application/json";
    srv.Get("/api/state", guarded([st, js](const auto &, auto &res) { res.set_content(st->stateJson(), js); }));
    // The mesh in pieces (chunked transfer), so the page draws it as it arrives.
    srv.Get("/api/mesh", guarded([st, bin](const auto &, auto &res) {
        auto bytes = std::make_shared<const std::string>(st->meshBinary());
        res.set_chunked_content_provider(bin, [bytes](size_t offset, httplib::DataSink &sink) {
            if (offset < bytes->size()) {
                const size_t n = std::min(kMeshChunkBytes, bytes->size() - offset);
                if (!sink.write(bytes->data() + offset, n)) return false;
            }
            if (offset + kMeshChunkBytes >= bytes->size()) sink.done();
            return true;
        });
    }));
    srv.Post("/api/pick", guarded([st, js](const auto &req, auto &res) { res.set_content(st->pick(req.body), js); }));
    srv.Get("/api/field", guarded([st, bin](const auto &, auto &res) { res.set_content(st->fieldBinary(), bin); }));
    srv.Get("/api/singularities",
            guarded([st, js](const auto &, auto &res) { res.set_content(st->singularitiesJson(), js); }));
    srv.Get("/api/separatrices",
            guarded([st, js](const auto &, auto &res) { res.set_content(st->separatricesJson(), js); }));
    srv.Post("/api/edit", guarded([st, bin](const auto &req, auto &res) { res.set_content(st->edit(req.body), bin); }));
    srv.Post("/api/undo", guarded([st, bin](const auto &, auto &res) { res.set_content(st->undo(), bin); }));
    srv.Post("/api/redo", guarded([st, bin](const auto &, auto &res) { res.set_content(st->redo(), bin); }));
    srv.Post("/api/preview", guarded([st](const auto &req, auto &res) {
        int size = 512;
        if (req.has_param("size")) {
            const std::string s = req.get_param_value("size");
            if (s.empty() || s.size() > 5 || !std::all_of(s.begin(), s.end(), ::isdigit))
                throw InputError(FileLoc{"request"}, "size must be a whole number of pixels", "e.g. ?size=512");
            size = std::stoi(s);
        }
        bool original = false;
        if (req.has_param("of")) {
            const std::string of = req.get_param_value("of");
            if (of != "current" && of != "original")
                throw InputError(FileLoc{"request"}, "unknown preview `of=" + of.substr(0, 40) + "`",
                                 "of=current (the default) or of=original (the field as the scene file gave it)");
            original = of == "original";
        }
        res.set_content(st->previewPng(size, original), "image/png");
    }));
    srv.Post("/api/save", guarded([st, js](const auto &req, auto &res) {
        std::string name;
        if (req.has_param("name")) name = req.get_param_value("name");
        const std::string path = st->save(name);
        std::string quoted = "\"";
        for (char c : path) {
            if (c == '"' || c == '\\') quoted += '\\';
            if (static_cast<unsigned char>(c) >= 0x20) quoted += c;
        }
        res.set_content("{\"path\": " + quoted + "\"}", js);
    }));

    srv.set_error_handler([](const httplib::Request &, httplib::Response &res) {
        if (res.body.empty()) {
            if (res.status == 404) sendText(res, 404, "error: no such page or API endpoint");
            else if (res.status == 413) sendText(res, 413, "error: request body too large");
            else if (res.status == 400) sendText(res, 400, "error: malformed request");
            else sendText(res, res.status, "error: HTTP " + std::to_string(res.status));
        }
    });
    srv.set_exception_handler([](const httplib::Request &, httplib::Response &res, std::exception_ptr) {
        sendText(res, 500, "internal error");
    });
}

StudioServer::~StudioServer() { stop(); }

int StudioServer::bind() {
    for (const auto &[urlPath, asset] : m_impl->assets)
        if (!std::filesystem::is_regular_file(asset.file))
            throw IoError(asset.file, "the studio's page file " + urlPath +
                                          " is missing; install libjs-three (tools/setup.sh) or set "
                                          "ROSY_STUDIO_WEB_DIR / ROSY_THREE_DIR");
    if (m_options.port == 0) {
        m_port = m_impl->server.bind_to_any_port(m_options.host);
        if (m_port <= 0) m_port = 0;
    } else if (m_impl->server.bind_to_port(m_options.host, m_options.port)) {
        m_port = m_options.port;
    }
    if (m_port == 0)
        throw IoError(m_options.host + ":" + std::to_string(m_options.port),
                      "cannot listen on this address; pick another --port (or free this one)");
    return m_port;
}

void StudioServer::run() { m_impl->server.listen_after_bind(); }

void StudioServer::start() {
    m_thread = std::thread([this] { run(); });
    while (!m_impl->server.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

void StudioServer::stop() {
    m_impl->server.stop();
    if (m_thread.joinable()) m_thread.join();
}

std::string StudioServer::url() const {
    const bool v6 = m_options.host.find(':') != std::string::npos;
    return "http://" + (v6 ? "[" + m_options.host + "]" : m_options.host) + ":" + std::to_string(m_port) +
           "/?token=" + m_options.token;
}

} // namespace rosy::studio
