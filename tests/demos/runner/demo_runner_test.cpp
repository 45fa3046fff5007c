// The runner end to end, in-process: a small scene of plain Bullet bodies (and one Shatter
// body) is stepped, written and summarised into a temporary directory.
#include "demos/runner/DemoRunner.h"

#include "demos/runner/FrameWriter.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include "test_files.h"

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace shatter;
using namespace shatter::demo;
using shatter::demo::test::readObj;
using shatter::demo::test::readPng;
using shatter::demo::test::readText;
using shatter::demo::test::TempDir;
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

struct Result {
    int code = -1;
    std::string out, err;
};

Result runDemo(std::vector<std::string> args, const DemoRunner::Setup& setup) {
    DemoRunner runner("test", "A test scene.");
    std::ostringstream out, err;
    runner.setStreams(out, err);
    const int code = runner.run(std::move(args), setup);
    return {code, out.str(), err.str()};
}

std::vector<std::string> args(const TempDir& dir, std::vector<std::string> extra) {
    std::vector<std::string> a = {"--out", dir.path().string(), "--quiet"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
}

constexpr double kRadius = 0.5;

// A ball dropped from 3 m onto the ground; its x comes from the scene's seeded generator.
void ballScene(Scene& scene) {
    scene.addGround();
    const double x = std::uniform_real_distribution<double>(-1, 1)(scene.random());
    scene.addRigidBody(std::make_unique<btSphereShape>(btScalar(kRadius)), 1.0,
                       btTransform(btQuaternion::getIdentity(), btVector3(btScalar(x), 3, 0)), "ball");
}

Json readJson(const fs::path& path) { return Json::parse(readText(path)); }

// A summary without its wall-clock fields: what must repeat exactly.
Json withoutTimings(Json summary) {
    for (auto it = summary.begin(); it != summary.end();) it = it.key().rfind("ms_", 0) == 0 ? summary.erase(it) : ++it;
    return summary;
}

} // namespace

TEST(DemoRunner, BallFallsAndComesToRestOnTheGround) {
    TempDir dir;
    const Result r = runDemo(args(dir, {"--frames", "150"}), ballScene);
    ASSERT_EQ(r.code, 0) << r.err;
    const Json summary = readJson(dir.path() / "summary.json");
    ASSERT_EQ(summary["rigid_bodies"].size(), 1u);
    const Json& ball = summary["rigid_bodies"][0];
    EXPECT_EQ(ball["name"], "ball");
    EXPECT_DOUBLE_EQ(ball["mass"].get<double>(), 1.0);
    EXPECT_NEAR(ball["position"][1].get<double>(), kRadius, 0.02);
    EXPECT_NEAR(ball["linear_velocity"][1].get<double>(), 0.0, 0.05);

    // After one frame it has started to fall, by about g t²/2.
    const auto first = readText(dir.path() / "frame_0001.obj");
    const auto obj = readObj(dir.path() / "frame_0001.obj");
    ASSERT_EQ(obj.objects, (std::vector<std::string>{"ground", "ball"})); // in the order the scene added them
    double top = -1e9;
    std::istringstream lines(first);
    std::string line;
    int v = 0;
    while (std::getline(lines, line))
        if (line.rfind("v ", 0) == 0 && v++ >= obj.verticesPerObject[0]) {
            double x, y, z;
            std::sscanf(line.c_str(), "v %lf %lf %lf", &x, &y, &z);
            top = std::max(top, y);
        }
    EXPECT_LT(top, 3.0 + kRadius);
    EXPECT_GT(top, 3.0 + kRadius - 0.01);
}

TEST(DemoRunner, WritesOneObjPerFrameWithEveryObject) {
    TempDir dir;
    const Result r = runDemo(args(dir, {"--frames", "12"}), ballScene);
    ASSERT_EQ(r.code, 0) << r.err;
    const ShapeMesh ball = tessellate(btSphereShape(btScalar(kRadius)), "ball");
    for (int i = 1; i <= 12; ++i) {
        const fs::path path = dir.path() / frameFileName(i, 12, "obj");
        ASSERT_TRUE(fs::exists(path)) << path;
        const auto obj = readObj(path);
        EXPECT_EQ(obj.objects, (std::vector<std::string>{"ground", "ball"}));
        EXPECT_EQ(obj.vertices, int(ball.mesh.positions.size()) + 4);
        EXPECT_EQ(obj.faces, int(ball.mesh.faces.size()) + 1);
        EXPECT_EQ(obj.badIndices, 0);
        EXPECT_EQ(obj.shortFaces, 0);
        EXPECT_EQ(obj.badNumbers, 0);
    }
    EXPECT_FALSE(fs::exists(dir.path() / "frame_0013.obj"));
    EXPECT_FALSE(fs::exists(dir.path() / "frame_0000.obj"));
}

