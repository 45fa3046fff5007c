#include <shatter/bullet_ext/Plugin.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/OutOfWorld.h>
#include <shatter/bullet_ext/RemovalInWorld.h>
#include <shatter/bullet_ext/Watched.h>
#include <shatter/bullet_ext/fracture/FractureSystem.h>
#include <shatter/bullet_ext/lattice/LatticeAnchors.h>
#include <shatter/bullet_ext/fracture/TearSystem.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/bullet_ext/oriented/DeformationSystem.h>
#include <shatter/bullet_ext/shape/GroupCollisionAlgorithms.h>
#include <shatter/bullet_ext/shape/HullPairContacts.h>
#include <shatter/plugin/common/InputError.h>

#include <BulletDynamics/Dynamics/btActionInterface.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorldMt.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <algorithm>
#include <string>
#include <utility>

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

// Whether the world made its solver and frees it (setConstraintSolver would free it at once).
bool worldOwnsSolver(btDiscreteDynamicsWorld& world) {
    struct Access : btDiscreteDynamicsWorld {
        using btDiscreteDynamicsWorld::m_ownsConstraintSolver;
    };
    return world.*(&Access::m_ownsConstraintSolver);
}

// Why the world's solver cannot be wrapped to take the contacts in their own order, or "".
std::string whyBulletsOrder(btDiscreteDynamicsWorld& world) {
    // Its island manager solves large islands (all of them, dispatched serially) with the
    // world's multi-threaded solver, past the one a wrapper would stand in front of.
    if (dynamic_cast<btDiscreteDynamicsWorldMt*>(&world))
        return "a multi-threaded world (btDiscreteDynamicsWorldMt) solves its islands with solvers of its own";
    if (worldOwnsSolver(world)) return "the world made its own solver (pass it a btSequentialImpulseConstraintSolver)";
    // A multibody world's solver reports the sequential-impulse type too, and the world casts
    // whatever solver it is given to its own kind.
    btConstraintSolver* solver = world.getConstraintSolver();
    if (solver->getSolverType() != BT_SEQUENTIAL_IMPULSE_SOLVER || dynamic_cast<btMultiBodyConstraintSolver*>(solver))
        return "the world's solver is not a btSequentialImpulseConstraintSolver (a multibody one or of type " +
               std::to_string(int(solver->getSolverType())) + ")";
    return "";
}

} // namespace

// A wrapper in front of the world's solver changes what getConstraintSolver() is (a
// btMultiBodyDynamicsWorld casts a solver by its type), so it goes only in front of a
// sequential-impulse solver the application passed; any other world keeps its own solver and
// Bullet's order (HullPairContacts::contactOrder says whether that is an error).
bool Plugin::ownOrderAllowed(btDiscreteDynamicsWorld& world) {
    using Order = HullPairContacts::ContactOrder;
    const Order order = hullPairContacts().contactOrder;
    if (order == Order::Bullets) return false;
    const std::string why = whyBulletsOrder(world);
    if (why.empty()) return true;
    if (order == Order::Own) throw InputError("shatter::Plugin: HullPairContacts::ContactOrder::Own: " + why);
    warnings_.push_back("shatter::Plugin: contacts are solved in Bullet's order, with their empty manifolds, "
                        "in this world: " + why);
    return false;
}

void Plugin::unorderContacts() {
    if (!solver_) return;
    if (world_->getConstraintSolver() == solver_.get()) world_->setConstraintSolver(&solver_->inner());
    attachedWorld_->setContactsOrdered(false);
}

// The application may replace the world's solver (setConstraintSolver) while the Plugin is
// attached: its solver takes the manifolds in Bullet's order, where every empty one counts, so
// the world goes back to that order for good (its group pairs keep their empty manifolds from
// the next step on). The wrapper stays alive until detach: the application may put it back.
void Plugin::noticeReplacedSolver() {
    if (!attachedWorld_->contactsOrdered() || world_->getConstraintSolver() == solver_.get()) return;
    attachedWorld_->setContactsOrdered(false);
    warnings_.emplace_back("shatter::Plugin: the world's constraint solver was replaced while the Plugin took the "
                           "contacts in its own order: they are solved in Bullet's order, with their empty manifolds, "
                           "from now on (HullPairContacts::contactOrder)");
}

