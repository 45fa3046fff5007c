// The scene file: every key of the format is read, and bad input is refused with a message
// that names the file and the key path.
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/mpm/SceneFile.h>
#include <shatter/plugin/mpm/Solver2D.h>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>

namespace shatter::mpm {
namespace {

using nlohmann::json;

json validScene() {
    return json::parse(R"({
        "analysis": "plane_strain",
        "gravity": [0, -9.81],
        "grid": {"dx": 0.5, "ppc": 2, "kernel": "cubic", "jitter": 0.1},
        "time": {"end": 1.0, "frame": 0.05, "cfl": 0.3, "max_step": 0.001},
        "transfer": "pic",
        "materials": {
            "pmma": {"preset": "pmma"},
            "soft": {"model": "snow", "E": 1.4e5, "nu": 0.2, "rho": 400, "Kc": 10, "theta_c": 0.02, "theta_s": 0.005, "xi": 7}
        },
        "bodies": [
            {"shape": {"type": "rect", "min": [0, 0], "max": [10, 10]}, "material": "pmma", "velocity": [1, 0]},
            {"shape": {"type": "circle", "center": [5, 5], "radius": 1}, "material": "soft"},
            {"shape": {"type": "polygon", "points": [[12, 0], [14, 0], [13, 2]]}, "material": "soft"}
        ],
        "cracks": [{"points": [[2, 8], [4, 8]], "propagate": true, "tips": "both", "guide": [[5, 7]]}],
        "loads": [
            {"region": {"min": [-1, -1], "max": [11, 0.1]}, "traction": [0, -1e6], "ramp": 0.1},
            {"region": {"min": [9, 0], "max": [10, 10]}, "force": [1e6, 0]}
        ],
        "fixed": [{"min": [0, 0], "max": [1, 1]}],
        "colliders": [
            {"type": "half_plane", "point": [0, -1], "normal": [0, 1], "friction": 0.2},
            {"type": "box", "min": [20, 0], "max": [21, 1]},
            {"type": "circle", "center": [30, 0], "radius": 2}
        ],
        "damping": 5,
        "fracture": {"contour_radius": 2, "contour_segments": 16, "growth": 0.5, "mixity_tolerance": 0.02,
                     "speed_limit": 1, "filter": 1, "analysis_interval": 0.25},
        "seed": 42
    })");
}

TEST(SceneFile, ReadsEveryKey) {
    const Scene s = parseScene(validScene().dump(), "all.json");
    EXPECT_EQ(s.analysis, Analysis::PlaneStrain);
    EXPECT_EQ(s.gravity, Vec2(0, -9.81));
    EXPECT_EQ(s.grid.dx, 0.5);
    EXPECT_EQ(s.grid.ppc, 2);
    EXPECT_EQ(s.grid.jitter, 0.1);
    EXPECT_EQ(s.time.frame, 0.05);
    EXPECT_EQ(s.time.maxStep, 0.001);
    EXPECT_EQ(s.transfer, VelocityTransfer::Pic);
    ASSERT_EQ(s.materials.size(), 2u);
    EXPECT_EQ(s.materials[0].name, "pmma");
    EXPECT_EQ(s.materials[0].E, 2.94e9);
    EXPECT_EQ(s.materials[0].Kc, 1.2e6);
    EXPECT_EQ(s.materials[1].model, ConstitutiveModelType::Snow);
    EXPECT_EQ(s.materials[1].xi, 7);
    ASSERT_EQ(s.bodies.size(), 3u);
    EXPECT_EQ(s.bodies[1].material, 1);
    EXPECT_EQ(s.bodies[0].velocity, Vec2(1, 0));
    ASSERT_EQ(s.cracks.size(), 1u);
    EXPECT_TRUE(s.cracks[0].propagate);
    EXPECT_EQ(s.cracks[0].guide.size(), 1u);
    ASSERT_EQ(s.loads.size(), 2u);
    EXPECT_EQ(s.loads[0].kind, Load::Kind::Traction);
    EXPECT_EQ(s.loads[1].kind, Load::Kind::Force);
    EXPECT_EQ(s.loads[0].ramp, 0.1);
    EXPECT_EQ(s.fixed.size(), 1u);
    EXPECT_EQ(s.colliders.size(), 3u);
    EXPECT_EQ(s.colliders[0]->friction(), 0.2);
    EXPECT_EQ(s.damping, 5);
    EXPECT_EQ(s.fracture.contourSegments, 16);
    EXPECT_EQ(s.fracture.analysisCells, 0.25);
    EXPECT_EQ(s.seed, 42u);
}

TEST(SceneFile, MaterialPresetsAreTheSourcesTable) {
    // Table 1 of 001 (toughness read as Pa·√m, see Material.h).
    const auto snow = materialPreset("snow"), pmma = materialPreset("pmma"), glass = materialPreset("glass"),
               jello = materialPreset("jello");
    ASSERT_TRUE(snow && pmma && glass && jello);
    EXPECT_EQ(snow->E, 140e3);
    EXPECT_EQ(snow->nu, 0.2);
    EXPECT_EQ(snow->rho, 400);
    EXPECT_EQ(snow->model, ConstitutiveModelType::Snow);
    EXPECT_EQ(pmma->E, 2.94e9);
    EXPECT_EQ(pmma->rho, 1190);
    EXPECT_EQ(glass->E, 70e9);
    EXPECT_EQ(glass->nu, 0.22);
    EXPECT_EQ(glass->Kc, 0.75e6);
    EXPECT_EQ(jello->E, 50);
    EXPECT_EQ(jello->rho, 2);
    EXPECT_FALSE(materialPreset("steel"));
}

// Applies `edit` to the valid scene and expects an InputError containing `expected`.
void expectError(const std::function<void(json&)>& edit, const std::string& expected) {
    json j = validScene();
    edit(j);
    try {
        parseScene(j.dump(), "bad.json");
        ADD_FAILURE() << "no error; expected one naming " << expected;
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).rfind("bad.json: ", 0), 0u) << e.what();
    }
}

