#pragma once
// What the lattice demos (wall, table, noise) share: the ball that hits the body, the solver
// setting they need, and the summary keys every lattice demo writes.
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include "demos/runner/Scene.h"
#include <shatter/plugin/common/InputError.h>

#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <memory>
#include <string>

namespace shatter::demo {

struct Ball {
    double speed; // m/s
    double mass;  // kg
    double radius; // m
};

// --ball-speed, --ball-mass, --ball-radius; `note` ends each help text (e.g. "(both balls)").
inline void addBallOptions(CLI::App& cli, Ball& ball, const std::string& note = "") {
    const std::string tail = note.empty() ? "" : " " + note;
    cli.add_option("--ball-speed", ball.speed, "ball speed in m/s" + tail)->capture_default_str();
    cli.add_option("--ball-mass", ball.mass, "ball mass in kg" + tail)->capture_default_str();
    cli.add_option("--ball-radius", ball.radius, "ball radius in m" + tail)->capture_default_str();
}

inline void checkBall(const Ball& ball) {
    if (!(std::isfinite(ball.speed) && ball.speed >= 0)) throw InputError("--ball-speed must be finite and >= 0 m/s");
    if (!(std::isfinite(ball.mass) && ball.mass > 0)) throw InputError("--ball-mass must be finite and > 0 kg");
    if (!(std::isfinite(ball.radius) && ball.radius > 0)) throw InputError("--ball-radius must be finite and > 0 m");
}

// Penetration is resolved by split impulses only, never by added velocity: a ball pushed into
// fresh fragments is not thrown back by the overlap.
inline void useSplitImpulsesOnly(btDiscreteDynamicsWorld& world) {
    world.getSolverInfo().m_splitImpulse = 1;
    world.getSolverInfo().m_splitImpulsePenetrationThreshold = 0;
}

// A ball at `at` flying along the unit `direction` at the ball's speed.
inline btRigidBody& launchBall(Scene& scene, const Ball& ball, const btVector3& at, const btVector3& direction,
                               const std::string& name = "ball") {
    btRigidBody& body = scene.addRigidBody(std::make_unique<btSphereShape>(btScalar(ball.radius)), ball.mass,
                                           btTransform(btQuaternion::getIdentity(), at), name);
    body.setLinearVelocity(direction * btScalar(ball.speed));
    return body;
}

// The summary keys of a lattice demo for one breakable body.
inline nlohmann::json latticeCounts(const LatticeBody& b) {
    return {{"tets", b.tetCount()},
            {"links", b.linkCount()},
            {"links_broken", b.brokenLinkCount()},
            {"fragments", b.pieceCount()},
            {"fragments_frozen", b.frozenPieceCount()},
            {"mass_initial", b.initialMass()},
            {"mass_final", b.currentMass()},
            {"mass_relative_change", (b.currentMass() - b.initialMass()) / b.initialMass()}};
}

inline void addSummaries(Scene& scene, const nlohmann::json& counts) {
    for (const auto& [key, value] : counts.items()) scene.addSummary(key, value);
}

} // namespace shatter::demo