bool Plugin::contactsOrdered() const {
    return attached_ && attachedWorld_->contactsOrdered() && world_->getConstraintSolver() == solver_.get();
}

Plugin::Plugin(btDiscreteDynamicsWorld& world)
    : world_(&world), attached_(true), hook_(std::make_unique<StepHook>(*this)),
      attachedWorld_(std::make_unique<AttachedWorld>(collisionDispatcher(world))) {
    // Everything that may throw comes first, while nothing of the world's has changed (the
    // claim on the dispatcher ends with the member if the constructor throws).
    if (ownOrderAllowed(world)) solver_ = std::make_unique<OrderedContactSolver>(*world.getConstraintSolver());
    // The watch object: static, no contact response, collision group and mask 0, so it makes
    // no pairs and no ray hits; its deletion by the application (or its missing broadphase
    // handle after the world's destructor) says the world is going.
    auto watch = std::make_unique<Watched<btCollisionObject>>();
    watch->setCollisionShape(&watchShape_);
    watch->setCollisionFlags(btCollisionObject::CF_STATIC_OBJECT | btCollisionObject::CF_NO_CONTACT_RESPONSE);
    watch_.reset(std::move(watch), [this] { onWorldTeardown(); });
    // Then the world changes (Bullet's registrations and arrays do not throw).
    registerGroupShapeAlgorithms(collisionDispatcher(world));
    world.addAction(hook_.get());
    world.addCollisionObject(watch_.get(), 0, 0);
    if (solver_) {
        world.setConstraintSolver(solver_.get());
        attachedWorld_->setContactsOrdered(true);
    }
}

Plugin::~Plugin() { detach(); }

// The step order, in one list. Bullet has detected the contacts, solved them and integrated
// the bodies; the contact snapshot holds this step's manifolds. Then:
// 1. lattice bodies: contact impulses load each piece's lattice, links break, pieces that
//    came apart become new bodies (LatticeSystem);
// 2. fracture: rigid visual bodies break where a contact pair's impulse passed their
//    threshold, their fragments become bodies; bodies in FractureMode::Subdivide are cut finer
//    there instead, and a plastic one dents on the finer primitives at once (FractureSystem);
// 3. deformation: plastic bodies dent where contacts approached faster than their
//    threshold, soft bodies take one oriented-particle step (DeformationSystem). It runs after
//    fracture so that a body subdivided in this step is never first dented coarsely;
// 4. tearing: soft bodies whose breakable connections stretched past their distance in this
//    step's oriented-particle step, and plastic bodies whose dents of this step (steps 2 and 3)
//    pulled them that far apart, tear, and their parts become bodies (TearSystem).
// Bullet's own updateActivationState runs after this, so a system's changes to the
// deactivation timers count in the same step.
std::array<System*, 4> Plugin::stepOrder() const {
    return {lattices_.get(), fractures_.get(), deformation_.get(), tears_.get()};
}

void Plugin::onInternalStep(double dt) {
    if (solver_) noticeReplacedSolver();
    time_ += dt;
    const auto order = stepOrder();
    const bool active = std::any_of(order.begin(), order.end(), [](System* s) { return s && s->active(); });
    if (active) {
        contacts_.capture(*world_->getDispatcher());
        for (System* system : order)
            if (system && system->active()) {
                system->step(dt, contacts_);
                system->recordImpulses(contacts_);
            }
    }
    noteBrokenJoints();
    watchMassRatios();
    const bool motion = std::any_of(order.begin(), order.end(), [](System* s) { return s && s->needsMotionBefore(); });
    if (motion) contacts_.recordMotion(*world_);
    else contacts_.clearMotion();
}

void Plugin::noteBrokenJoints() {
    // Bullet disables a constraint whose impulse passed its breaking threshold.
    for (auto& joint : joints_) {
        if (!joint->broken_ && !joint->constraint_->isEnabled()) {
            joint->broken_ = true;
            push(EventType::JointBroken, -1, joint->id_, joint->name());
        }
    }
}

