/// \file remesh_cli_test.cpp
/// `rosyhatch remesh` through the executable: outputs, report, exit codes.

#include "../cli/cli_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace rosy::test {
namespace {

fs::path workDir(const std::string &name) {
    const fs::path dir = fs::path(ROSY_BINARY_DIR) / "tests" / "remesh" / "out" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

TEST(RemeshCli, SceneToObjWithReport) {
    const fs::path dir = workDir("scene");
    std::ofstream(dir / "torus.yaml") << "mesh: {primitive: torus, nu: 72, nv: 30}\nfield: {symmetry: 4}\n";
    const CliRun r = runRosyhatch(dir, "remesh torus.yaml -o torus.obj --edge 4% --report torus.json --quiet", "ok");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string obj = slurp(dir / "torus.obj");
    EXPECT_NE(obj.find("\nf "), std::string::npos);
    const nlohmann::json j = nlohmann::json::parse(slurp(dir / "torus.json"));
    EXPECT_EQ(j["method"], "position-field");
    EXPECT_EQ(j["options"]["symmetry"], 4);
    EXPECT_EQ(j["options"]["adaptive_scale"], 0.0);
    const auto &q = j["quality"];
    EXPECT_TRUE(q["topology"]["closed"].get<bool>());
    EXPECT_EQ(q["topology"]["euler_characteristic"], 0);
    // faces by sides add up, and the quad fraction is their share
    int sum = 0;
    for (const auto &[sides, n] : q["faces_by_sides"].items()) sum += n.get<int>();
    EXPECT_EQ(sum, q["faces"].get<int>());
    // (the JSON writer keeps 9 significant digits)
    EXPECT_NEAR(q["quad_fraction"].get<double>(), q["faces_by_sides"]["4"].get<double>() / q["faces"].get<double>(),
                1e-8);
    // every face line of the OBJ is counted in the report
    int faces = 0;
    for (size_t p = obj.find("\nf "); p != std::string::npos; p = obj.find("\nf ", p + 1)) ++faces;
    EXPECT_EQ(faces, q["faces"].get<int>());
}

TEST(RemeshCli, SixRosyToOffAndPly) {
    const fs::path dir = workDir("six");
    std::ofstream(dir / "s.yaml") << "mesh: {primitive: icosphere, subdivisions: 3}\n";
    for (const char *out : {"s.off", "s.ply"}) {
        const CliRun r = runRosyhatch(dir, std::string("remesh s.yaml -o ") + out + " --symmetry 6 --edge 8% --quiet",
                                      out);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_GT(fs::file_size(dir / out), 100u);
    }
    EXPECT_EQ(slurp(dir / "s.off").substr(0, 3), "OFF");
}

TEST(RemeshCli, RejectedInputExitsTwoAndWritesNothing) {
    const fs::path dir = workDir("bad");
    std::ofstream(dir / "s.yaml") << "mesh: {primitive: icosphere, subdivisions: 2}\n";
    struct Case {
        std::string args, message;
    } cases[] = {
        {"remesh s.yaml -o out.stl", "polygon mesh"},
        {"remesh s.yaml -o out.obj --symmetry 3", "N = 4"},
        {"remesh s.yaml -o out.obj --edge -1", "--edge"},
        {"remesh s.yaml -o out.obj --edge 0.01%", "--edge"},
        {"remesh s.yaml -o out.obj --edge abc", "--edge"},
        {"remesh s.yaml -o out.obj --separatrices maybe", "--separatrices"},
        {"remesh s.yaml -o out.obj --adaptive-scale 3", "--adaptive-scale"},
        {"remesh s.yaml -o out.obj --adaptive-scale -0.5", "--adaptive-scale"},
        {"remesh missing.off -o out.obj", "missing.off"},
    };
    int k = 0;
    for (const Case &c : cases) {
        const CliRun r = runRosyhatch(dir, c.args, "bad" + std::to_string(k++));
        EXPECT_EQ(r.exitCode, c.args.find("missing") != std::string::npos ? 3 : 2) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_FALSE(fs::exists(dir / "out.obj")) << c.args;
    }
}

} // namespace
} // namespace rosy::test