TEST(SceneFile, UnknownKeysAreRefusedWithTheirPath) {
    expectError([](json& j) { j["gravitty"] = {0, 0}; }, "gravitty: unknown key");
    expectError([](json& j) { j["bodies"][1]["shape"]["radiuss"] = 1; }, "bodies[1].shape.radiuss: unknown key");
    expectError([](json& j) { j["materials"]["pmma"]["youngs"] = 1; }, "materials.pmma.youngs: unknown key");
    expectError([](json& j) { j["cracks"][0]["tip"] = "end"; }, "cracks[0].tip: unknown key");
}

TEST(SceneFile, WrongTypesAreRefusedWithTheirPath) {
    expectError([](json& j) { j["grid"]["dx"] = "0.5"; }, "grid.dx: expected a number, got a string");
    expectError([](json& j) { j["bodies"][0]["velocity"] = {1, 2, 3}; }, "bodies[0].velocity: expected a list of two");
    expectError([](json& j) { j["cracks"][0]["propagate"] = 1; }, "cracks[0].propagate: expected true or false");
    expectError([](json& j) { j["grid"]["ppc"] = 2.5; }, "grid.ppc: expected an integer");
    expectError([](json& j) { j["bodies"] = json::object(); }, "bodies: expected a list");
    expectError([](json& j) { j["analysis"] = "plane"; }, "analysis: \"plane\" is not one of");
    expectError([](json& j) { j["bodies"][0]["shape"]["type"] = "square"; }, "bodies[0].shape.type");
}

TEST(SceneFile, MissingOrUnknownMaterialIsNamed) {
    expectError([](json& j) { j["bodies"][0]["material"] = "steel"; },
                "bodies[0].material: no material named \"steel\" (materials: pmma, soft)");
    expectError([](json& j) { j["bodies"][0].erase("material"); }, "bodies[0]: missing required key \"material\"");
    expectError([](json& j) { j["materials"]["soft"].erase("E"); }, "materials.soft: missing required key \"E\"");
    expectError([](json& j) { j.erase("materials"); }, "missing required key \"materials\"");
}

TEST(SceneFile, OutOfRangeValuesAreNamed) {
    expectError([](json& j) { j["grid"]["dx"] = 0; }, "grid.dx: must be > 0");
    expectError([](json& j) { j["grid"]["dx"] = -1; }, "grid.dx: must be > 0");
    expectError([](json& j) { j["materials"]["soft"]["E"] = 0; }, "materials.soft.E: must be > 0");
    expectError([](json& j) { j["materials"]["pmma"]["E"] = -5; }, "materials.pmma.E: must be > 0");
    expectError([](json& j) { j["materials"]["soft"]["nu"] = 0.5; }, "materials.soft.nu: must be below 0.5");
    expectError([](json& j) { j["materials"]["soft"]["rho"] = 0; }, "materials.soft.rho: must be > 0");
    expectError([](json& j) { j["bodies"][1]["shape"]["radius"] = 0; }, "bodies[1].shape.radius: must be > 0");
    expectError([](json& j) { j["grid"]["ppc"] = 0; }, "grid.ppc: must be an integer from 1 to 16");
    expectError([](json& j) { j["time"]["cfl"] = 2; }, "time.cfl: must be at most 1");
    expectError([](json& j) { j["loads"][0]["ramp"] = -1; }, "loads[0].ramp: must be >= 0");
    expectError([](json& j) { j["fracture"]["analysis_interval"] = -0.5; },
                "fracture.analysis_interval: must be >= 0");
}

