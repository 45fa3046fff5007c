// Replays every input that ever broke a loader (tests/fuzz/regressions/<loader>/), and the
// fuzzers' seeds (the demos' own files), through the fuzz targets' checks: in every build, no
// clang needed. A new finding of scripts/fuzz.sh goes into the regression folder with a name
// that says what it was; under scripts/sanitize.sh these run with ASan and UBSan.
#include "tests/fuzz/FuzzChecks.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace shatter::test {
namespace {

namespace fs = std::filesystem;

std::string readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// Every file in `folders` (below the source tree) through `check`; returns how many.
int replay(FuzzOutcome (*check)(const std::string&), std::initializer_list<const char*> folders, const char* extension = "") {
    int count = 0;
    for (const char* folder : folders)
        for (const auto& entry : fs::directory_iterator(fs::path(SHATTER_SOURCE_DIR) / folder)) {
            if (!entry.is_regular_file() || !entry.path().string().ends_with(extension)) continue;
            const FuzzOutcome outcome = check(readBytes(entry.path()));
            EXPECT_NE(outcome, FuzzOutcome::Bug) << entry.path().string() << ": " << outcomeName(outcome);
            ++count;
        }
    return count;
}

TEST(FuzzRegressions, ObjInputsGiveResultsOrInputErrors) {
    EXPECT_GE(replay(checkObjInput, {"tests/fuzz/regressions/obj", "demos/assets"}, ".obj"), 10);
}

TEST(FuzzRegressions, TetGenInputsGiveResultsOrInputErrors) {
    EXPECT_GE(replay(checkTetGenInput, {"tests/fuzz/regressions/tetgen", "tests/fuzz/seeds/tetgen"}), 13);
}

TEST(FuzzRegressions, SceneInputsGiveResultsOrInputErrors) {
    EXPECT_GE(replay(checkSceneInput, {"tests/fuzz/regressions/scene", "demos/scenes"}, ".json"), 9);
}

TEST(FuzzRegressions, FracturePatternInputsGiveResultsOrInputErrors) {
    EXPECT_GE(replay(checkPatternInput, {"tests/fuzz/regressions/pattern", "tests/fuzz/seeds/pattern"}, ".obj"), 2);
}

TEST(FuzzRegressions, SeedsAreAccepted) {
    // The seeds are good files: a check that refused them would fuzz only the error paths.
    for (const char* name : {"box_2x1x1", "two_tets_one_based", "second_order_zero_based", "inverted_order"})
        EXPECT_EQ(checkTetGenInput(readBytes(fs::path(SHATTER_SOURCE_DIR) / "tests/fuzz/seeds/tetgen" / (std::string(name) + ".tetgen"))),
                  FuzzOutcome::Accepted)
            << name;
    EXPECT_EQ(checkObjInput(readBytes(fs::path(SHATTER_SOURCE_DIR) / "demos/assets/chair.obj")), FuzzOutcome::Accepted);
    EXPECT_EQ(checkPatternInput(readBytes(fs::path(SHATTER_SOURCE_DIR) / "tests/fuzz/seeds/pattern/two_cells.obj")),
              FuzzOutcome::Accepted);
    EXPECT_EQ(checkSceneInput(readBytes(fs::path(SHATTER_SOURCE_DIR) / "demos/scenes/pull_test.json")), FuzzOutcome::Accepted);
}

} // namespace
} // namespace shatter::test
