#pragma once
// Per-frame times by phase, and their distribution: what a benchmark reports about frames
// (median, 99th percentile, worst), since a game runs at the pace of its worst frames.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace shatter::bench {

// Frame times (ms) by phase, in the order phases were first added; any numeric per-frame
// counts ride along (pieces, contacts, ...). One row per frame.
class FrameTable {
public:
    void beginFrame();
    // Adds to this frame's value of `phase` (ms) or of `count`.
    void addTime(const std::string& phase, double ms);
    void setCount(const std::string& name, double value);

    int frames() const { return int(rows_.size()); }
    const std::vector<std::string>& phases() const { return phases_; }
    double time(int frame, const std::string& phase) const;
    double total(int frame) const; // the sum of its phases
    double count(int frame, const std::string& name) const;

    // CSV: frame, total_ms, each phase's ms, each count.
    void writeCsv(const std::string& path) const;
    // {"frame": {median_ms, p99_ms, worst_ms, worst_frame, over_16_7_ms, over_33_3_ms}, phase: {...}}
    nlohmann::ordered_json summary() const;

private:
    struct Row {
        std::vector<double> times;  // by phase index
        std::vector<double> counts; // by count index
    };
    int indexOf(std::vector<std::string>& names, const std::string& name);
    std::vector<std::string> phases_, counts_;
    std::vector<Row> rows_;
};

// Median and nearest-rank percentile (q in [0, 1]) of a list.
double percentile(std::vector<double> values, double q);

// A PNG of the frame times stacked by phase, one bar per frame, with the 16.7 and 33.3 ms
// lines; the y axis ends at the worst frame (or 40 ms). Throws shatter::InputError naming
// the file when it cannot be written.
void plotFrames(const FrameTable& table, const std::string& title, const std::string& path);

} // namespace shatter::bench