void Plugin::detach() {
    if (!world_) return;
    if (worldReachable()) {
        while (!joints_.empty()) removeJoint(joints_.size() - 1);
        for (auto& body : bodies_) takeOutOfWorld(*body);
        world_->removeCollisionObject(watch_.get());
        world_->removeAction(hook_.get());
        unorderContacts();
        unregisterGroupShapeAlgorithms(collisionDispatcher(*world_));
    } else {
        // The world's destructor ran (it cleared the handles of the objects it held), or the
        // application is walking its objects to delete them (the hook and joints are gone):
        // only bodies still in a world are taken out.
        for (auto& body : bodies_) takeOutOfWorld(*body);
    }
    attachedWorld_.reset(); // Shatter's own record: ends whether or not the world is still there
    // Systems after their bodies left the world: nothing of theirs is in it any more.
    lattices_.reset();
    deformation_.reset();
    fractures_.reset();
    tears_.reset();
    joints_.clear();
    bodies_.clear();
    watch_.reset();
    world_ = nullptr;
    attached_ = false;
}

void Plugin::onWorldTeardown() {
    // Inside the application's walk over the world's objects: the world is alive, but its
    // object array must not change under the walk, so the bodies stay (the walk deletes them,
    // or detach takes them out later).
    attached_ = false;
    world_->removeAction(hook_.get());
    unorderContacts();
    unregisterGroupShapeAlgorithms(collisionDispatcher(*world_));
    attachedWorld_.reset();
    for (auto& joint : joints_) world_->removeConstraint(joint->constraint_.get());
    joints_.clear();
}

bool Plugin::worldReachable() const { return watch_ && inWorld(*watch_); }

void Plugin::takeOutOfWorld(VisualBody& body) {
    if (inWorld(body.rigidBody())) world_->removeRigidBody(&body.rigidBody());
}

void Plugin::forgetDeletedBody(VisualBody& body) {
    // Bullet's samples take an object out of the world before deleting it; its joints are
    // still there.
    forgetEverywhere(body);
    push(EventType::BodyRemoved, body.id(), -1, body.name());
    std::erase_if(bodies_, [&](const auto& b) { return b.get() == &body; });
}

void Plugin::forgetEverywhere(VisualBody& body) {
    for (System* system : stepOrder())
        if (system) system->forget(body);
    for (size_t i = joints_.size(); i-- > 0;)
        if (joints_[i]->bodyA_ == &body || joints_[i]->bodyB_ == &body) removeJoint(i);
    contacts_.forget(&body.rigidBody());
    massRatios_.forget(body.rigidBody());
    applicationBodies_.erase(&body.rigidBody());
}

void Plugin::forgetDeletedJoint(Joint& joint) {
    std::erase_if(joints_, [&](const auto& j) { return j.get() == &joint; });
}

VisualBody& Plugin::addVisualBody(const geometry::PhysicalMesh& mesh, const BodySettings& settings,
                                  const btTransform& pose) {
    VisualBody& body = addBody(mesh, settings, pose);
    warnAboutPrecision(body);
    if (settings.fracture.enabled) fractures().add(body);
    if (settings.tear.enabled) tears().add(body);
    return body;
}

BodySettings Plugin::settingsInWorld(const BodySettings& settings) const {
    if (!attached_) throw InputError("shatter::Plugin: a body added after detach");
    BodySettings used = settings;
    used.solver.gravity = toEigen(world_->getGravity());
    return used;
}

VisualBody& Plugin::addBody(geometry::PhysicalMesh mesh, const BodySettings& settings, const btTransform& pose,
                            const std::function<void(VisualBody&, CollisionFilter&)>& prepare) {
    return enter(std::make_unique<VisualBody>(nextBodyId_, std::move(mesh), settingsInWorld(settings), pose), prepare);
}

VisualBody& Plugin::addPart(VisualBody& parent, geometry::PhysicalMesh part, const std::vector<int>& parents) {
    // It enters the world where a new body of the part would, then moves where it is, as one
    // that took its particles (takeParticles) would: the same broadphase pairs, in the same order.
    VisualBody& body =
        enter(std::make_unique<VisualBody>(nextBodyId_, parent, std::move(part), parents, settingsInWorld(parent.settings())), {});
    body.fitShapeBox();
    world_->updateSingleAabb(&body.rigidBody());
    return body;
}

