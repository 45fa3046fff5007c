#include "demos/runner/Summary.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace shatter::demo {

namespace {

using Json = nlohmann::ordered_json;

Json vector3(const btVector3& v) { return Json::array({double(v.x()), double(v.y()), double(v.z())}); }

Json shatterBody(VisualBody& body) {
    const btRigidBody& rb = body.rigidBody();
    return Json{{"name", body.name()},
                {"id", body.id()},
                {"primitives", body.physicalMesh().primitives.size()},
                {"connections", body.physicalMesh().connections.size()},
                {"mass", body.physicalMesh().mass.mass},
                {"position", vector3(rb.getCenterOfMassPosition())},
                {"linear_velocity", vector3(rb.getLinearVelocity())},
                {"angular_velocity", vector3(rb.getAngularVelocity())}};
}

Json plainBody(const RigidEntry& entry) {
    const btRigidBody& rb = *entry.body;
    const double inverseMass = rb.getInvMass();
    return Json{{"name", entry.name},
                {"shape", entry.shape->getName()},
                {"mass", inverseMass > 0 ? 1.0 / inverseMass : 0.0},
                {"position", vector3(rb.getCenterOfMassPosition())},
                {"linear_velocity", vector3(rb.getLinearVelocity())},
                {"angular_velocity", vector3(rb.getAngularVelocity())}};
}

constexpr std::array kReserved = {"demo",  "description",        "frames",           "fps",    "substeps",     "seed",
                                  "time",  "ms_per_frame_median", "ms_per_frame_p99", "ms_per_frame_max", "bodies", "rigid_bodies", "events",
                                  "ms_per_frame", "bodies_per_frame", "events_per_frame"};

// Sub-microsecond digits of a wall-clock time are noise.
double roundedMs(double ms) { return std::round(ms * 1e4) / 1e4; }

void appendPretty(std::string& text, const Json& value, int indent) {
    const auto scalar = [](const Json& v) { return v.dump(-1, ' ', false, Json::error_handler_t::replace); };
    const std::string pad(size_t(indent + 2), ' ');
    if (value.is_object() && !value.empty()) {
        text += "{\n";
        size_t i = 0;
        for (const auto& [key, item] : value.items()) {
            text += pad + scalar(key) + ": ";
            appendPretty(text, item, indent + 2);
            text += ++i < value.size() ? ",\n" : "\n";
        }
        text += std::string(size_t(indent), ' ') + "}";
    } else if (value.is_array() && !value.empty()) {
        const bool flat = std::none_of(value.begin(), value.end(), [](const Json& v) { return v.is_structured(); });
        text += flat ? "[" : "[\n";
        for (size_t i = 0; i < value.size(); ++i) {
            if (flat) {
                text += (i ? ", " : "") + scalar(value[i]);
            } else {
                text += pad;
                appendPretty(text, value[i], indent + 2);
                text += i + 1 < value.size() ? ",\n" : "\n";
            }
        }
        text += flat ? "]" : std::string(size_t(indent), ' ') + "]";
    } else {
        text += scalar(value);
    }
}

} // namespace

double StepTimes::median() const {
    if (ms.empty()) return 0.0;
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    const size_t n = sorted.size();
    return n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
}

double StepTimes::p99() const {
    if (ms.empty()) return 0.0;
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    const size_t rank = size_t(std::ceil(0.99 * double(sorted.size())));
    return sorted[std::max<size_t>(rank, 1) - 1];
}

double StepTimes::max() const { return ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end()); }

bool isReservedSummaryKey(const std::string& key) {
    return std::find(kReserved.begin(), kReserved.end(), key) != kReserved.end();
}

Json buildSummary(const std::string& demo, const std::string& description, const RunOptions& options, Scene& scene,
                  const StepTimes& times, const EventCounts& events, const FrameCounts& counts) {
    Json bodies = Json::array();
    for (const auto& body : scene.plugin().bodies()) bodies.push_back(shatterBody(*body));
    Json rigid = Json::array();
    for (const auto& entry : scene.rigidBodies())
        if (!entry->ground) rigid.push_back(plainBody(*entry));
    Json eventCounts = Json::object();
    for (const auto& [type, count] : events) eventCounts[type] = count;

    Json summary{{"demo", demo},
                 {"description", description},
                 {"frames", options.frames},
                 {"fps", options.fps},
                 {"substeps", options.substeps},
                 {"seed", options.seed},
                 {"time", options.frames / options.fps},
                 {"ms_per_frame_median", roundedMs(times.median())},
                 {"ms_per_frame_p99", roundedMs(times.p99())},
                 {"ms_per_frame_max", roundedMs(times.max())},
                 {"bodies", std::move(bodies)},
                 {"rigid_bodies", std::move(rigid)},
                 {"events", std::move(eventCounts)}};
    Json ms = Json::array();
    for (double t : times.ms) ms.push_back(roundedMs(t));
    summary["ms_per_frame"] = std::move(ms);
    summary["bodies_per_frame"] = counts.bodies;
    summary["events_per_frame"] = counts.events;
    for (const auto& [key, value] : scene.extraSummary().items()) summary[key] = value;
    return summary;
}

std::string summaryText(const Json& summary) {
    std::string text;
    appendPretty(text, summary, 0);
    return text + "\n";
}

} // namespace shatter::demo