TEST(SceneFile, BadGeometryIsNamed) {
    expectError([](json& j) { j["cracks"][0]["points"] = {{50, 50}, {60, 50}}; }, "cracks[0]: lies outside every body");
    expectError([](json& j) { j["cracks"][0]["points"] = {{-2, 5}, {2, 5}}; },
                "cracks[0].tips: the start tip (-2, 5) lies outside every body");
    expectError([](json& j) { j["cracks"][0]["points"] = {{2, 8}}; }, "cracks[0].points: needs at least 2 points");
    expectError([](json& j) { j["bodies"][2]["shape"]["points"] = {{12, 0}, {16, 0}, {16, 4}, {14, -1}}; },
                "bodies[2].shape.points: outline crosses itself");
    expectError([](json& j) { j["bodies"][0]["shape"]["max"] = {0, 10}; }, "bodies[0].shape: min must be below max");
    expectError([](json& j) { j["loads"][1].erase("force"); }, "loads[1]: needs exactly one of");
}

TEST(SceneFile, InvalidJsonAndMissingFilesAreNamed) {
    try {
        parseScene("{\"grid\": ", "broken.json");
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("broken.json: not valid JSON"), std::string::npos) << e.what();
    }
    EXPECT_THROW(loadScene("/nonexistent/scene.json"), InputError);
}

// The message of the InputError that parsing `text` throws ("" if none).
std::string parseError(const std::string& text) {
    try {
        parseScene(text, "raw.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(SceneFile, LibraryErrorsNameTheFileAndTheKeyWithInputEscaped) {
    // The JSON library reports a number beyond a double's range as out_of_range 406, with
    // neither file nor key: the reader names both.
    EXPECT_EQ(parseError(R"({"grid": {"dx": 1e400}})"), "raw.json: grid.dx: number overflow parsing '1e400'");
    EXPECT_EQ(parseError(R"({"bodies": [{"shape": {}}, {"velocity": [0, -1e999]}]})"),
              "raw.json: bodies[1].velocity[1]: number overflow parsing '-1e999'");
    EXPECT_EQ(parseError(R"([1, 2, 1e400])"), "raw.json: [2]: number overflow parsing '1e400'");
    // Syntax errors keep the library's position, with the bytes it quotes escaped.
    const std::string binary = parseError("{\"grid\": \xff\x1b[2J}");
    EXPECT_EQ(binary.rfind("raw.json: not valid JSON: parse error at line 1, column 10", 0), 0u) << binary;
    EXPECT_NE(binary.find("\\xFF"), std::string::npos) << binary;
    for (char c : binary) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << binary;
    EXPECT_EQ(binary.find("[json.exception"), std::string::npos) << binary;
    // Keys and values quoted back from the file are escaped too.
    json j = validScene();
    j["analysis"] = "\x1b[31mred";
    EXPECT_NE(parseError(j.dump()).find("analysis: \"\\x1B[31mred\" is not one of"), std::string::npos) << parseError(j.dump());
}

TEST(SceneFile, IntegersBeyondTheirTypeAreRefused) {
    expectError([](json& j) { j["seed"] = 18446744073709551615ull; }, "seed: integer too large");
    expectError([](json& j) { j["fracture"]["contour_segments"] = 4294967298ll; },
                "fracture.contour_segments: must be an even number from 2 to 4096");
}

TEST(SceneFile, RegionsThatHoldNothingAreNamedWhenTheSceneIsBuilt) {
    json j = validScene();
    j["loads"][0]["region"] = {{"min", {50, 50}}, {"max", {60, 60}}};
    const Scene s = parseScene(j.dump(), "empty.json");
    try {
        Solver2D solver(s);
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("empty.json: loads[0].region: contains no part"), std::string::npos)
            << e.what();
    }
}

TEST(SceneFile, ShippedScenesLoadAndSeed) {
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::string(SHATTER_SOURCE_DIR) + "/demos/scenes")) {
        if (entry.path().extension() != ".json") continue;
        SCOPED_TRACE(entry.path().string());
        const Scene scene = loadScene(entry.path().string());
        Solver2D solver(scene); // seeding, loads and cracks are checked here
        EXPECT_GT(solver.particles().size(), 1000u);
        ++count;
    }
    EXPECT_GE(count, 9);
}

} // namespace
} // namespace shatter::mpm
