#pragma once
// story.png: six moments of a run in a 3×2 grid, each with its time, all seen through one
// camera, one of them the moment something first broke, dented or tore (framed and named),
// so a single picture tells what happened.
#include "demos/runner/PngRenderer.h"
#include "demos/runner/RunRecording.h"

#include <shatter/bullet_ext/Events.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace shatter::demo {

// The first frame in which an event changed a body (a break, a dent, a tear, a fracture),
// and what it was in words ("first break").
struct FirstChange {
    int frame = 0;
    std::string what;
};

// What an event means for the story: words for an event that changes a body ("first break",
// "first dent"), nothing for bookkeeping (bodies or joints added, removed, expired). An event
// type added later counts as a change, named after its type.
std::optional<std::string> changeWords(EventType type);

// Six frames (all of them when the run has fewer), evenly spread from the first to the last,
// the one nearest `change` replaced by it; ascending and distinct.
std::vector<int> storyFrames(int frameCount, std::optional<int> change);

// Draws those frames of `recording` (each tile half the picture's width and height) under the
// picture's title and writes the PNG. Throws std::runtime_error naming the file when it cannot
// be written.
void writeStory(const RunRecording& recording, double fps, const std::optional<FirstChange>& change,
                const Picture& picture, const std::filesystem::path& path);

} // namespace shatter::demo
