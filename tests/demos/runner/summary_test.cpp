// Step-time statistics and the summary keys a scene may not overwrite.
#include "demos/runner/Summary.h"

#include <gtest/gtest.h>

using namespace shatter::demo;

TEST(DemoSummary, MedianAndMaxOfStepTimes) {
    EXPECT_EQ(StepTimes{}.median(), 0.0);
    EXPECT_EQ(StepTimes{}.max(), 0.0);
    EXPECT_EQ((StepTimes{{5, 1, 3}}).median(), 3.0);
    EXPECT_EQ((StepTimes{{4, 1, 3, 2}}).median(), 2.5);
    EXPECT_EQ((StepTimes{{4, 1, 9, 2}}).max(), 9.0);
}

TEST(DemoSummary, RunnerKeysAreReserved) {
    for (const char* key : {"demo", "frames", "fps", "substeps", "seed", "ms_per_frame_median", "ms_per_frame_max",
                            "bodies", "events"})
        EXPECT_TRUE(isReservedSummaryKey(key)) << key;
    EXPECT_FALSE(isReservedSummaryKey("fragments"));
}

TEST(DemoSummary, TextParsesBackToTheSameJsonWithVectorsOnOneLine) {
    nlohmann::ordered_json j = {{"demo", "drop"},
                                {"bodies", {{{"name", "a"}, {"position", {1.5, -2.0, 3.25}}}, {{"name", "b\xff"}}}},
                                {"events", nlohmann::ordered_json::object()},
                                {"empty", nlohmann::ordered_json::array()},
                                {"seed", 18446744073709551615ull}};
    const std::string text = summaryText(j);
    EXPECT_NE(text.find("\"position\": [1.5, -2.0, 3.25]"), std::string::npos) << text;
    EXPECT_EQ(text.back(), '\n');
    const auto back = nlohmann::ordered_json::parse(text);
    EXPECT_EQ(back["bodies"][0], j["bodies"][0]);
    EXPECT_EQ(back["seed"], j["seed"]);
    EXPECT_EQ(back["events"], j["events"]);
    EXPECT_EQ(back["empty"], j["empty"]);
    EXPECT_EQ(back["bodies"][1]["name"], "b\xef\xbf\xbd"); // invalid UTF-8 replaced, not thrown
}
