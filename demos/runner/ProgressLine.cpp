#include "demos/runner/ProgressLine.h"

#include <cstdio>
#include <unistd.h>

namespace shatter::demo {

ProgressLine::ProgressLine(std::ostream& stream, std::string program, int frameCount, bool enabled)
    : stream_(stream), program_(std::move(program)), frameCount_(frameCount), enabled_(enabled) {}

void ProgressLine::update(int index, double stepMs) {
    if (!enabled_) return;
    pendingMs_ += stepMs;
    ++pendingFrames_;
    const auto now = std::chrono::steady_clock::now();
    if (drawn_ && index < frameCount_ && now - lastDraw_ < std::chrono::milliseconds(100)) return;
    char text[160];
    // Trailing spaces wipe what a longer previous line left behind.
    const double ms = pendingMs_ / pendingFrames_;
    std::snprintf(text, sizeof text, ms < 1 ? "\r%s: frame %d/%d  %.2f ms/frame   " : "\r%s: frame %d/%d  %.1f ms/frame   ",
                  program_.c_str(), index, frameCount_, ms);
    stream_ << text << std::flush;
    drawn_ = true;
    lastDraw_ = now;
    pendingMs_ = 0;
    pendingFrames_ = 0;
}

void ProgressLine::finish() {
    if (enabled_ && drawn_) stream_ << '\n' << std::flush;
    drawn_ = false;
}

bool ProgressLine::stderrIsTerminal() { return isatty(STDERR_FILENO) == 1; }

} // namespace shatter::demo
