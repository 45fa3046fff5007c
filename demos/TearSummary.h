#pragma once
// The tearing keys of summary.json, shared by the demos whose bodies tear (shatter-tear,
// shatter-door --tear): watches the tearable bodies and every part of theirs, and asks for
// `tear.png` six frames after the first tear.
#include "demos/runner/DemoRunner.h"
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/fracture/TearSystem.h>

#include <algorithm>
#include <set>
#include <vector>

namespace shatter::demo {

// Writes the tearing keys after every frame.
class TearSummary {
public:
    explicit TearSummary(Scene& scene) : scene_(scene) {}

    void watch(const VisualBody& body) {
        tracked_.insert(body.id());
        massInitial_ += body.physicalMesh().mass.mass;
    }

    // The watched bodies and their parts that are in the world now, in the plugin's order.
    std::vector<const VisualBody*> watched() const {
        std::vector<const VisualBody*> out;
        for (const auto& body : scene_.plugin().bodies())
            if (tracked_.count(body->id())) out.push_back(body.get());
        return out;
    }

    void frame(const Frame& frame) {
        for (const Event& e : frame.events)
            if (e.type == EventType::BodyTorn && tracked_.count(e.body)) {
                ++events_;
                broken_ += e.count;
                tracked_.insert(e.fragments.begin(), e.fragments.end());
                if (firstTear_ < 0) firstTear_ = frame.index;
            }
        if (firstTear_ > 0 && frame.index == firstTear_ + 6) scene_.pictureAfterFrame("tear.png");
        for (const auto& r : scene_.plugin().tears().takeRecords()) {
            // Relative to the parent's momentum (an exact copy of particles gives 0).
            const double p = r.momentumBefore.norm(), l = r.angularMomentumBefore.norm();
            if (p > 0) momentumError_ = std::max(momentumError_, (r.momentumAfter - r.momentumBefore).norm() / p);
            if (l > 0)
                angularError_ = std::max(angularError_, (r.angularMomentumAfter - r.angularMomentumBefore).norm() / l);
            idsSplit_ += r.idsSplit;
        }
        write();
    }

private:
    void write() {
        double mass = 0;
        nlohmann::json parts = nlohmann::json::array();
        for (const VisualBody* body : watched()) {
            mass += body->physicalMesh().mass.mass;
            parts.push_back({{"name", body->name()}, {"primitives", body->physicalMesh().primitives.size()}});
        }
        scene_.addSummary("tear_events", events_);
        scene_.addSummary("connections_broken", broken_);
        scene_.addSummary("ids_split", idsSplit_);
        scene_.addSummary("torn_bodies", parts);
        scene_.addSummary("mass_initial", massInitial_);
        scene_.addSummary("mass_final", mass);
        scene_.addSummary("momentum_error_max", momentumError_);
        scene_.addSummary("angular_momentum_error_max", angularError_);
        scene_.addSummary("first_tear_frame", firstTear_);
        // Where the tearing time went (wall seconds summed over the run).
        const auto& t = scene_.plugin().tears().timing();
        scene_.addSummary("tear_seconds", {{"stretch", t.stretch}, {"tearing", t.tearing}, {"bodies", t.bodies}});
    }

    Scene& scene_;
    std::set<int> tracked_;
    double massInitial_ = 0, momentumError_ = 0, angularError_ = 0;
    int events_ = 0, broken_ = 0, idsSplit_ = 0, firstTear_ = -1;
};

} // namespace shatter::demo