TEST(DemoRunner, SummaryHasEveryKeyAndTheSceneOwnKeys) {
    TempDir dir;
    const Result r = runDemo(args(dir, {"--frames", "7", "--fps", "30", "--substeps", "2", "--seed", "42"}),
                             [](Scene& scene) {
                                 ballScene(scene);
                                 scene.addSummary("drop_height", 3.0);
                                 scene.addSummary("notes", {{"kind", "ball"}});
                             });
    ASSERT_EQ(r.code, 0) << r.err;
    const Json s = readJson(dir.path() / "summary.json");
    for (const char* key : {"demo", "frames", "fps", "substeps", "seed", "ms_per_frame_median", "ms_per_frame_max",
                            "bodies", "rigid_bodies", "events", "drop_height", "notes"})
        EXPECT_TRUE(s.contains(key)) << key;
    EXPECT_EQ(s["demo"], "test");
    // One number per frame: its step time, the bodies there (the ball, not the ground), its events.
    EXPECT_EQ(s["ms_per_frame"].size(), 7u);
    EXPECT_EQ(s["bodies_per_frame"], Json::array({1, 1, 1, 1, 1, 1, 1}));
    EXPECT_EQ(s["events_per_frame"], Json::array({0, 0, 0, 0, 0, 0, 0}));
    EXPECT_EQ(s["frames"], 7);
    EXPECT_EQ(s["fps"], 30.0);
    EXPECT_EQ(s["substeps"], 2);
    EXPECT_EQ(s["seed"], 42u);
    EXPECT_TRUE(s["bodies"].is_array());
    EXPECT_TRUE(s["events"].is_object());
    EXPECT_GE(s["ms_per_frame_max"].get<double>(), s["ms_per_frame_median"].get<double>());
    EXPECT_GE(s["ms_per_frame_median"].get<double>(), 0.0);
    EXPECT_EQ(s["drop_height"], 3.0);
    EXPECT_EQ(s["notes"]["kind"], "ball");
}

TEST(DemoRunner, EmptySceneStillWritesEveryFile) {
    TempDir dir;
    const Result r = runDemo(args(dir, {"--frames", "2"}), [](Scene&) {});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(readObj(dir.path() / "frame_0002.obj").vertices, 0);
    EXPECT_EQ(readJson(dir.path() / "summary.json")["bodies"].size(), 0u);
    EXPECT_EQ(readPng(dir.path() / "final.png").width, 1280);
}

TEST(DemoRunner, SceneCannotOverwriteARunnerSummaryKey) {
    TempDir dir;
    const Result r = runDemo(args(dir, {"--frames", "1"}), [](Scene& scene) { scene.addSummary("frames", 3); });
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("'frames'"), std::string::npos) << r.err;
}

TEST(DemoRunner, FinalPictureHasTheDefaultSizeAndShowsTheScene) {
    TempDir dir;
    const Result r = runDemo(args(dir, {"--frames", "5"}), ballScene);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto image = readPng(dir.path() / "final.png");
    EXPECT_EQ(image.width, 1280);
    EXPECT_EQ(image.height, 720);
    EXPECT_GT(image.distinctColours(), 20);
    // The ball is framed in the middle of the image: the centre is not background.
    EXPECT_NE(image.at(640, 400), image.at(2, 60));
}

TEST(DemoRunner, PngOptionsSetTheSizeAndWriteEveryNthFrame) {
    TempDir dir;
    const Result r = runDemo(args(dir, {"--frames", "10", "--png-every", "5", "--png-size", "320x240"}), ballScene);
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* name : {"frame_0005.png", "frame_0010.png", "final.png"}) {
        const auto image = readPng(dir.path() / name);
        EXPECT_EQ(image.width, 320) << name;
        EXPECT_EQ(image.height, 240) << name;
    }
    EXPECT_FALSE(fs::exists(dir.path() / "frame_0001.png"));
    EXPECT_FALSE(fs::exists(dir.path() / "frame_0004.png"));
}

