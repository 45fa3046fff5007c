#include "demos/bench/FrameStats.h"

#include <shatter/plugin/common/InputError.h>

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

namespace shatter::bench {

int FrameTable::indexOf(std::vector<std::string>& names, const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) return int(it - names.begin());
    names.push_back(name);
    return int(names.size()) - 1;
}

void FrameTable::beginFrame() { rows_.emplace_back(); }

void FrameTable::addTime(const std::string& phase, double ms) {
    const int i = indexOf(phases_, phase);
    Row& row = rows_.back();
    if (int(row.times.size()) <= i) row.times.resize(size_t(i) + 1, 0.0);
    row.times[i] += ms;
}

void FrameTable::setCount(const std::string& name, double value) {
    const int i = indexOf(counts_, name);
    Row& row = rows_.back();
    if (int(row.counts.size()) <= i) row.counts.resize(size_t(i) + 1, 0.0);
    row.counts[i] = value;
}

double FrameTable::time(int frame, const std::string& phase) const {
    const auto it = std::find(phases_.begin(), phases_.end(), phase);
    const size_t i = size_t(it - phases_.begin());
    const Row& row = rows_[size_t(frame)];
    return i < row.times.size() ? row.times[i] : 0.0;
}

double FrameTable::total(int frame) const {
    double sum = 0.0;
    for (double t : rows_[size_t(frame)].times) sum += t;
    return sum;
}

double FrameTable::count(int frame, const std::string& name) const {
    const auto it = std::find(counts_.begin(), counts_.end(), name);
    const size_t i = size_t(it - counts_.begin());
    const Row& row = rows_[size_t(frame)];
    return i < row.counts.size() ? row.counts[i] : 0.0;
}

void FrameTable::writeCsv(const std::string& path) const {
    std::ofstream out(path);
    if (!out) throw InputError(path + ": cannot write the frame table");
    out << "frame,total_ms";
    for (const auto& p : phases_) out << "," << p << "_ms";
    for (const auto& c : counts_) out << "," << c;
    out << "\n";
    char buffer[64];
    for (int f = 0; f < frames(); ++f) {
        std::snprintf(buffer, sizeof buffer, "%d,%.4f", f + 1, total(f));
        out << buffer;
        for (const auto& p : phases_) {
            std::snprintf(buffer, sizeof buffer, ",%.4f", time(f, p));
            out << buffer;
        }
        for (const auto& c : counts_) {
            std::snprintf(buffer, sizeof buffer, ",%.6g", count(f, c));
            out << buffer;
        }
        out << "\n";
    }
}

double percentile(std::vector<double> values, double q) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    if (q == 0.5 && values.size() % 2 == 0) return 0.5 * (values[values.size() / 2 - 1] + values[values.size() / 2]);
    const size_t rank = size_t(std::ceil(q * double(values.size())));
    return values[std::min(values.size() - 1, rank == 0 ? 0 : rank - 1)];
}

nlohmann::ordered_json FrameTable::summary() const {
    auto stats = [&](auto valueOf) {
        std::vector<double> v;
        int worstFrame = 0, over16 = 0, over33 = 0;
        for (int f = 0; f < frames(); ++f) {
            v.push_back(valueOf(f));
            if (v.back() > v[size_t(worstFrame)]) worstFrame = f;
            over16 += v.back() > 1000.0 / 60.0;
            over33 += v.back() > 2000.0 / 60.0;
        }
        nlohmann::ordered_json s;
        s["median_ms"] = percentile(v, 0.5);
        s["p99_ms"] = percentile(v, 0.99);
        s["worst_ms"] = v.empty() ? 0.0 : v[size_t(worstFrame)];
        s["worst_frame"] = worstFrame + 1;
        s["frames_over_16_7_ms"] = over16;
        s["frames_over_33_3_ms"] = over33;
        return s;
    };
    nlohmann::ordered_json out;
    out["frame"] = stats([&](int f) { return total(f); });
    for (const auto& p : phases_) out[p] = stats([&](int f) { return time(f, p); });
    return out;
}

