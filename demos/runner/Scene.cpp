#include "demos/runner/Scene.h"

#include <shatter/bullet_ext/Convert.h>
#include "demos/runner/Summary.h"
#include <shatter/plugin/common/InputError.h>

#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>

#include <cmath>
#include <stdexcept>

namespace shatter::demo {

namespace {

bool finite(const btTransform& t) {
    const Eigen::Isometry3d e = toEigen(t);
    return e.matrix().allFinite();
}

geometry::VisualMesh groundSquare(double halfSize) {
    geometry::VisualMesh mesh;
    const double h = halfSize;
    mesh.positions = {{-h, 0, -h}, {-h, 0, h}, {h, 0, h}, {h, 0, -h}};
    mesh.faces = {{0, 1, 2, 3}}; // counter-clockwise seen from above
    return mesh;
}

// A breaking body's contacts are per primitive pair, each pair with its own manifold: the
// lattice table keeps up to 40,000 at once, Spot's wall 32,000. Bullet's pool holds 4,096
// and takes the rest from the heap, a malloc and a free per manifold (2.5% of the table's
// instructions). 65,536 manifolds of 880 bytes: 58 MB, all touched when the pool is made
// (its free list runs through every element): the table peaks at 115 MB instead of 96.
btDefaultCollisionConstructionInfo collisionConstruction() {
    btDefaultCollisionConstructionInfo info;
    info.m_defaultMaxPersistentManifoldPoolSize = 1 << 16;
    return info;
}

} // namespace

Scene::Scene(std::uint64_t seed)
    : seed_(seed), random_(seed), configuration_(std::make_unique<btDefaultCollisionConfiguration>(collisionConstruction())),
      dispatcher_(std::make_unique<btCollisionDispatcher>(configuration_.get())),
      broadphase_(std::make_unique<btDbvtBroadphase>()),
      solver_(std::make_unique<btSequentialImpulseConstraintSolver>()),
      world_(std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(),
                                                       configuration_.get())) {
    world_->setGravity(btVector3(0, btScalar(-9.81), 0));
    // Two friction directions per contact: with Bullet's default single direction, resting
    // bodies creep by a fraction of a millimetre per second until they fall asleep.
    world_->getSolverInfo().m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
    plugin_ = std::make_unique<Plugin>(*world_);
}

Scene::~Scene() {
    // Shatter's bodies and hooks leave first, then ours, while the world still exists.
    plugin_.reset();
    for (auto& entry : rigid_) world_->removeRigidBody(entry->body.get());
}

void Scene::useSplitImpulsesOnly() {
    world_->getSolverInfo().m_splitImpulse = 1;
    world_->getSolverInfo().m_splitImpulsePenetrationThreshold = 0;
}

btRigidBody& Scene::addGround(double friction, double halfSize) {
    if (!(std::isfinite(friction) && friction >= 0)) throw InputError("ground: friction must be finite and >= 0");
    if (!(std::isfinite(halfSize) && halfSize > 0)) throw InputError("ground: half size must be finite and > 0");
    auto entry = std::make_unique<RigidEntry>();
    entry->name = "ground";
    entry->ground = true;
    entry->shape = std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), 0);
    entry->motionState = std::make_unique<btDefaultMotionState>();
    entry->body = std::make_unique<btRigidBody>(0, entry->motionState.get(), entry->shape.get());
    entry->body->setFriction(btScalar(friction));
    entry->surface = {groundSquare(halfSize), false};
    world_->addRigidBody(entry->body.get());
    rigid_.push_back(std::move(entry));
    return *rigid_.back()->body;
}

btRigidBody& Scene::addRigidBody(std::unique_ptr<btCollisionShape> shape, double mass, const btTransform& pose,
                                 std::string name) {
    if (!shape) throw InputError("body '" + name + "': no collision shape");
    if (!(std::isfinite(mass) && mass >= 0)) throw InputError("body '" + name + "': mass must be finite and >= 0 kg");
    if (!finite(pose)) throw InputError("body '" + name + "': pose has a non-finite value");
    auto entry = std::make_unique<RigidEntry>();
    entry->surface = tessellate(*shape, name); // throws before anything enters the world
    entry->name = std::move(name);
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(btScalar(mass), inertia);
    entry->shape = std::move(shape);
    entry->motionState = std::make_unique<btDefaultMotionState>(pose);
    entry->body = std::make_unique<btRigidBody>(
        btRigidBody::btRigidBodyConstructionInfo(btScalar(mass), entry->motionState.get(), entry->shape.get(), inertia));
    world_->addRigidBody(entry->body.get());
    rigid_.push_back(std::move(entry));
    return *rigid_.back()->body;
}

void Scene::addSummary(const std::string& key, nlohmann::json value) {
    if (isReservedSummaryKey(key)) throw std::invalid_argument("summary key '" + key + "' is written by the runner");
    extra_[key] = nlohmann::ordered_json(value);
}

void Scene::onFrame(std::function<void(const Frame&)> callback) { frameCallbacks_.push_back(std::move(callback)); }

void Scene::notifyFrame(const Frame& frame) const {
    for (const auto& callback : frameCallbacks_) callback(frame);
}

bool Scene::hasGround() const {
    for (const auto& entry : rigid_)
        if (entry->ground) return true;
    return false;
}

std::vector<NamedMesh> Scene::meshes() {
    std::vector<NamedMesh> out;
    out.reserve(plugin_->bodies().size() + rigid_.size());
    for (const auto& body : plugin_->bodies())
        out.push_back({body->name(), body->visualMesh(), true, false, toEigen(body->meshTransform())});
    for (const auto& entry : rigid_) {
        const btTransform& pose = entry->body->getWorldTransform();
        out.push_back({entry->name, transformed(entry->surface.mesh, pose), !entry->surface.round, entry->ground,
                       toEigen(pose)});
    }
    return out;
}

} // namespace shatter::demo