TEST(DemoRunner, SameSeedGivesIdenticalFramesAndSummary) {
    TempDir a, b, c;
    const auto run = [](const TempDir& dir, const char* seed) {
        return runDemo(args(dir, {"--frames", "30", "--seed", seed}), [](Scene& scene) {
            ballScene(scene);
            // A tumbling box makes the contact and rotation history non-trivial.
            scene.addRigidBody(std::make_unique<btBoxShape>(btVector3(0.3f, 0.2f, 0.4f)), 2.0,
                               btTransform(btQuaternion(btVector3(1, 1, 0).normalized(), 0.7f), btVector3(0.2f, 1.5f, 0.1f)),
                               "box");
        });
    };
    ASSERT_EQ(run(a, "7").code, 0);
    ASSERT_EQ(run(b, "7").code, 0);
    ASSERT_EQ(run(c, "8").code, 0);
    for (int i = 1; i <= 30; ++i) {
        const std::string name = frameFileName(i, 30, "obj");
        ASSERT_EQ(readText(a.path() / name), readText(b.path() / name)) << name;
    }
    EXPECT_EQ(withoutTimings(readJson(a.path() / "summary.json")), withoutTimings(readJson(b.path() / "summary.json")));
    EXPECT_NE(readText(a.path() / "frame_0030.obj"), readText(c.path() / "frame_0030.obj"));
}

TEST(DemoRunner, BadOptionValuesFailNamingTheOptionWithoutBuildingTheScene) {
    for (const auto& [option, value] : std::vector<std::pair<std::string, std::string>>{
             {"--frames", "0"}, {"--fps", "-1"}, {"--substeps", "0"}, {"--seed", "x"}, {"--png-size", "big"}}) {
        TempDir dir;
        bool built = false;
        const Result r = runDemo(args(dir, {option, value}), [&](Scene&) { built = true; });
        EXPECT_NE(r.code, 0) << option;
        EXPECT_NE(r.err.find("shatter-test: error: "), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
        EXPECT_FALSE(built);
        EXPECT_FALSE(fs::exists(dir.path() / "summary.json"));
    }
}

TEST(DemoRunner, UnknownOptionIsAnError) {
    TempDir dir;
    const Result r = runDemo(args(dir, {"--framez", "3"}), ballScene);
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.err.find("--framez"), std::string::npos) << r.err;
}

TEST(DemoRunner, HelpExitsZeroAndListsCommonAndDemoOptions) {
    DemoRunner runner("test", "A test scene.");
    std::string mesh;
    runner.cli().add_option("--mesh", mesh, "OBJ file to drop");
    std::ostringstream out, err;
    runner.setStreams(out, err);
    bool built = false;
    EXPECT_EQ(runner.run({"--help"}, [&](Scene&) { built = true; }), 0);
    EXPECT_FALSE(built);
    for (const char* option : {"--frames", "--fps", "--substeps", "--out", "--seed", "--quiet", "--png-every",
                               "--png-size", "--no-gltf", "--mesh", "A test scene."})
        EXPECT_NE(out.str().find(option), std::string::npos) << option;
    EXPECT_EQ(err.str(), "");
}

TEST(DemoRunner, DemoOptionsReachTheSetup) {
    TempDir dir;
    DemoRunner runner("test", "A test scene.");
    double height = 0;
    runner.cli().add_option("--height", height, "Drop height");
    std::ostringstream out, err;
    runner.setStreams(out, err);
    double seen = -1;
    const int code = runner.run(args(dir, {"--frames", "1", "--height", "2.5"}), [&](Scene&) { seen = height; });
    EXPECT_EQ(code, 0) << err.str();
    EXPECT_EQ(seen, 2.5);
}