VisualBody& Plugin::enter(std::unique_ptr<VisualBody> body,
                          const std::function<void(VisualBody&, CollisionFilter&)>& prepare) {
    ++nextBodyId_;
    body->onRigidBodyDeleted([this](VisualBody& deleted) { forgetDeletedBody(deleted); });
    if (prepare) {
        CollisionFilter filter;
        if (body->rigidBody().isStaticOrKinematicObject()) filter = {int(btBroadphaseProxy::StaticFilter),
                                                                     int(btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter)};
        prepare(*body, filter);
        body->readyToEnter();
        world_->addRigidBody(&body->rigidBody(), filter.group, filter.mask);
    } else {
        body->readyToEnter();
        world_->addRigidBody(&body->rigidBody());
    }
    push(EventType::BodyAdded, body->id(), -1, body->name());
    bodies_.push_back(std::move(body));
    // A deformable body deforms whoever made it (the application, or a tear's parts).
    VisualBody& added = *bodies_.back();
    if (added.deformation() != Deformation::None) {
        if (!deformation_) deformation_ = std::make_unique<DeformationSystem>(context());
        deformation_->add(added);
    }
    return added;
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
        added.joints.push_back(&addJoint(box, *added.bodies[a], *added.bodies[b]));
    }
    return added;
}

void Plugin::addJointConstraint(Joint& joint, VisualBody& a, VisualBody& b) {
    joint.bodyA_ = &a;
    joint.bodyB_ = &b;
    joint.constraint_.reset(makeJointConstraint(joint.box_, a.rigidBody(), toBullet(a.meshToBody()), b.rigidBody(),
                                                toBullet(b.meshToBody())),
                            [this, &joint] { forgetDeletedJoint(joint); });
    const double breaking = std::max(a.settings().jointBreakingImpulse, b.settings().jointBreakingImpulse);
    if (breaking > 0.0) joint.constraint_->setBreakingImpulseThreshold(btScalar(breaking));
    world_->addConstraint(joint.constraint_.get(), /*disableCollisionsBetweenLinkedBodies=*/true);
}

LatticeBody& Plugin::addLatticeBody(const lattice::TetMesh& mesh, const LatticeSettings& settings,
                                    const btTransform& pose) {
    if (!attached_) throw InputError("shatter::Plugin: addLatticeBody after detach");
    LatticeBody& body = lattices().add(mesh, resolveAnchors(mesh, settings, pose, *world_), pose);
    for (const auto& piece : body.pieces()) warnAboutPrecision(*piece.body);
    return body;
}

std::vector<VisualBody*> Plugin::fracture(VisualBody& body, const btVector3& point, const btVector3& direction) {
    return fractures().fracture(body, toEigen(point), toEigen(direction));
}

FractureSystem& Plugin::fractures() {
    if (!fractures_) fractures_ = std::make_unique<FractureSystem>(context());
    return *fractures_;
}

TearSystem& Plugin::tears() {
    if (!tears_) tears_ = std::make_unique<TearSystem>(context());
    return *tears_;
}

LatticeSystem& Plugin::lattices() {
    if (!lattices_) lattices_ = std::make_unique<LatticeSystem>(context());
    return *lattices_;
}

void Plugin::removeBody(VisualBody& body) {
    const auto it = std::find_if(bodies_.begin(), bodies_.end(), [&](const auto& b) { return b.get() == &body; });
    if (it == bodies_.end()) return;
    forgetEverywhere(body);
    takeOutOfWorld(body);
    push(EventType::BodyRemoved, body.id(), -1, body.name());
    bodies_.erase(it);
}

void Plugin::removeJoint(size_t index) {
    if (worldReachable()) world_->removeConstraint(joints_[index]->constraint_.get());
    joints_.erase(joints_.begin() + long(index));
}

void Plugin::removeJoint(const Joint& joint) {
    const auto it = std::find_if(joints_.begin(), joints_.end(), [&](const auto& j) { return j.get() == &joint; });
    if (it != joints_.end()) removeJoint(size_t(it - joints_.begin()));
}

