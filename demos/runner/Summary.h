#pragma once
// summary.json: what a run produced, in numbers a script or a test can check.
#include "demos/runner/RunOptions.h"
#include "demos/runner/Scene.h"

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace shatter::demo {

// Wall-clock milliseconds of each frame's stepSimulation. The only non-deterministic
// content of the summary, kept in fields named ms_* so a comparison can drop them.
struct StepTimes {
    std::vector<double> ms;
    double median() const;
    double p99() const; // the 99th percentile (nearest rank)
    double max() const;
};

// Per frame: the bodies there (all but the ground) and the Shatter events of that frame, for
// plots and the browser viewer.
struct FrameCounts {
    std::vector<int> bodies;
    std::vector<int> events;
};

// Shatter events seen during the run, by EventType name.
using EventCounts = std::map<std::string, int>;

// Keys the runner writes itself; Scene::addSummary refuses them.
bool isReservedSummaryKey(const std::string& key);

// demo, description, frames, fps, substeps, seed, time, ms_per_frame_median,
// ms_per_frame_max, bodies (Shatter bodies), rigid_bodies (plain bodies but the ground),
// events, ms_per_frame, bodies_per_frame, events_per_frame (one number per frame), then the
// scene's own keys in the order they were added.
nlohmann::ordered_json buildSummary(const std::string& demo, const std::string& description, const RunOptions& options,
                                    Scene& scene, const StepTimes& times, const EventCounts& events,
                                    const FrameCounts& counts = {});

// JSON text for people as well as scripts: indented objects, but an array of numbers or
// strings (a position, a velocity) on one line. Invalid UTF-8 in names is replaced.
std::string summaryText(const nlohmann::ordered_json& summary);

} // namespace shatter::demo
