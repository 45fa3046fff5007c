#include "demos/runner/StoryBoard.h"

#include "demos/runner/PngCanvas.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace shatter::demo {

namespace {

constexpr int kColumns = 3;
constexpr int kTitleBand = 56;   // pixels above the grid for the run's title
constexpr int kCaptionBand = 30; // pixels at the top of each tile for its time

std::string tileCaption(int frame, double fps) {
    char text[64];
    std::snprintf(text, sizeof text, "t = %.2f s  (frame %d)", frame / fps, frame);
    return text;
}

} // namespace

std::optional<std::string> changeWords(EventType type) {
    switch (type) {
    case EventType::BodyAdded:
    case EventType::BodyRemoved:
    case EventType::JointAdded:
    case EventType::DebrisExpired:
    case EventType::JointRecreated: return std::nullopt; // follows a fracture, which says it
    case EventType::LinksBroken:
    case EventType::FragmentCreated:
    case EventType::BodyFractured: return "first break";
    case EventType::BodyDented: return "first dent";
    case EventType::JointBroken: return "a joint breaks";
    default: break;
    }
    std::string words = std::string("first ") + toString(type);
    std::replace(words.begin(), words.end(), '_', ' ');
    return words;
}

std::vector<int> storyFrames(int frameCount, std::optional<int> change) {
    const int count = std::min(frameCount, 2 * kColumns);
    std::vector<int> frames;
    for (int k = 0; k < count; ++k)
        frames.push_back(count == 1 ? frameCount : 1 + int(std::lround(double(k) * (frameCount - 1) / (count - 1))));
    if (change && *change >= 1 && *change <= frameCount &&
        std::find(frames.begin(), frames.end(), *change) == frames.end()) {
        // Replace the nearest frame, but keep the first and the last: the run's start and end.
        auto nearest = frames.end();
        for (auto it = frames.begin(); it != frames.end(); ++it) {
            const bool end = it == frames.begin() || it + 1 == frames.end();
            if (!end && (nearest == frames.end() || std::abs(*it - *change) < std::abs(*nearest - *change))) nearest = it;
        }
        if (nearest == frames.end()) nearest = std::abs(frames.front() - *change) < std::abs(frames.back() - *change) ? frames.begin() : frames.end() - 1;
        *nearest = *change;
        std::sort(frames.begin(), frames.end());
    }
    return frames;
}

void writeStory(const RunRecording& recording, double fps, const std::optional<FirstChange>& change,
                const Picture& picture, const std::filesystem::path& path) {
    const std::vector<int> frames = storyFrames(recording.frames(), change ? std::optional(change->frame) : std::nullopt);
    const int tileW = picture.width / 2, tileH = picture.height / 2;
    const int rows = (int(frames.size()) + kColumns - 1) / kColumns;
    std::vector<std::vector<NamedMesh>> moments;
    std::vector<Eigen::Vector3d> points;
    for (int frame : frames) {
        moments.push_back(recording.meshesAt(frame));
        const auto framing = framingPoints(moments.back());
        points.insert(points.end(), framing.begin(), framing.end());
    }
    // One camera for every tile, so that the pictures compare.
    const Camera camera = Camera::framing(points, tileW, tileH, kCaptionBand);
    PngCanvas canvas(kColumns * tileW, kTitleBand + rows * tileH);
    std::string floorScale;
    for (size_t i = 0; i < frames.size(); ++i) {
        const int x = int(i % kColumns) * tileW, y = kTitleBand + int(i / kColumns) * tileH;
        const SceneImage scene = renderScene(moments[i], camera, tileW, tileH);
        if (floorScale.empty()) floorScale = scene.floorScale;
        canvas.paste(scene, x, y);
        canvas.titleLine(x + 14, y + 22, "", tileCaption(frames[i], fps), 20);
        if (change && change->frame == frames[i]) {
            canvas.accentFrame(x, y, tileW, tileH, 4);
            canvas.accentText(x + 14, y + tileH - 14, change->what, 16);
        }
    }
    std::string caption = picture.caption;
    if (!floorScale.empty()) caption += (caption.empty() ? "" : "  ·  ") + floorScale;
    canvas.titleLine(24, 36, picture.title, caption);
    canvas.write(path);
}

} // namespace shatter::demo
