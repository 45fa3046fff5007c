// The progress line redraws in place and ends with a newline; disabled, it writes nothing.
#include "demos/runner/ProgressLine.h"

#include <gtest/gtest.h>

#include <sstream>

using namespace shatter::demo;

TEST(ProgressLine, RedrawsInPlaceAndEndsTheLine) {
    std::ostringstream s;
    ProgressLine line(s, "shatter-drop", 3, true);
    line.update(1, 2.0);
    line.update(2, 2.0); // within 100 ms of the first: skipped
    line.update(3, 5.0); // the last frame is always drawn
    line.finish();
    const std::string text = s.str();
    EXPECT_EQ(text.rfind("\rshatter-drop: frame 1/3  2.0 ms/frame", 0), 0u) << text;
    EXPECT_NE(text.find("\rshatter-drop: frame 3/3  3.5 ms/frame"), std::string::npos) << text; // mean since last draw
    EXPECT_EQ(text.find("frame 2/3"), std::string::npos) << text;
    EXPECT_EQ(text.back(), '\n');
}

TEST(ProgressLine, DisabledWritesNothing) {
    std::ostringstream s;
    ProgressLine line(s, "shatter-drop", 3, false);
    line.update(1, 1.0);
    line.update(3, 1.0);
    line.finish();
    EXPECT_EQ(s.str(), "");
}