namespace {

// Distinct colours for up to a dozen phases (then they repeat).
void phaseColour(cairo_t* cr, int i) {
    static const double rgb[][3] = {{0.26, 0.45, 0.76}, {0.55, 0.71, 0.93}, {0.20, 0.60, 0.35}, {0.60, 0.82, 0.50},
                                    {0.85, 0.55, 0.15}, {0.98, 0.78, 0.40}, {0.70, 0.25, 0.25}, {0.95, 0.55, 0.55},
                                    {0.50, 0.35, 0.65}, {0.75, 0.65, 0.85}, {0.45, 0.45, 0.45}, {0.75, 0.75, 0.75}};
    const auto& c = rgb[i % 12];
    cairo_set_source_rgb(cr, c[0], c[1], c[2]);
}

} // namespace

void plotFrames(const FrameTable& table, const std::string& title, const std::string& path) {
    const int width = 1400, height = 700, left = 70, right = 230, top = 50, bottom = 50;
    cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
    cairo_t* cr = cairo_create(surface);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    double yMax = 40.0;
    for (int f = 0; f < table.frames(); ++f) yMax = std::max(yMax, table.total(f));
    const double plotW = width - left - right, plotH = height - top - bottom;
    const double barW = plotW / std::max(1, table.frames());
    auto y = [&](double ms) { return top + plotH * (1.0 - ms / yMax); };
    for (int f = 0; f < table.frames(); ++f) {
        double base = 0.0;
        for (size_t p = 0; p < table.phases().size(); ++p) {
            const double ms = table.time(f, table.phases()[p]);
            if (ms <= 0) continue;
            phaseColour(cr, int(p));
            cairo_rectangle(cr, left + f * barW, y(base + ms), std::max(1.0, barW), y(base) - y(base + ms));
            cairo_fill(cr);
            base += ms;
        }
    }
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 13);
    // Budget lines and axes.
    double labelEnd = left + plotW - 6;
    for (const auto& [ms, label] : {std::pair{1000.0 / 60.0, "16.7 ms (60 fps)"}, std::pair{2000.0 / 60.0, "33.3 ms (30 fps)"}}) {
        cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
        cairo_set_line_width(cr, 1.5);
        cairo_move_to(cr, left, y(ms));
        cairo_line_to(cr, left + plotW, y(ms));
        cairo_stroke(cr);
        // Inside the plot, just above the line toward its right end (the last frames are the
        // quiet ones; the legend takes the right margin), side by side: on a tall axis the two
        // lines are a few pixels apart.
        cairo_text_extents_t extents;
        cairo_text_extents(cr, label, &extents);
        cairo_move_to(cr, labelEnd - extents.x_advance, y(ms) - 4);
        cairo_show_text(cr, label);
        labelEnd -= extents.x_advance + 20;
    }
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1);
    cairo_move_to(cr, left, top);
    cairo_line_to(cr, left, top + plotH);
    cairo_line_to(cr, left + plotW, top + plotH);
    cairo_stroke(cr);
    char text[64];
    for (int k = 0; k <= 4; ++k) {
        const double ms = yMax * k / 4.0;
        std::snprintf(text, sizeof text, "%.0f ms", ms);
        cairo_move_to(cr, 8, y(ms) + 4);
        cairo_show_text(cr, text);
    }
    std::snprintf(text, sizeof text, "frame (1..%d)", table.frames());
    cairo_move_to(cr, left + plotW / 2 - 40, height - 15);
    cairo_show_text(cr, text);
    // Legend: phases bottom-up, as stacked.
    for (size_t p = 0; p < table.phases().size(); ++p) {
        const double ly = top + plotH - 20.0 * double(p) - 12;
        phaseColour(cr, int(p));
        cairo_rectangle(cr, left + plotW + 8, ly - 10, 12, 12);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_move_to(cr, left + plotW + 26, ly);
        cairo_show_text(cr, table.phases()[p].c_str());
    }
    cairo_set_font_size(cr, 16);
    cairo_move_to(cr, left, 30);
    cairo_show_text(cr, title.c_str());
    cairo_destroy(cr);
    const cairo_status_t status = cairo_surface_write_to_png(surface, path.c_str());
    cairo_surface_destroy(surface);
    if (status != CAIRO_STATUS_SUCCESS) throw InputError(path + ": cannot write the plot (" + cairo_status_to_string(status) + ")");
}

} // namespace shatter::bench