TEST(DemoRunner, SetupErrorsArePrintedWithTheProgramNameAndExitOne) {
    TempDir dir;
    Result r = runDemo(args(dir, {}), [](Scene&) { throw InputError("door.obj:12: face index 40 out of range"); });
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shatter-test: error: door.obj:12: face index 40 out of range\n");

    r = runDemo(args(dir, {}), [](Scene&) { throw std::runtime_error("out of cheese"); });
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shatter-test: error: out of cheese\n");

    r = runDemo(args(dir, {}), [](Scene& scene) {
        scene.addRigidBody(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), 0), 0, btTransform::getIdentity(),
                           "slab");
    });
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("'slab'"), std::string::npos) << r.err;

    r = runDemo(args(dir, {}), [](Scene& scene) {
        scene.addRigidBody(std::make_unique<btSphereShape>(1), -2, btTransform::getIdentity(), "antiball");
    });
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("'antiball'"), std::string::npos) << r.err;
}

TEST(DemoRunner, ErrorsInFrameCallbacksAreCaughtToo) {
    TempDir dir;
    const Result r = runDemo(args(dir, {"--frames", "5"}), [](Scene& scene) {
        ballScene(scene);
        scene.onFrame([](const Frame& f) {
            if (f.index == 3) throw std::runtime_error("stop at 3");
        });
    });
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shatter-test: error: stop at 3\n");
}

TEST(DemoRunner, FrameCallbacksSeeEveryFrameInOrder) {
    TempDir dir;
    std::vector<int> indices;
    std::vector<double> times;
    const Result r = runDemo(args(dir, {"--frames", "6", "--fps", "30"}), [&](Scene& scene) {
        ballScene(scene);
        scene.onFrame([&](const Frame& f) {
            EXPECT_EQ(f.count, 6);
            indices.push_back(f.index);
            times.push_back(f.time);
        });
    });
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(indices, (std::vector<int>{1, 2, 3, 4, 5, 6}));
    EXPECT_NEAR(times.back(), 0.2, 1e-12);
}

TEST(DemoRunner, EachFrameTakesExactlyTheRequestedSubsteps) {
    // 25 fps with 3 substeps is a case where Bullet's float accumulator, given 1/fps as is,
    // takes 2 steps in some frame.
    for (const auto& [fps, substeps] : {std::pair{"60", 4}, std::pair{"25", 3}, std::pair{"29.97", 7}}) {
        TempDir dir;
        int internalSteps = 0, wrongFrames = 0;
        const Result r = runDemo(args(dir, {"--frames", "600", "--fps", fps, "--substeps", std::to_string(substeps)}),
                                 [&](Scene& scene) {
                                     scene.world().setInternalTickCallback(
                                         [](btDynamicsWorld* world, btScalar) { ++*static_cast<int*>(world->getWorldUserInfo()); },
                                         &internalSteps);
                                     scene.onFrame([&](const Frame& f) { wrongFrames += internalSteps != f.index * substeps; });
                                 });
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(internalSteps, 600 * substeps) << fps << " fps";
        EXPECT_EQ(wrongFrames, 0) << fps << " fps";
    }
}

TEST(DemoRunner, ReportSaysWhatWasWrittenAndWhere) {
    TempDir dir;
    const Result r = runDemo({"--out", dir.path().string(), "--frames", "10"}, ballScene);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string root = fs::absolute(dir.path()).lexically_normal().string();
    EXPECT_NE(r.out.find(root), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("10 OBJ files"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find((fs::path(root) / "summary.json").string()), std::string::npos) << r.out;
    EXPECT_NE(r.out.find((fs::path(root) / "final.png").string()), std::string::npos) << r.out;
    EXPECT_NE(r.out.find((fs::path(root) / "story.png").string()), std::string::npos) << r.out;
    EXPECT_NE(r.out.find((fs::path(root) / "scene.glb").string()), std::string::npos) << r.out;
    EXPECT_EQ(r.err, ""); // no progress line: the error stream is not a terminal

    const Result quiet = runDemo(args(dir, {"--frames", "2"}), ballScene);
    EXPECT_EQ(quiet.out, "");
    EXPECT_EQ(quiet.err, "");
}

TEST(DemoRunner, OutputDirectoryIsCreatedAndCleanedOfAnEarlierRunsFrames) {
    TempDir dir;
    const fs::path out = dir.path() / "nested" / "deeper";
    fs::create_directories(out);
    std::ofstream(out / "frame_0099.obj") << "old";
    std::ofstream(out / "frame_0099.png") << "old";
    std::ofstream(out / "notes.txt") << "mine";
    const Result r = runDemo({"--out", out.string(), "--frames", "3"}, ballScene);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(fs::exists(out / "frame_0099.obj"));
    EXPECT_FALSE(fs::exists(out / "frame_0099.png"));
    EXPECT_TRUE(fs::exists(out / "notes.txt"));
    EXPECT_TRUE(fs::exists(out / "frame_0003.obj"));
    EXPECT_NE(r.out.find("cleared 2 frame files"), std::string::npos) << r.out;

    const fs::path fresh = dir.path() / "a" / "b" / "c";
    EXPECT_EQ(runDemo({"--out", fresh.string(), "--frames", "1", "--quiet"}, ballScene).code, 0);
    EXPECT_TRUE(fs::exists(fresh / "frame_0001.obj"));
}

TEST(DemoRunner, OutputPathThatIsAFileIsAnErrorNamingIt) {
    TempDir dir;
    std::ofstream(dir.path() / "taken") << "x";
    const Result r = runDemo({"--out", (dir.path() / "taken").string(), "--frames", "1"}, ballScene);
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("taken"), std::string::npos) << r.err;
}

