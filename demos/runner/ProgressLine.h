#pragma once
// The `\r`-updated status line a person sees while a demo runs in a terminal:
//   shatter-drop: frame 120/240  3.1 ms/frame
#include <chrono>
#include <ostream>
#include <string>

namespace shatter::demo {

class ProgressLine {
public:
    // `enabled` is false when the stream is not a terminal (a log file must not fill with
    // carriage returns) or the user asked for quiet; every call is then a no-op.
    ProgressLine(std::ostream& stream, std::string program, int frameCount, bool enabled);
    // Ends the line, so an error thrown mid-run is not printed on top of it.
    ~ProgressLine() { finish(); }
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    // After frame `index` (1-based) whose step took `stepMs`. Redraws at most ten times a
    // second, and always for the last frame.
    void update(int index, double stepMs);
    // Ends the line so later output starts on a fresh one.
    void finish();

    // True when standard error is a terminal.
    static bool stderrIsTerminal();

private:
    std::ostream& stream_;
    std::string program_;
    int frameCount_;
    bool enabled_;
    bool drawn_ = false;
    double pendingMs_ = 0; // step time since the last redraw
    int pendingFrames_ = 0;
    std::chrono::steady_clock::time_point lastDraw_{};
};

} // namespace shatter::demo
