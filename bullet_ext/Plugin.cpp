#include "bullet_ext/Plugin.h"

#include "bullet_ext/Convert.h"
#include "bullet_ext/JointFactory.h"
#include "bullet_ext/LatticeSystem.h"
#include "plugin/geometry/InputError.h"

#include <BulletDynamics/Dynamics/btActionInterface.h>
#include <algorithm>

namespace shatter {

// Runs Shatter's per-step work inside every internal world step, after Bullet has
// integrated the bodies. An action leaves the application's tick callbacks and world
// user info untouched, so nothing of the application's has to be chained or restored.
class Plugin::StepHook : public btActionInterface {
public:
    explicit StepHook(Plugin& plugin) : plugin_(plugin) {}
    void updateAction(btCollisionWorld*, btScalar dt) override { plugin_.onInternalStep(double(dt)); }
    void debugDraw(btIDebugDraw*) override {}

private:
    Plugin& plugin_;
};

namespace {

btCollisionDispatcher& collisionDispatcher(btDiscreteDynamicsWorld& world) {
    auto* dispatcher = dynamic_cast<btCollisionDispatcher*>(world.getDispatcher());
    if (!dispatcher) throw InputError("shatter::Plugin: the world's dispatcher is not a btCollisionDispatcher");
    return *dispatcher;
}

} // namespace

Plugin::Plugin(btDiscreteDynamicsWorld& world) : world_(&world), hook_(std::make_unique<StepHook>(*this)) {
    registerGroupShapeAlgorithms(collisionDispatcher(world));
    world.addAction(hook_.get());
}

Plugin::~Plugin() { detach(); }

void Plugin::detach() {
    if (!world_) return;
    lattices_.reset(); // refers to bodies removed below
    while (!joints_.empty()) removeJoint(joints_.size() - 1);
    while (!bodies_.empty()) removeBody(*bodies_.back());
    world_->removeAction(hook_.get());
    unregisterGroupShapeAlgorithms(collisionDispatcher(*world_));
    world_ = nullptr;
}

VisualBody& Plugin::addVisualBody(const geometry::PhysicalMesh& mesh, const BodySettings& settings,
                                  const btTransform& pose) {
    if (!world_) throw InputError("shatter::Plugin: addVisualBody after detach");
    auto body = std::make_unique<VisualBody>(nextBodyId_, mesh, settings, pose);
    ++nextBodyId_;
    world_->addRigidBody(&body->rigidBody());
    push(EventType::BodyAdded, body->id(), -1, body->name());
    bodies_.push_back(std::move(body));
    return *bodies_.back();
}

Plugin::Object Plugin::addObject(const geometry::PhysicalObject& object, const BodySettings& settings,
                                 const btTransform& pose, const std::map<std::string, BodySettings>& perBody) {
    Object added;
    for (const auto& mesh : object.bodies) {
        const auto custom = perBody.find(mesh.name);
        added.bodies.push_back(&addVisualBody(mesh, custom == perBody.end() ? settings : custom->second, pose));
    }
    for (const auto& box : object.joints) {
        const int a = object.findBody(box.bodyA), b = object.findBody(box.bodyB);
        if (a < 0 || b < 0) throw InputError("joint '" + box.name + "': names a body that the object does not have");
        VisualBody& bodyA = *added.bodies[a];
        VisualBody& bodyB = *added.bodies[b];
        auto joint = std::make_unique<Joint>();
        joint->id_ = nextJointId_++;
        joint->box_ = box;
        joint->constraint_ = makeJointConstraint(box, pose, bodyA.rigidBody(), bodyB.rigidBody());
        const double breaking = std::max(bodyA.settings().jointBreakingImpulse, bodyB.settings().jointBreakingImpulse);
        if (breaking > 0.0) joint->constraint_->setBreakingImpulseThreshold(btScalar(breaking));
        world_->addConstraint(joint->constraint_.get(), /*disableCollisionsBetweenLinkedBodies=*/true);
        push(EventType::JointAdded, -1, joint->id_, box.name);
        added.joints.push_back(joint.get());
        joints_.push_back(std::move(joint));
    }
    return added;
}

LatticeBody& Plugin::addLatticeBody(const lattice::TetMesh& mesh, const LatticeSettings& settings,
                                    const btTransform& pose) {
    if (!world_) throw InputError("shatter::Plugin: addLatticeBody after detach");
    return lattices().add(mesh, settings, pose);
}

LatticeSystem& Plugin::lattices() {
    if (!lattices_) lattices_ = std::make_unique<LatticeSystem>(*this);
    return *lattices_;
}

void Plugin::removeBody(VisualBody& body) {
    for (size_t i = joints_.size(); i-- > 0;) {
        const btTypedConstraint& c = *joints_[i]->constraint_;
        if (&c.getRigidBodyA() == &body.rigidBody() || &c.getRigidBodyB() == &body.rigidBody()) removeJoint(i);
    }
    const auto it = std::find_if(bodies_.begin(), bodies_.end(), [&](const auto& b) { return b.get() == &body; });
    if (it == bodies_.end()) return;
    world_->removeRigidBody(&body.rigidBody());
    push(EventType::BodyRemoved, body.id(), -1, body.name());
    bodies_.erase(it);
}

void Plugin::removeJoint(size_t index) {
    world_->removeConstraint(joints_[index]->constraint_.get());
    joints_.erase(joints_.begin() + long(index));
}

std::vector<Event> Plugin::takeEvents() {
    std::vector<Event> out;
    out.swap(events_);
    return out;
}

void Plugin::onInternalStep(double dt) {
    time_ += dt;
    if (lattices_) lattices_->step(dt);
    // Bullet disables a constraint whose impulse passed its breaking threshold.
    for (auto& joint : joints_) {
        if (!joint->broken_ && !joint->constraint_->isEnabled()) {
            joint->broken_ = true;
            push(EventType::JointBroken, -1, joint->id_, joint->name());
        }
    }
}

void Plugin::push(EventType type, int body, int joint, const std::string& name) {
    events_.push_back({type, body, joint, time_, name});
}

} // namespace shatter
