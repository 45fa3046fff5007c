// The common options parse strictly: a bad value is refused with a message naming the
// option, never silently read as something else.
#include "demos/runner/RunOptions.h"

#include <gtest/gtest.h>

using namespace shatter::demo;

namespace {

// Parses `args` (after the program name) into fresh options; returns the error message or "".
std::string parse(std::vector<std::string> args, RunOptions& options) {
    CLI::App app("test", "shatter-test");
    addRunOptions(app, options);
    std::reverse(args.begin(), args.end());
    try {
        app.parse(args);
    } catch (const CLI::ParseError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(RunOptions, DefaultsAreTheDocumentedOnes) {
    RunOptions o;
    EXPECT_EQ(parse({}, o), "");
    EXPECT_EQ(o.frames, 240);
    EXPECT_EQ(o.fps, 60);
    EXPECT_EQ(o.substeps, 4);
    EXPECT_EQ(o.out, "");
    EXPECT_EQ(o.seed, 1u);
    EXPECT_FALSE(o.quiet);
    EXPECT_EQ(o.pngEvery, 0);
    EXPECT_EQ(o.pngWidth, 1280);
    EXPECT_EQ(o.pngHeight, 720);
    EXPECT_DOUBLE_EQ(o.substepSeconds(), 1.0 / 240);
}

TEST(RunOptions, ValidValuesAreRead) {
    RunOptions o;
    EXPECT_EQ(parse({"--frames", "010", "--fps", "29.97", "--substeps", "8", "--out", "x/y", "--seed",
                     "18446744073709551615", "--quiet", "--png-every", "5", "--png-size", "640x480"},
                    o),
              "");
    EXPECT_EQ(o.frames, 10); // decimal, not octal
    EXPECT_DOUBLE_EQ(o.fps, 29.97);
    EXPECT_EQ(o.substeps, 8);
    EXPECT_EQ(o.out, "x/y");
    EXPECT_EQ(o.seed, 18446744073709551615ull);
    EXPECT_TRUE(o.quiet);
    EXPECT_EQ(o.pngEvery, 5);
    EXPECT_EQ(o.pngWidth, 640);
    EXPECT_EQ(o.pngHeight, 480);
}

TEST(RunOptions, BadValuesAreRefusedNamingTheOption) {
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"--frames", "0"},     {"--frames", "-3"},      {"--frames", "2.5"},  {"--frames", "ten"},
        {"--frames", "99999999999"},                     {"--fps", "0"},       {"--fps", "-1"},
        {"--fps", "nan"},      {"--fps", "inf"},        {"--fps", "60fps"},   {"--substeps", "0"},
        {"--seed", "-1"},      {"--seed", "0x10"},      {"--seed", "18446744073709551616"},
        {"--png-every", "-1"}, {"--png-size", "1280"},  {"--png-size", "8x8"}, {"--png-size", "100000x720"},
    };
    for (const auto& [option, value] : bad) {
        RunOptions o;
        const std::string message = parse({option, value}, o);
        EXPECT_NE(message.find(option), std::string::npos) << option << " " << value << " gave: '" << message << "'";
        EXPECT_NE(message.find(value), std::string::npos) << message; // and shows what was wrong
    }
}