// /proc is a directory nobody, not even root, can create files in: the run must stop before
// building its scene, not after simulating it.
TEST(DemoRunner, OutputDirectoryThatCannotBeWrittenFailsBeforeTheSetup) {
    bool built = false;
    const Result r = runDemo({"--out", "/proc", "--frames", "1"}, [&](Scene&) { built = true; });
    EXPECT_EQ(r.code, 1);
    EXPECT_FALSE(built);
    EXPECT_NE(r.err.find("--out /proc: cannot write in the directory"), std::string::npos) << r.err;
}

TEST(DemoRunner, EveryRunWritesItsStoryAndSceneUnlessToldNot) {
    TempDir dir;
    Result r = runDemo(args(dir, {"--frames", "8", "--png-size", "320x180"}), ballScene);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(readPng(dir.path() / "story.png").width, 3 * 160);
    EXPECT_GT(fs::file_size(dir.path() / "scene.glb"), 100u);
    EXPECT_EQ(readText(dir.path() / "scene.glb").substr(0, 4), "glTF");

    r = runDemo(args(dir, {"--frames", "2", "--no-gltf"}), ballScene);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(fs::exists(dir.path() / "scene.glb")); // the earlier run's is gone too
    EXPECT_TRUE(fs::exists(dir.path() / "story.png"));
}

// Needs shatter::Plugin::addVisualBody and geometry::buildPhysicalMesh.
TEST(DemoRunner, ShatterBodyIsWrittenAndSummarised) {
    TempDir dir;
    const Result r = runDemo(args(dir, {"--frames", "120"}), [](Scene& scene) {
        scene.addGround();
        const std::vector<Eigen::Vector3d> corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                                                      {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
        const std::vector<std::vector<int>> faces = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                                     {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
        const auto mesh = geometry::buildPhysicalMesh("cube", corners, faces);
        scene.plugin().addVisualBody(mesh, BodySettings{}, btTransform(btQuaternion::getIdentity(), btVector3(0, 1, 0)));
    });
    ASSERT_EQ(r.code, 0) << r.err;
    const Json s = readJson(dir.path() / "summary.json");
    ASSERT_EQ(s["bodies"].size(), 1u);
    const Json& cube = s["bodies"][0];
    EXPECT_EQ(cube["name"], "cube");
    EXPECT_GE(cube["primitives"].get<int>(), 1);
    EXPECT_GE(cube["connections"].get<int>(), 0);
    EXPECT_NEAR(cube["mass"].get<double>(), 1000.0, 1.0); // 1 m³ at the default 1000 kg/m³
    EXPECT_NEAR(cube["position"][1].get<double>(), 0.5, 0.03); // resting on the ground
    for (const char* key : {"position", "linear_velocity", "angular_velocity"}) EXPECT_EQ(cube[key].size(), 3u);
    EXPECT_EQ(s["events"].value(toString(EventType::BodyAdded), 0), 1);

    const auto obj = readObj(dir.path() / "frame_0120.obj");
    ASSERT_EQ(obj.objects.size(), 2u);
    EXPECT_EQ(obj.objects[0], "cube");
    EXPECT_EQ(obj.verticesPerObject[0], 8);
    EXPECT_EQ(obj.facesPerObject[0], 6);
    EXPECT_EQ(obj.badIndices, 0);
}
