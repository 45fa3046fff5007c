// shatter-mpm as a user meets it: the files it writes, the same bytes for the same seed,
// and errors that name the input and exit with 1.
#include "demos/mpm/MpmProgram.h"

#include <cairo.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

namespace shatter::mpm::demo {
namespace {

namespace fs = std::filesystem;

// A jello disk with a crack, falling onto the ground: a few hundred particles, a few
// substeps per frame (E = 50 Pa), so the whole run takes well under a second.
const char* kScene = R"({
  "grid": {"dx": 0.5, "ppc": 2, "jitter": 0.2},
  "time": {"end": 0.3, "frame": 0.1},
  "materials": {"jello": {"preset": "jello"}},
  "bodies": [{"shape": {"type": "circle", "center": [0, 3.2], "radius": 3}, "material": "jello"}],
  "cracks": [{"points": [[-1, 3.3], [1, 3.3]], "propagate": true}],
  "colliders": [{"type": "half_plane", "point": [0, 0], "normal": [0, 1]}]
})";

class MpmProgram : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("shatter_mpm_program_" + std::to_string(::getpid()) + "_" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        write("scene.json", kScene);
    }
    void TearDown() override { fs::remove_all(dir_); }

    void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
    static std::string read(const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        std::ostringstream s;
        s << in.rdbuf();
        return s.str();
    }
    int run(std::vector<std::string> args) {
        out_.str("");
        err_.str("");
        return runMpmProgram(args, out_, err_, false);
    }

    fs::path dir_;
    std::ostringstream out_, err_;
};

TEST_F(MpmProgram, WritesTipsParticlesCracksAndPictures) {
    const fs::path out = dir_ / "out";
    ASSERT_EQ(run({(dir_ / "scene.json").string(), "--out", out.string(), "--quiet"}), 0) << err_.str();
    EXPECT_TRUE(out_.str().empty()); // --quiet
    EXPECT_TRUE(err_.str().empty()); // no progress line when stderr is not a terminal
    const std::string tips = read(out / "tips.csv");
    EXPECT_EQ(tips.rfind("time,crack,tip,x,y,J,KI,KII,theta,grew\n", 0), 0u);
    // Frames 0..3, two tips each.
    EXPECT_EQ(std::count(tips.begin(), tips.end(), '\n'), 1 + 4 * 2);
    for (int f = 0; f <= 3; ++f) {
        const std::string n = std::to_string(f);
        EXPECT_TRUE(fs::exists(out / ("particles_000" + n + ".csv"))) << f;
        EXPECT_TRUE(fs::exists(out / ("cracks_000" + n + ".csv"))) << f;
        cairo_surface_t* png = cairo_image_surface_create_from_png((out / ("frame_000" + n + ".png")).string().c_str());
        EXPECT_EQ(cairo_surface_status(png), CAIRO_STATUS_SUCCESS) << f;
        EXPECT_EQ(cairo_image_surface_get_width(png), 1000);
        EXPECT_EQ(cairo_image_surface_get_height(png), 800);
        cairo_surface_destroy(png);
    }
    EXPECT_EQ(read(out / "particles_0000.csv").rfind("id,body,material,x,y,vx,vy,sxx,sxy,syy\n", 0), 0u);
    EXPECT_EQ(read(out / "cracks_0000.csv").rfind("crack,point,x,y,above_x,above_y,below_x,below_y\n", 0), 0u);
}

TEST_F(MpmProgram, SameSeedSameBytesOtherSeedOtherParticles) {
    const std::string scene = (dir_ / "scene.json").string();
    auto once = [&](const std::string& name, const std::string& seed) {
        EXPECT_EQ(run({scene, "--out", (dir_ / name).string(), "--quiet", "--seed", seed, "--png-every", "0"}), 0)
            << err_.str();
        return read(dir_ / name / "tips.csv") + read(dir_ / name / "particles_0003.csv");
    };
    const std::string a = once("a", "7"), b = once("b", "7"), c = once("c", "8");
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c); // the seed moves the jittered particles
}

TEST_F(MpmProgram, BadInputIsAnErrorNamingItWithExitCodeOne) {
    write("bad.json", R"({"grid": {"dx": -1}, "time": {"end": 1}, "materials": {}, "bodies": []})");
    EXPECT_EQ(run({(dir_ / "bad.json").string(), "--out", (dir_ / "o").string()}), 1);
    EXPECT_NE(err_.str().find("shatter-mpm: error: "), std::string::npos) << err_.str();
    EXPECT_NE(err_.str().find("bad.json: "), std::string::npos) << err_.str();
    EXPECT_TRUE(out_.str().empty());

    EXPECT_EQ(run({(dir_ / "missing.json").string()}), 1);
    EXPECT_NE(err_.str().find("missing.json: cannot open"), std::string::npos) << err_.str();

    EXPECT_EQ(run({(dir_ / "scene.json").string(), "--frames", "0"}), 1);
    EXPECT_NE(err_.str().find("shatter-mpm: error: "), std::string::npos) << err_.str();
    EXPECT_NE(err_.str().find("--frames"), std::string::npos) << err_.str();

    // Limits: the estimate and the option that raises the limit, before anything runs.
    EXPECT_EQ(run({(dir_ / "scene.json").string(), "--out", (dir_ / "o").string(), "--max-particles", "10"}), 1);
    EXPECT_NE(err_.str().find("particles at spacing"), std::string::npos) << err_.str();
    EXPECT_NE(err_.str().find("(raise it with --max-particles"), std::string::npos) << err_.str();
    EXPECT_FALSE(fs::exists(dir_ / "o"));
    EXPECT_EQ(run({(dir_ / "scene.json").string(), "--frames", "1000000", "--max-substeps", "1e5"}), 1);
    EXPECT_NE(err_.str().find("1e+06 frames"), std::string::npos) << err_.str();
    EXPECT_EQ(run({(dir_ / "scene.json").string(), "--max-memory", "-1"}), 1);
    EXPECT_NE(err_.str().find("--max-memory"), std::string::npos) << err_.str();
    EXPECT_EQ(run({(dir_ / "scene.json").string(), "--no-such-option"}), 1);
    EXPECT_EQ(run({"--help"}), 0);
}

} // namespace
} // namespace shatter::mpm::demo
