#include <shatter/bullet_ext/Plugin.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/Joints.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/bullet_ext/OutOfWorld.h>
#include <shatter/bullet_ext/oriented/SoftContacts.h>
#include <shatter/plugin/common/InputError.h>

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
    BodySettings used = settings;
    used.solver.gravity = toEigen(world_->getGravity());
    auto body = std::make_unique<VisualBody>(nextBodyId_, mesh, used, pose);
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
        // Primitives inside a joint box are the boundary conditions of deformation (000 §3.5).
        added.bodies[a]->fixPrimitives(box.attachmentsA);
        added.bodies[b]->fixPrimitives(box.attachmentsB);
        auto joint = std::make_unique<Joint>();
        joint->id_ = nextJointId_++;
        joint->box_ = box;
        addJointConstraint(*joint, *added.bodies[a], *added.bodies[b]);
        push(EventType::JointAdded, -1, joint->id_, box.name);
        added.joints.push_back(joint.get());
        joints_.push_back(std::move(joint));
    }
    return added;
}

void Plugin::addJointConstraint(Joint& joint, VisualBody& a, VisualBody& b) {
    joint.bodyA_ = &a;
    joint.bodyB_ = &b;
    joint.constraint_ = makeJointConstraint(joint.box_, a.rigidBody(), toBullet(a.meshToBody()), b.rigidBody(),
                                            toBullet(b.meshToBody()));
    const double breaking = std::max(a.settings().jointBreakingImpulse, b.settings().jointBreakingImpulse);
    if (breaking > 0.0) joint.constraint_->setBreakingImpulseThreshold(btScalar(breaking));
    world_->addConstraint(joint.constraint_.get(), /*disableCollisionsBetweenLinkedBodies=*/true);
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
    deformBodies(dt);
    // Bullet disables a constraint whose impulse passed its breaking threshold.
    for (auto& joint : joints_) {
        if (!joint->broken_ && !joint->constraint_->isEnabled()) {
            joint->broken_ = true;
            push(EventType::JointBroken, -1, joint->id_, joint->name());
        }
    }
}

template <class Change>
void Plugin::reshape(VisualBody& body, const Change& change) {
    outOfWorldWhile(*world_, body.rigidBody(), change);
    for (auto& joint : joints_) {
        if (joint->bodyA_ != &body && joint->bodyB_ != &body) continue;
        const bool enabled = joint->constraint_->isEnabled();
        world_->removeConstraint(joint->constraint_.get());
        addJointConstraint(*joint, *joint->bodyA_, *joint->bodyB_);
        joint->constraint_->setEnabled(enabled);
    }
}

void Plugin::deformBodies(double dt) {
    bool plastic = false;
    for (auto& body : bodies_) {
        if (body->deformation() == Deformation::Soft) {
            auto contacts = softContacts(*world_, *body);
            reshape(*body, [&] { body->advanceSoft(dt, contacts); });
        } else if (body->deformation() == Deformation::Plastic) {
            plastic = true;
            const auto dents = findDents(*world_->getDispatcher(), *body, velocities_, dt);
            if (dents.empty()) continue;
            oriented::PlasticResult result;
            reshape(*body, [&] { result = body->dent(dents); });
            if (!result.moved.empty()) {
                push(EventType::BodyDented, body->id(), -1, body->name(), int(result.moved.size()));
            }
        }
    }
    if (plastic) velocities_.record(*world_);
}

void Plugin::push(EventType type, int body, int joint, const std::string& name, int count) {
    events_.push_back({type, body, joint, time_, name, count});
}

} // namespace shatter
