#pragma once
/// \file studio_test_util.h
/// What the studio's C++ test programs share: reading the binary payloads and a
/// fixture that serves a scene on an ephemeral loopback port.

#include "studio/server.h"
#include "studio/studio.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

namespace rosy::test {

/// CGAL's head, the studio tests' mesh (extracted by tools/setup.sh).
inline const std::string kHead = std::string(ROSY_DATA_DIR) + "/meshes/head.off";

/// Little-endian uint32 / float32 at byte `at` of a payload.
inline uint32_t u32(const std::string &s, size_t at) {
    uint32_t v;
    std::memcpy(&v, s.data() + at, 4);
    return v;
}
inline float f32(const std::string &s, size_t at) {
    float v;
    std::memcpy(&v, s.data() + at, 4);
    return v;
}

/// A studio on `sceneText` (written as head.yaml in a fresh temporary folder named
/// after `prefix` and the running test), its server on an ephemeral port and a client
/// that sends the token. The folder is removed and the server stopped afterwards.
class StudioFixture : public ::testing::Test {
protected:
    void serve(const std::string &prefix, const std::string &sceneText, const studio::StudioOptions &options = {}) {
        dir = std::filesystem::temp_directory_path() /
              (prefix + std::to_string(::getpid()) + "-" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
        scenePath = (dir / "head.yaml").string();
        std::ofstream(scenePath) << sceneText;
        studio = std::make_unique<studio::Studio>(scenePath, options);
        server = std::make_unique<studio::StudioServer>(*studio, studio::ServerOptions{});
        port = server->bind();
        server->start();
        client = std::make_unique<httplib::Client>("127.0.0.1", port);
        client->set_default_headers({{"X-Rosy-Token", server->token()}});
    }
    void TearDown() override {
        if (server) server->stop();
        std::filesystem::remove_all(dir);
    }
    std::filesystem::path dir;
    std::string scenePath;
    std::unique_ptr<studio::Studio> studio;
    std::unique_ptr<studio::StudioServer> server;
    std::unique_ptr<httplib::Client> client;
    int port = 0;
};

} // namespace rosy::test
