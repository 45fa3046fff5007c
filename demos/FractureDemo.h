#pragma once
// What the fracture demos (vase, glass) and their benchmark share: the fracture options
// (--pattern, --cells, --fracture-threshold, --fracture-radius, --depth), and the summary of a
// breaking run (events, fragments, mass and volume kept, momentum errors at each break, crack
// faces), with a picture of the moment after the first break.
#include "demos/runner/Scene.h"
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/fracture/FractureSystem.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <memory>
#include <set>
#include <string>

namespace shatter::demo {

// --pattern voronoi|glass|grid|PATH.obj, --cells, --fracture-threshold, --fracture-radius,
// --min-piece, --depth into `f` (enabled). --seed is the runner's: the scene passes it on.
inline void addFractureOptions(CLI::App& cli, FractureSettings& f) {
    cli.add_option_function<std::string>(
           "--pattern",
           [&f](const std::string& name) {
               const bool file = name.size() > 4 && name.compare(name.size() - 4, 4, ".obj") == 0;
               f.pattern = file ? PatternKind::File : patternKindNamed(name);
               f.patternFile = file ? name : "";
           },
           "fracture pattern: voronoi, glass, grid, or an OBJ file of convex cells")
        ->default_str(toString(f.pattern));
    cli.add_option_function<int>(
           "--cells", [&f](int cells) { f.setCells(cells); },
           "cells of a generated pattern (Voronoi sites; glass sectors x rings and grid count^3 about this many)")
        ->check(CLI::PositiveNumber);
    cli.add_option("--fracture-threshold", f.threshold, "contact impulse that breaks a body, N*s")->capture_default_str();
    cli.add_option("--fracture-radius", f.radius, "cells within this distance of the hit break free, m")
        ->capture_default_str();
    cli.add_option("--min-piece", f.minimumPieceSize, "smallest piece, m (smaller ones merge)")->capture_default_str();
    cli.add_option("--depth", f.depth, "how many more times fragments may break")->capture_default_str();
}

// Watches the breakable bodies of a scene (those added before watch() and every fragment of
// theirs) and writes the fracture keys of summary.json after every frame; asks for
// `break.png` four frames after the first break.
class FractureSummary {
public:
    explicit FractureSummary(Scene& scene) : scene_(scene) {}

    void watch(const VisualBody& body) {
        tracked_.insert(body.id());
        massInitial_ += body.physicalMesh().mass.mass;
        volumeInitial_ += body.physicalMesh().mass.volume;
    }

    // Call from Scene::onFrame.
    void frame(const Frame& frame) {
        for (const Event& e : frame.events)
            if (e.type == EventType::BodyFractured && tracked_.count(e.body)) {
                ++events_;
                fragments_ += int(e.fragments.size());
                tracked_.insert(e.fragments.begin(), e.fragments.end());
                if (firstBreak_ < 0) firstBreak_ = frame.index;
            }
        if (firstBreak_ > 0 && frame.index == firstBreak_ + 4) scene_.pictureAfterFrame("break.png");
        for (const auto& r : scene_.plugin().fractures().takeRecords()) noteErrors(r);
        write();
    }

    int events() const { return events_; }

private:
    void noteErrors(const FractureSystem::Record& r) {
        // Relative to the size of the terms summed (a parent's total can cancel to zero).
        double pScale = r.before.linearMomentum().norm(), lScale = r.before.angularMomentum().norm();
        Eigen::Vector3d p = Eigen::Vector3d::Zero(), l = Eigen::Vector3d::Zero();
        for (const auto& part : r.parts) {
            p += part.linearMomentum();
            l += part.angularMomentum();
            pScale += part.linearMomentum().norm();
            lScale += part.centre.cross(part.linearMomentum()).norm() + (part.inertia * part.angularVelocity).norm();
        }
        if (pScale > 0) momentumError_ = std::max(momentumError_, (p - r.before.linearMomentum()).norm() / pScale);
        if (lScale > 0) angularError_ = std::max(angularError_, (l - r.before.angularMomentum()).norm() / lScale);
    }

    void write() {
        double mass = 0, volume = 0;
        int crackFaces = 0;
        for (const auto& body : scene_.plugin().bodies()) {
            if (!tracked_.count(body->id())) continue;
            mass += body->physicalMesh().mass.mass;
            volume += body->physicalMesh().mass.volume;
            const auto& flags = body->physicalMesh().visual.crackFace;
            crackFaces += int(std::count(flags.begin(), flags.end(), true));
        }
        scene_.addSummary("fracture_events", events_);
        scene_.addSummary("fragments", fragments_);
        scene_.addSummary("mass_initial", massInitial_);
        scene_.addSummary("mass_final", mass);
        scene_.addSummary("volume_initial", volumeInitial_);
        scene_.addSummary("volume_final", volume);
        scene_.addSummary("momentum_error_max", momentumError_);
        scene_.addSummary("angular_momentum_error_max", angularError_);
        scene_.addSummary("crack_faces", crackFaces);
        scene_.addSummary("first_break_frame", firstBreak_);
    }

    Scene& scene_;
    std::set<int> tracked_;
    double massInitial_ = 0, volumeInitial_ = 0, momentumError_ = 0, angularError_ = 0;
    int events_ = 0, fragments_ = 0, firstBreak_ = -1;
};

} // namespace shatter::demo
