// Loads on the outline do what the scene means (issue 20): a pressure pushes along the
// inward normal, `facing` keeps a load to the outline facing one way, and a region that
// catches outline facing different directions is reported, naming the load.
#include <shatter/plugin/mpm/SceneFile.h>
#include <shatter/plugin/mpm/Solver2D.h>

#include "TestScenes.h"

#include <gtest/gtest.h>

namespace shatter::mpm {
namespace {

// A 10 m × 10 m plate, 0.5 m cells.
Scene plateScene() {
    Scene s = test::baseScene(0.5, test::elastic(ConstitutiveModelType::LinearElastic, 1e6, 0.3, 1000));
    s.bodies.push_back(Body{Shape(RectShape{Vec2(0, 0), Vec2(10, 10)}), 0, Vec2::Zero()});
    return s;
}

Vec2 totalForce(const Solver2D& solver, size_t load) {
    Vec2 sum = Vec2::Zero();
    for (const Vec2& f : solver.state().loads.at(load).force) sum += f;
    return sum;
}

TEST(Loads, ABoxAroundTheTopEdgeThatReachesDownTheSidesIsReportedWithTheLengthPerDirection) {
    // The issue's case: a box reaching 3 cm below the top (here 0.25 m) also catches 0.25 m of
    // each side edge, where the traction acts as shear: the plate carries 10.5 m of load, not 10.
    Scene s = plateScene();
    s.loads.push_back(Load{.region = Box{Vec2(-1, 9.75), Vec2(11, 11)}, .value = Vec2(0, 1000)});
    const Solver2D solver(s);
    EXPECT_NEAR(totalForce(solver, 0).y(), 1000 * 10.5, 1e-6);
    ASSERT_EQ(solver.warnings().size(), 1u);
    const std::string& w = solver.warnings()[0];
    EXPECT_NE(w.find("loads[0].region: catches outline facing different directions"), std::string::npos) << w;
    EXPECT_NE(w.find("10 m facing +y"), std::string::npos) << w;
    EXPECT_NE(w.find("0.25 m facing +x"), std::string::npos) << w;
    EXPECT_NE(w.find("0.25 m facing -x"), std::string::npos) << w;
}

TEST(Loads, FacingLoadsOnlyTheEdgeMeant) {
    Scene s = plateScene();
    s.loads.push_back(Load{.region = Box{Vec2(-1, 9.75), Vec2(11, 11)}, .value = Vec2(0, 1000), .facing = Vec2(0, 1)});
    const Solver2D solver(s);
    EXPECT_TRUE(solver.warnings().empty());
    const Vec2 f = totalForce(solver, 0);
    EXPECT_NEAR(f.y(), 1000 * 10, 1e-6);
    EXPECT_EQ(f.x(), 0);
}

TEST(Loads, PressurePushesAlongTheInwardNormal) {
    // On the top edge alone: −p·n·length with n = +y. A negative pressure pulls.
    Scene s = plateScene();
    s.loads.push_back(Load{.region = Box{Vec2(-1, 9.9), Vec2(11, 11)}, .kind = Load::Kind::Pressure,
                           .pressure = 2000, .facing = Vec2(0, 1)});
    s.loads.push_back(Load{.region = Box{Vec2(-1, -1), Vec2(11, 0.1)}, .kind = Load::Kind::Pressure,
                           .pressure = -500, .facing = Vec2(0, -1)});
    const Solver2D solver(s);
    EXPECT_LT((totalForce(solver, 0) - Vec2(0, -2000 * 10)).norm(), 1e-6);
    EXPECT_LT((totalForce(solver, 1) - Vec2(0, -500 * 10)).norm(), 1e-6);
}

TEST(Loads, AUniformPressureOnAClosedOutlineHasNoResultantAndPointsInward) {
    // Either orientation of a polygon: the normal is outward all the same.
    for (const bool clockwise : {false, true}) {
        Scene s = test::baseScene(0.5, test::elastic(ConstitutiveModelType::LinearElastic, 1e6, 0.3, 1000));
        std::vector<Vec2> points{Vec2(0, 0), Vec2(8, 0), Vec2(8, 4), Vec2(4, 7), Vec2(0, 4)};
        if (clockwise) std::reverse(points.begin(), points.end());
        s.bodies.push_back(Body{Shape(PolygonShape{points}), 0, Vec2::Zero()});
        s.loads.push_back(Load{.region = Box{Vec2(-1, -1), Vec2(9, 8)}, .kind = Load::Kind::Pressure, .pressure = 1e3});
        const Solver2D solver(s);
        EXPECT_LT(totalForce(solver, 0).norm(), 1e-6) << clockwise;
        const auto& load = solver.state().loads[0];
        const Vec2 centre(4, 3);
        for (size_t k = 0; k < load.particle.size(); ++k)
            EXPECT_LT(load.force[k].dot(solver.particles().x0[load.particle[k]] - centre), 0) << k;
        EXPECT_EQ(solver.warnings().size(), 1u); // every direction is caught: reported
    }
}

TEST(Loads, PressureAndFacingAreReadFromTheSceneFileAndCheckedByName) {
    const std::string head = R"({"grid": {"dx": 0.5}, "time": {"end": 1},
        "materials": {"m": {"model": "linear_elastic", "E": 1e6, "nu": 0.3, "rho": 1000}},
        "bodies": [{"shape": {"type": "rect", "min": [0, 0], "max": [10, 10]}, "material": "m"}],
        "loads": [)";
    const Scene s = parseScene(head + R"({"region": {"min": [-1, 9.7], "max": [11, 11]}, "pressure": -1e3,
                                          "facing": [0, 2]}]})",
                               "p.json");
    ASSERT_EQ(s.loads.size(), 1u);
    EXPECT_EQ(s.loads[0].kind, Load::Kind::Pressure);
    EXPECT_EQ(s.loads[0].pressure, -1e3);
    EXPECT_EQ(s.loads[0].facing, Vec2(0, 1));
    auto error = [&](const std::string& load) {
        try {
            parseScene(head + load + "]}", "p.json");
        } catch (const std::exception& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(error(R"({"region": {"min": [0, 0], "max": [1, 1]}, "pressure": 1, "traction": [0, 1]})")
                  .find("loads[0]: needs exactly one of"),
              std::string::npos);
    EXPECT_NE(error(R"({"region": {"min": [0, 0], "max": [1, 1]}, "pressure": 1, "facing": [0, 0]})")
                  .find("loads[0].facing: must be a non-zero direction"),
              std::string::npos);
    EXPECT_NE(error(R"({"region": {"min": [0, 0], "max": [1, 1]}, "force": [0, 1], "facing": [0, 1]})")
                  .find("loads[0].facing: applies to traction and pressure loads"),
              std::string::npos);
}

} // namespace
} // namespace shatter::mpm
