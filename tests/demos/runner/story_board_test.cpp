// story.png: six moments, the first change among them, drawn from the recording.
#include "demos/runner/StoryBoard.h"

#include "test_files.h"

#include <gtest/gtest.h>

using namespace shatter;
using namespace shatter::demo;

TEST(StoryBoard, SixFramesFromFirstToLastWithTheChangeAmongThem) {
    EXPECT_EQ(storyFrames(240, std::nullopt), (std::vector<int>{1, 49, 97, 144, 192, 240}));
    EXPECT_EQ(storyFrames(240, 3), (std::vector<int>{1, 3, 97, 144, 192, 240}));
    EXPECT_EQ(storyFrames(240, 150), (std::vector<int>{1, 49, 97, 150, 192, 240}));
    EXPECT_EQ(storyFrames(240, 97), (std::vector<int>{1, 49, 97, 144, 192, 240}));
    // A change in the last frame keeps it; the nearest inner frame goes.
    EXPECT_EQ(storyFrames(240, 239), (std::vector<int>{1, 49, 97, 144, 239, 240}));
    EXPECT_EQ(storyFrames(4, 2), (std::vector<int>{1, 2, 3, 4}));
    EXPECT_EQ(storyFrames(1, 1), (std::vector<int>{1}));
}

TEST(StoryBoard, BreaksAndDentsAreChangesBookkeepingIsNot) {
    EXPECT_EQ(changeWords(EventType::FragmentCreated), "first break");
    EXPECT_EQ(changeWords(EventType::LinksBroken), "first break");
    EXPECT_EQ(changeWords(EventType::BodyFractured), "first break");
    EXPECT_EQ(changeWords(EventType::BodyDented), "first dent");
    EXPECT_FALSE(changeWords(EventType::JointRecreated));
    EXPECT_FALSE(changeWords(EventType::BodyAdded));
    EXPECT_FALSE(changeWords(EventType::JointAdded));
    EXPECT_FALSE(changeWords(EventType::BodyRemoved));
}

TEST(StoryBoard, PictureIsAGridOfSixTilesUnderTheTitle) {
    test::TempDir dir;
    RunRecording recording;
    for (int f = 1; f <= 10; ++f) {
        NamedMesh box;
        box.name = "box";
        box.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
        box.mesh.faces = {{0, 1, 2, 3}};
        recording.add(f, {box});
    }
    writeStory(recording, 60, FirstChange{4, "first break"}, Picture{640, 360, "shatter-test", "caption"},
               dir.path() / "story.png");
    const auto image = test::readPng(dir.path() / "story.png");
    EXPECT_EQ(image.width, 3 * 320);
    EXPECT_EQ(image.height, 56 + 2 * 180);
    // The marked tile (frame 4, the second) has the accent frame: red at its left edge.
    const unsigned edge = image.at(320 + 1, 56 + 90);
    EXPECT_GT(int(edge >> 16 & 255), 150);
    EXPECT_LT(int(edge >> 8 & 255), 80);
    EXPECT_NE(image.at(1, 56 + 90), edge); // the unmarked first tile has none
}
