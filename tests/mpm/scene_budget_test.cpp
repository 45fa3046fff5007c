// Limits stated up front: a scene's cost is estimated from the scene alone, a scene beyond a
// limit is refused before anything is allocated, with the estimate and the option that raises
// the limit, and physically absurd values are refused naming the key.
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/mpm/SceneBudget.h>
#include <shatter/plugin/mpm/SceneFile.h>
#include <shatter/plugin/mpm/Solver2D.h>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace shatter::mpm {
namespace {

using nlohmann::json;

// A 20 m x 10 m PMMA plate, dx 0.5 m, ppc 2: 3200 particles.
json plate() {
    return json::parse(R"({
        "gravity": [0, 0],
        "grid": {"dx": 0.5, "ppc": 2},
        "time": {"end": 0.01, "frame": 0.001},
        "materials": {"pmma": {"preset": "pmma"}},
        "bodies": [{"shape": {"type": "rect", "min": [0, 0], "max": [20, 10]}, "material": "pmma"}]
    })");
}

// The message of the InputError that reading `j`, estimating it and building a solver within
// `limits` throws ("" if none).
std::string refusal(const json& j, const SceneLimits& limits = {}) {
    try {
        const Scene scene = parseScene(j.dump(), "s.json");
        checkSceneLimits(scene, estimateScene(scene), limits);
        Solver2D solver(scene, limits);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(SceneBudget, EstimatesMatchWhatTheSolverBuilds) {
    json j = plate();
    j["bodies"].push_back(json::parse(R"({"shape": {"type": "circle", "center": [30, 5], "radius": 2}, "material": "pmma"})"));
    const Scene scene = parseScene(j.dump(), "s.json");
    const SceneEstimate e = estimateScene(scene);
    Solver2D solver(scene);
    // Areas over the spacing²: exact for the plate, π r²/h² for the disc (lattice count within
    // its perimeter in sites: 2π r/h = 50).
    EXPECT_NEAR(e.particles, double(solver.particles().size()), 50);
    EXPECT_NEAR(e.particles, 3200 + M_PI * 4 / 0.0625, 1e-9);
    // The CFL step at rest: cfl·dx / the dilatational wave speed (plane stress: √(E/(ρ(1−ν²)))),
    // which is the solver's first step.
    const Material pmma = *materialPreset("pmma");
    const double c = std::sqrt(pmma.E / (pmma.rho * (1 - pmma.nu * pmma.nu)));
    EXPECT_NEAR(e.firstStep, 0.4 * 0.5 / c, 1e-12 * e.firstStep);
    EXPECT_NEAR(solver.stableTimeStep(), e.firstStep, 1e-12 * e.firstStep);
    EXPECT_NEAR(e.substeps, 0.01 / e.firstStep, 1e-6);
    EXPECT_NEAR(e.frames, 10, 1e-9);
    // Nodes over the bodies' box (32 m x 10 m in 0.5 m cells) with 3 cells of padding.
    EXPECT_NEAR(e.gridNodes, (64 + 7) * (20 + 7), 1e-9);
}

TEST(SceneBudget, EachLimitNamesTheEstimateAndItsOption) {
    SceneLimits tight;
    tight.maxParticles = 3000;
    EXPECT_NE(refusal(plate(), tight).find("s.json: the bodies hold about 3.2e+03 particles at spacing 0.25 m"), std::string::npos)
        << refusal(plate(), tight);
    EXPECT_NE(refusal(plate(), tight).find("--max-particles"), std::string::npos);
    tight = {};
    tight.maxSubsteps = 50; // the plate needs 10 frames and 0.01 s / 1.21e-4 s = 82.4 substeps
    EXPECT_NE(refusal(plate(), tight).find("about 82.4 substeps, more than the limit of 50 (raise it with --max-substeps"),
              std::string::npos)
        << refusal(plate(), tight);
    tight.maxSubsteps = 5;
    EXPECT_NE(refusal(plate(), tight).find("time.end / time.frame is 10 frames"), std::string::npos) << refusal(plate(), tight);
    tight = {};
    tight.maxMemory = 1e5;
    EXPECT_NE(refusal(plate(), tight).find("the scene needs about 0.00104 GB (3.2e+03 particles"), std::string::npos)
        << refusal(plate(), tight);
    EXPECT_NE(refusal(plate(), tight).find("--max-memory"), std::string::npos);
    tight = {};
    tight.maxParticleSteps = 2e5; // 3200 particles × 82.4 substeps = 2.64e5
    EXPECT_NE(refusal(plate(), tight).find("about 3.2e+03 particles for about 82.4 substeps are 2.64e+05 particle-steps, "
                                           "about 1.46e-05 hours on one core: more than the limit of 2e+05 (raise it "
                                           "with --max-particle-steps"),
              std::string::npos)
        << refusal(plate(), tight);
    EXPECT_EQ(refusal(plate()), "");
}

TEST(SceneBudget, HostileScenesAreRefusedBeforeTheyRun) {
    struct Case {
        const char* what;
        std::function<void(json&)> edit;
        std::string expected;
    };
    const std::vector<Case> cases = {
        {"10^7 particles", [](json& j) { j["grid"]["dx"] = 0.005; }, "about 3.2e+07 particles"},
        {"dx 1e-9 on a 100 m body", [](json& j) { j["grid"]["dx"] = 1e-9; j["bodies"][0]["shape"]["max"] = {100, 1}; },
         "materials.pmma: E = 2.94e+09 Pa and rho = 1.19e+03 kg/m^3 give a wave speed of 1.65e+03 m/s: with grid.dx = "
         "1e-09 m the CFL step is 2.43e-13 s, below the limit of 1e-12 s"},
        {"E = 1e300", [](json& j) { j["materials"]["pmma"]["E"] = 1e300; }, "the CFL step is"},
        {"rho = 1e-300", [](json& j) { j["materials"]["pmma"]["rho"] = 1e-300; }, "below the limit of 1e-12 s"},
        {"nu = 0.4999999 in plane strain", [](json& j) { j["analysis"] = "plane_strain"; j["materials"]["pmma"]["nu"] = 0.4999999; },
         "materials.pmma.nu: must be below 0.5 - 1e-6 in plane strain (nearly incompressible: the wave speed and the "
         "substep count grow without bound), got 0.4999999"},
        {"time.end 1e6 with a tiny frame", [](json& j) { j["time"]["end"] = 1e6; j["time"]["frame"] = 1e-5; },
         "time.end / time.frame is 1e+11 frames"},
        {"time.end 1e12 with 1 ms frames", [](json& j) { j["time"]["end"] = 1e12; }, "time.end / time.frame is 1e+15 frames"},
        {"time.end 1e4 in one frame", [](json& j) { j["time"]["end"] = 1e4; j["time"]["frame"] = 1e4; },
         "a run of 1e+04 s (time.end) in CFL steps of 0.000121 s is about 8.24e+07 substeps"},
        {"a crack 1e8 m long", [](json& j) { j["cracks"] = json::parse(R"([{"points": [[1, 5], [1e8, 5]], "tips": "start"}])"); },
         "the cracks would be cut into about 4e+08 points"},
        {"a crack of points 1e-6 m apart",
         [](json& j) {
             json points = json::array();
             for (int i = 0; i < 1000; ++i) points.push_back({5 + i * 1e-6, 5});
             j["cracks"] = {{{"points", points}}};
         },
         "cracks[0].points: points 0 and 1 are"},
        {"a body at 1e30 m/s", [](json& j) { j["bodies"][0]["velocity"] = {1e30, 0}; },
         "bodies[0].velocity: speed 1e+30 m/s is above the limit of 10000 m/s"},
        {"a body 1e300 m wide", [](json& j) { j["bodies"][0]["shape"]["max"] = {1e300, 10}; }, "particles at spacing"},
        {"2e6 particles for 2e5 substeps: a day", [](json& j) { j["grid"]["dx"] = 0.02; j["time"]["end"] = 1; j["time"]["frame"] = 0.01; },
         "2e+06 particles for about 2.06e+05 substeps are 4.12e+11 particle-steps, about 22.9 hours"},
    };
    for (const Case& c : cases) {
        json j = plate();
        c.edit(j);
        const std::string message = refusal(j);
        EXPECT_NE(message.find(c.expected), std::string::npos) << c.what << ": " << message;
        EXPECT_EQ(message.rfind("s.json: ", 0), 0u) << c.what << ": " << message;
    }
}

} // namespace
} // namespace shatter::mpm
