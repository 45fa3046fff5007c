#pragma once
// What a demo's setup sees: a Bullet world with Shatter attached, helpers for the plain
// bodies most scenes need (ground, balls, walls), and hooks into the summary and the frames.
#include <shatter/bullet_ext/Events.h>
#include <shatter/bullet_ext/Plugin.h>
#include "demos/runner/NamedMesh.h"
#include "demos/runner/ShapeMesh.h"

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <LinearMath/btDefaultMotionState.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace shatter::demo {

// Passed to onFrame callbacks after each frame has been stepped.
struct Frame {
    int index = 0;                  // 1-based
    int count = 0;                  // frames in the run
    double time = 0;                // simulated seconds at the end of this frame
    const std::vector<Event>& events; // Shatter events of this frame (frame 1 includes setup's)
};

// A body added with Scene::addRigidBody (or the ground): Bullet objects and the surface drawn.
struct RigidEntry {
    std::string name;
    std::unique_ptr<btCollisionShape> shape;
    std::unique_ptr<btDefaultMotionState> motionState;
    std::unique_ptr<btRigidBody> body;
    ShapeMesh surface; // body coordinates
    bool ground = false;
};

class Scene {
public:
    explicit Scene(std::uint64_t seed);
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    // ---- for a demo's setup ----
    btDiscreteDynamicsWorld& world() { return *world_; }
    Plugin& plugin() { return *plugin_; }
    std::uint64_t seed() const { return seed_; }
    // A generator seeded with seed(), for scenes that place things at random.
    std::mt19937_64& random() { return random_; }

    // A static plane y = 0 (Y is up). It is written to the frame files as a square of
    // `halfSize` metres and drawn as a checkered floor.
    btRigidBody& addGround(double friction = 0.8, double halfSize = 10.0);
    // Penetration is resolved by split impulses only, never by added velocity (Bullet's
    // default adds velocity for overlaps shallower than 4 cm): fresh fragments pressed into
    // the floor and into each other by the impact that broke them are pushed apart without
    // gaining energy, and a ball pushed into them is not thrown back by the overlap.
    void useSplitImpulsesOnly();
    // A plain Bullet body the scene owns; mass 0 makes it static. Box, sphere, capsule,
    // cylinder, convex hull and compound shapes are drawn and written. Throws
    // shatter::InputError naming the body for a null or undrawable shape, a negative or
    // non-finite mass, or a non-finite pose.
    btRigidBody& addRigidBody(std::unique_ptr<btCollisionShape> shape, double mass, const btTransform& pose,
                              std::string name);
    // An extra key in summary.json. Throws std::invalid_argument for a key the runner
    // writes itself.
    void addSummary(const std::string& key, nlohmann::json value);
    // Called after every frame's step, before the frame is written; several may be added.
    void onFrame(std::function<void(const Frame&)> callback);
    // From an onFrame callback: also write a picture of this frame to `fileName` (a .png in
    // the output directory), e.g. the moment after a break. With `focus` (world points), the
    // camera frames those points from the usual direction instead of the whole scene: a close-up.
    struct PictureRequest {
        std::string file;
        std::vector<Eigen::Vector3d> focus;
    };
    void pictureAfterFrame(std::string fileName, std::vector<Eigen::Vector3d> focus = {}) {
        pictures_.push_back({std::move(fileName), std::move(focus)});
    }

    // ---- for the runner ----
    // Every object as it is now, in world coordinates: Shatter bodies, then the plain bodies
    // and the ground in the order they were added.
    std::vector<NamedMesh> meshes();
    const std::vector<std::unique_ptr<RigidEntry>>& rigidBodies() const { return rigid_; }
    const nlohmann::ordered_json& extraSummary() const { return extra_; }
    void notifyFrame(const Frame& frame) const;
    // The pictures asked for since the last call.
    std::vector<PictureRequest> takePictureRequests() { return std::exchange(pictures_, {}); }
    bool hasGround() const;

private:
    std::uint64_t seed_;
    std::mt19937_64 random_;
    std::unique_ptr<btDefaultCollisionConfiguration> configuration_;
    std::unique_ptr<btCollisionDispatcher> dispatcher_;
    std::unique_ptr<btDbvtBroadphase> broadphase_;
    std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
    std::unique_ptr<btDiscreteDynamicsWorld> world_;
    std::unique_ptr<Plugin> plugin_;
    std::vector<std::unique_ptr<RigidEntry>> rigid_;
    nlohmann::ordered_json extra_ = nlohmann::ordered_json::object();
    std::vector<std::function<void(const Frame&)>> frameCallbacks_;
    std::vector<PictureRequest> pictures_;
};

} // namespace shatter::demo