void Plugin::warnAboutPrecision(const VisualBody& body) {
    applicationBodies_.insert(&body.rigidBody());
    geometry::Aabb box;
    for (const auto& primitive : body.physicalMesh().primitives) box.extend(primitive.bounds());
    const double inverseMass = body.rigidBody().getInvMass();
    const double mass = inverseMass > 0 ? 1.0 / inverseMass : 0.0;
    for (auto& warning : precisionWarnings(body.name(), mass, box.extent())) warnings_.push_back(std::move(warning));
}

// Once a simulated second: a pass over the manifolds costs about as much as a contact snapshot.
void Plugin::watchMassRatios() {
    if (time_ < nextMassRatioCheck_) return;
    nextMassRatioCheck_ = time_ + 1.0;
    const auto name = [this](const btCollisionObject& object) -> std::optional<std::string> {
        for (const auto& body : bodies_)
            if (&body->rigidBody() == &object)
                return applicationBodies_.count(&object) ? std::optional(body->name()) : std::nullopt;
        return std::string();
    };
    massRatios_.check(*world_->getDispatcher(), name, warnings_);
}

std::vector<std::string> Plugin::takeWarnings() { return std::exchange(warnings_, {}); }

std::vector<Event> Plugin::takeEvents() {
    std::vector<Event> out;
    out.swap(events_);
    return out;
}

void Plugin::reshape(VisualBody& body, const std::function<void(CollisionFilter&)>& change) {
    contacts_.forget(&body.rigidBody());
    outOfWorldWhile(*world_, body.rigidBody(), change);
    rebuildJoints(body);
}

bool Plugin::removeInWorld(VisualBody& body, const std::function<void()>& removal) {
    contacts_.forget(&body.rigidBody());
    btRigidBody& rigid = body.rigidBody();
    const btCollisionShape* shape = rigid.getCollisionShape();
    const GroupShape& group = body.shape();
    const std::uint64_t revision = group.revision();
    const btTransform before = rigid.getWorldTransform();
    removal();
    const std::vector<int> to = group.indexMapFrom(revision);
    const bool stays = rigid.getCollisionShape() == shape && group.revision() == revision + 1 && !to.empty();
    if (stays) {
        followRemoval(*world_->getDispatcher(), rigid, to, before);
        world_->updateSingleAabb(&rigid);
    } else {
        // Bullet's pairs hold algorithms made for the old shape: they go, with their manifolds
        // (nothing of the shape is read on the way out), and the body's pairs are made anew.
        outOfWorldWhile(*world_, rigid, [](CollisionFilter&) {});
    }
    rebuildJoints(body);
    return stays;
}

void Plugin::rebuildJoints(VisualBody& body) {
    for (auto& joint : joints_) {
        if (joint->bodyA_ != &body && joint->bodyB_ != &body) continue;
        const bool enabled = joint->constraint_->isEnabled();
        world_->removeConstraint(joint->constraint_.get());
        addJointConstraint(*joint, *joint->bodyA_, *joint->bodyB_);
        joint->constraint_->setEnabled(enabled);
    }
}

void Plugin::push(EventType type, const VisualBody& body, int count) { push(type, body.id(), -1, body.name(), count); }

void Plugin::push(Event event) {
    event.time = time_;
    events_.push_back(std::move(event));
}

std::vector<const Joint*> Plugin::jointsOf(const VisualBody& body) const {
    std::vector<const Joint*> out;
    for (const auto& joint : joints_)
        if (joint->bodyA_ == &body || joint->bodyB_ == &body) out.push_back(joint.get());
    return out;
}

Joint& Plugin::addJoint(const geometry::JointBox& box, VisualBody& a, VisualBody& b) {
    auto joint = std::make_unique<Joint>();
    joint->id_ = nextJointId_++;
    joint->box_ = box;
    addJointConstraint(*joint, a, b);
    push(EventType::JointAdded, -1, joint->id_, box.name);
    joints_.push_back(std::move(joint));
    return *joints_.back();
}

void Plugin::push(EventType type, int body, int joint, const std::string& name, int count) {
    events_.push_back({type, body, joint, time_, name, count, {}});
}

} // namespace shatter
