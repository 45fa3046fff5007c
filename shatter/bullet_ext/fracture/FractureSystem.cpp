#include <shatter/bullet_ext/fracture/FractureSystem.h>
#include <shatter/plugin/common/Stopwatch.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/Joints.h>
#include <shatter/bullet_ext/SleepingThreshold.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/fracture/JointTransfer.h>
#include <shatter/bullet_ext/fracture/SubdivisionEvent.h>
#include <shatter/bullet_ext/shape/FragmentHull.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/fracture/FractureMesh.h>
#include <shatter/plugin/fracture/Placement.h>

#include <algorithm>

namespace shatter {

namespace {

constexpr size_t kKeptRecords = 256; // records not taken are dropped beyond this
constexpr double kHullShrink = 1e-3;  // of a many-primitive fragment's hull (makeFragment)

// The pairs whose impulses Bullet's solver applied in this step (a pair of two sleeping or
// static bodies still holds the impulses of the step they fell asleep in).
bool carriesImpulses(const ContactPair& pair) { return !pair.gone && pair.solved && pair.rigidA && pair.rigidB; }

// A seed of its own for every body (names are made in a fixed order: "vase.3.1"), so
// repeated breaks do not show the same twist of the pattern.
std::uint64_t bodySeed(std::uint64_t seed, const std::string& name) {
    std::uint64_t h = 1469598103934665603ull ^ seed;
    for (unsigned char c : name) h = (h ^ c) * 1099511628211ull;
    return h;
}

// Whether a fragment whose hull is clear is small enough to collide as its hull: the diagonal
// of its primitives' box below FractureSettings::hullBelow.
bool smallForAHull(const geometry::PhysicalMesh& mesh, double hullBelow) {
    if (hullBelow <= 0.0 || mesh.primitives.empty()) return false; // off (the default), or nothing
    geometry::Aabb box;
    for (const auto& p : mesh.primitives) box.extend(p.bounds());
    return box.diagonal() < hullBelow;
}

// The distance from `centre` of a box's farthest corner, squared: never less for a box that
// holds it (each step rounds monotonically), so a tree's box bounds what lies below it.
double farthestCorner(const geometry::Aabb& box, const Eigen::Vector3d& centre) {
    return (box.min - centre).cwiseAbs().cwiseMax((box.max - centre).cwiseAbs()).squaredNorm();
}

// How far a point of the body's primitives can lie from `centre` (m): the farthest corner of
// any primitive's box. It bounds the vertices' distance from above (the sleeping threshold
// errs on the side of staying awake) and reads one cached box per primitive, where the
// vertices of a 16,000-primitive rest cost 2.6 M instructions at every break. With the body's
// primitive tree (`byTree`), the subtrees whose box cannot hold a farther corner than one
// already found are left out, the child with the farther corner first (searchLargestFirst),
// so the bound is near the maximum after one descent. The maximum is the same, so the radius
// has the same bits. A break of the 16k shell turns ~470 tree boxes and reads ~3 primitives,
// each box a cache miss (the tree is cold after the cut): ~37 us of CPU per break, against
// ~160 us left child first (thread CPU clock around the search, 60 breaks). A new fragment
// does without the tree: it reads its few dozen boxes at ~20 instructions each.
double reach(const VisualBody& body, const Eigen::Vector3d& centre, bool byTree) {
    const auto& primitives = body.physicalMesh().primitives;
    const fracture::PrimitiveIndex index = byTree ? body.fractureIndex() : fracture::PrimitiveIndex{};
    double farthest = 0.0;
    auto atLeaf = [&](int p) { farthest = std::max(farthest, farthestCorner(primitives[size_t(p)].bounds(), centre)); };
    if (!index.tree || index.tree->empty() || index.tree->itemCount() != int(primitives.size())) {
        for (int p = 0; p < int(primitives.size()); ++p) atLeaf(p);
        return std::sqrt(farthest);
    }
    // A tree box moved to the mesh holds its primitives' boxes up to round-off far below
    // this margin (as in fractureMesh's use of the index).
    const geometry::Aabb all = geometry::transformedAabb(index.tree->bounds(), index.treeToMesh);
    const double scale = std::max({all.min.cwiseAbs().maxCoeff(), all.max.cwiseAbs().maxCoeff(),
                                   index.treeToMesh.translation().cwiseAbs().maxCoeff()});
    const double margin = 1e-9 * (1.0 + scale);
    index.tree->searchLargestFirst(
        [&](const geometry::Aabb& box) {
            return farthestCorner(geometry::transformedAabb(box, index.treeToMesh).inflated(margin), centre);
        },
        [&] { return farthest; }, atLeaf);
    return std::sqrt(farthest);
}

} // namespace

void FractureSystem::add(VisualBody& body) {
    const FractureSettings& s = body.settings().fracture;
    if (!s.enabled) throw InputError("body '" + body.name() + "': fracture is not enabled in its settings");
    if (s.mode == FractureMode::Shatter && body.deformation() != Deformation::None)
        throw InputError("body '" + body.name() + "': fracture needs a rigid body (deformation None)");
    auto pattern = std::make_shared<const fracture::FracturePattern>(s.makePattern(body.name()));
    breakable_.push_back({&body, s.depth, context_.time(), std::move(pattern)});
    if (s.mode == FractureMode::Shatter) body.prepareFracture(); // its set-up, not its first break's
}

std::vector<FractureSystem::Breakable>::iterator FractureSystem::entryOf(const VisualBody* body) {
    return std::find_if(breakable_.begin(), breakable_.end(), [&](const Breakable& b) { return b.body == body; });
}

bool FractureSystem::breakable(const VisualBody& body) const {
    return std::any_of(breakable_.begin(), breakable_.end(),
                       [&](const Breakable& b) { return b.body == &body && context_.time() >= b.readyAt; });
}

VisualBody& FractureSystem::makeFragment(const VisualBody& parent, geometry::PhysicalMesh mesh, bool moves,
                                         const btTransform& pose, bool asHull) {
    BodySettings settings = parent.settings();
    settings.dynamic = moves;
    const bool onePiece = mesh.primitives.size() == 1;
    if (!asHull && !onePiece) return context_.addBody(std::move(mesh), settings, pose);
    // A single convex piece, or a small fragment whose hull overlaps nothing, collides as a
    // plain hull: Bullet's own convex algorithms cost a fraction of the group shape's
    // per-primitive tests (FragmentHull.h). It is set before the body enters the world, so the
    // body's group shape is not built unless something asks for it later (VisualBody::collideAs).
    // A fragment of several primitives touches its neighbours along whole crack faces.
    // Bullet's contact between its hull and a group shape's primitive there finds depths
    // of up to 1.5e-4 of the fragment's size (a normal from GJK at zero distance, clipped
    // across a large face), which pushed the pieces apart; its hull shrunk by 1e-3 of its
    // size towards its centre of mass leaves those faces just apart (FractureSystem test
    // FragmentsThatCollideAsTheirHullDoNotPushEachOtherApart).
    const double margin = settings.rigidBody.collisionMargin;
    return context_.addBody(std::move(mesh), settings, pose, [&](VisualBody& body, CollisionFilter&) {
        std::unique_ptr<btConvexHullShape> hull;
        if (onePiece) {
            hull = makeFragmentHull(body.shapePrimitives(), margin);
        } else {
            // Shard corners that span no volume (below the hull computer's resolution) have no
            // hull: the shard keeps colliding as its primitives, as a shard above hullBelow does,
            // rather than an error thrown out of the world's step.
            try {
                hull = makeShardHull(body.shapePrimitives(), margin, kHullShrink);
            } catch (const InputError&) {
                return;
            }
        }
        body.collideAs(*hull);
        hulls_[&body] = std::move(hull);
    });
}

std::vector<VisualBody*> FractureSystem::replace(VisualBody& parent, std::vector<geometry::PhysicalMesh> fragments,
                                                 int remainder) {
    return breakApart(parent, std::move(fragments), remainder, nullptr, {});
}

namespace {

// A body's motion in world coordinates with its exact mass properties; a static one is at rest.
geometry::RigidState motionBefore(const VisualBody& body, const Eigen::Isometry3d& toWorld, bool dynamic) {
    const btRigidBody& rigid = body.rigidBody();
    return geometry::rigidState(geometry::transformed(body.physicalMesh().mass, toWorld),
                                dynamic ? toEigen(rigid.getLinearVelocity()) : Eigen::Vector3d::Zero(),
                                dynamic ? toEigen(rigid.getAngularVelocity()) : Eigen::Vector3d::Zero());
}

} // namespace

std::vector<VisualBody*> FractureSystem::breakApart(VisualBody& parent, std::vector<geometry::PhysicalMesh> fragments,
                                                    int remainder, fracture::RemainderEdit* rest,
                                                    const std::vector<bool>& hullIsClear) {
    const auto t = SteadyClock::now();
    const auto it = entryOf(&parent);
    const int depthLeft = it == breakable_.end() ? 0 : it->depthLeft;
    const auto pattern = it == breakable_.end() ? nullptr : it->pattern;
    const int firstName = it == breakable_.end() ? 0 : it->fragmentsNamed;
    // The parent's motion in world coordinates with its exact mass properties; a static
    // parent is at rest.
    const btTransform pose = parent.meshTransform();
    const Eigen::Isometry3d toWorld = toEigen(pose);
    const btRigidBody& rigid = parent.rigidBody();
    const bool dynamic = rigid.getInvMass() > 0;
    Record record;
    record.parent = parent.id();
    record.time = context_.time();
    record.before = motionBefore(parent, toWorld, dynamic);
    const FractureSettings& s = parent.settings().fracture;
    std::vector<VisualBody*> bodies;
    // `rest`: the parent, edited in place, whose tree is worth searching (16k primitives).
    auto setMotion = [&](VisualBody& body, const geometry::MassProperties& mass, bool moves, bool rest) {
        const geometry::RigidState state = geometry::partState(record.before, geometry::transformed(mass, toWorld));
        if (moves) {
            // A shard of a few centimetres lying in the heap must be able to sleep (SleepingThreshold.h).
            sleepWhenNoPointIsFast(body.rigidBody(), btScalar(reach(body, mass.centerOfMass, rest)));
            body.rigidBody().setLinearVelocity(toBullet(state.velocity));
            body.rigidBody().setAngularVelocity(toBullet(state.angularVelocity));
        }
        record.parts.push_back(state);
        record.bodies.push_back(&body);
        bodies.push_back(&body);
    };
    for (int k = 0; k < int(fragments.size()); ++k) {
        fragments[k].name = parent.name() + "." + std::to_string(firstName + k);
        const bool moves = dynamic || k != remainder;
        const bool asHull = !hullIsClear.empty() && hullIsClear[size_t(k)] && smallForAHull(fragments[k], s.hullBelow);
        // The body takes the fragment's mesh; its physicalMesh() is that mesh from here on.
        VisualBody& body = makeFragment(parent, std::move(fragments[k]), moves, pose, asHull);
        setMotion(body, body.physicalMesh().mass, moves, false);
        if (depthLeft > 0 && pattern) breakable_.push_back({&body, depthLeft - 1, context_.time() + s.coolDown, pattern});
    }
    const std::vector<VisualBody*> made = bodies;
    if (rest) {
        // The parent stays as the rest: it keeps its id, name, joints (rebuilt at its new
        // frame by reshape) and a static parent stays static.
        // fractureMesh's edit of this body as it made it: its touched list is complete.
        context_.reshape(parent, [&](CollisionFilter&) {
            parent.keepRemainder(*rest, std::move(rest->added), fracture::TouchedList::FromEveryConnection);
        });
        setMotion(parent, rest->mass, dynamic, true);
        reportRestJoints(parent);
        scheduleRest(parent, depthLeft, firstName + int(fragments.size()));
    }
    announce(parent, made, bodies);
    keepApart(bodies, s.contactDelaySteps); // before the parent (and `s`, its settings) may go
    if (!rest) context_.removeBody(parent); // its joints go with it; forget() is called first
    records_.push_back(std::move(record));
    if (records_.size() > kKeptRecords) records_.erase(records_.begin());
    lastEventTime_ = context_.time();
    ++timing_.events;
    timing_.fragments += int(bodies.size());
    timing_.bodies += secondsSince(t);
    return bodies;
}

// The rest's joints were rebuilt for it (new frame, same id): reported as re-created for the
// piece that holds them, the joint being its own old joint.
void FractureSystem::reportRestJoints(const VisualBody& parent) {
    for (const Joint* joint : context_.jointsOf(parent)) {
        if (joint->broken()) continue;
        context_.push(Event{EventType::JointRecreated, parent.id(), joint->id(), 0.0, joint->name(), joint->id(), {}});
        ++timing_.jointsRecreated;
    }
}

// The rest breaks again after its cool-down while generations are left (naming its next
// fragments on from `fragmentsNamed`); else it is no longer breakable.
void FractureSystem::scheduleRest(const VisualBody& parent, int depthLeft, int fragmentsNamed) {
    const auto self = entryOf(&parent);
    if (self == breakable_.end()) return;
    if (depthLeft <= 0) {
        breakable_.erase(self);
        return;
    }
    self->depthLeft = depthLeft - 1;
    self->readyAt = context_.time() + parent.settings().fracture.coolDown;
    self->waiting = false; // a hit kept from before the break is not on this rest
    self->fragmentsNamed = fragmentsNamed;
}

// The parent's joints go to the fragments `made` that hold them; then the event, naming every
// body of the break (`bodies`: `made` and the rest, if the parent stays as it).
void FractureSystem::announce(VisualBody& parent, const std::vector<VisualBody*>& made,
                              const std::vector<VisualBody*>& bodies) {
    std::vector<const geometry::PhysicalMesh*> meshes;
    meshes.reserve(made.size());
    for (const VisualBody* body : made) meshes.push_back(&body->physicalMesh());
    timing_.jointsRecreated += transferJoints(context_, parent, made, meshes);
    Event fractured{EventType::BodyFractured, parent.id(), -1, 0.0, parent.name(), int(bodies.size()), {}};
    for (const VisualBody* b : bodies) fractured.fragments.push_back(b->id());
    context_.push(std::move(fractured));
}

void FractureSystem::keepApart(const std::vector<VisualBody*>& bodies, int steps) {
    if (steps <= 0 || bodies.size() < 2) return;
    for (VisualBody* a : bodies)
        for (VisualBody* b : bodies)
            if (a != b) a->rigidBody().setIgnoreCollisionCheck(&b->rigidBody(), true);
    // Ignored from the next step's collision detection on; step() lets them meet again at the
    // end of step `until`, after `steps` steps' collision detection passed them by.
    apart_.push_back({bodies, steps_ + steps});
}

namespace {

// Lets `body` and `others` collide again (undoes keepApart between them).
void meetAgain(VisualBody& body, const std::vector<VisualBody*>& others) {
    for (VisualBody* other : others) {
        if (other == &body) continue;
        body.rigidBody().setIgnoreCollisionCheck(&other->rigidBody(), false);
        other->rigidBody().setIgnoreCollisionCheck(&body.rigidBody(), false);
    }
}

} // namespace

std::vector<VisualBody*> FractureSystem::fracture(VisualBody& body, const Eigen::Vector3d& point,
                                                  const Eigen::Vector3d& direction) {
    return breakAt(body, point, direction, nullptr, 0.0);
}

std::vector<VisualBody*> FractureSystem::breakAt(VisualBody& body, const Eigen::Vector3d& point,
                                                 const Eigen::Vector3d& direction, const ContactSnapshot* contacts,
                                                 double dt) {
    auto t = SteadyClock::now();
    const auto it = entryOf(&body);
    if (it == breakable_.end() && !body.settings().fracture.enabled)
        throw InputError("body '" + body.name() + "': fracture is not enabled in its settings");
    const FractureSettings& s = body.settings().fracture;
    // The impact in rest coordinates; a sheet (glass) is cut through its thinnest axis.
    const Eigen::Isometry3d toMesh = toEigen(body.meshTransform()).inverse();
    fracture::Placement where;
    where.point = toMesh * point;
    where.normal = toMesh.linear() * direction;
    where.check(body.name());
    if (it == breakable_.end() || context_.time() < it->readyAt) return {};
    const auto pattern = it->pattern;
    if (s.pattern == PatternKind::Glass) where.normal = fracture::thinnestAxis(body.physicalMesh(), where.normal);
    where.twist = fracture::seededTwist(bodySeed(s.seed, body.name()));
    timing_.placement += secondsSince(t);
    if (s.mode == FractureMode::Subdivide) { // the body stays, cut finer (SubdivisionEvent.h)
        const SubdivisionOutcome done = subdivideInPlace(
            context_, body, *pattern, where, {s.minimumPieceSize, fracture::CutSettings{}.snapTolerance}, contacts, dt);
        timing_.cutting += done.cutSeconds;
        timing_.visualMesh += done.assemblySeconds;
        timing_.bodies += done.bodySeconds;
        timing_.primitivesCut += done.primitivesCut;
        it->readyAt = context_.time() + s.coolDown;
        if (done.primitivesCut > 0) {
            ++timing_.subdivisions;
            lastEventTime_ = context_.time(); // an event of the budget too
            if (it->depthLeft-- == 0) breakable_.erase(it); // it stays in the world, no longer subdivides
        }
        return {};
    }
    fracture::CutSettings cutSettings;
    cutSettings.minimumPieceSize = s.minimumPieceSize;
    // The rest stays the parent body, edited, unless a joint of the parent would not hold it
    // any more (the joint must then leave the parent, which only removing the parent does).
    cutSettings.remainderInPlace = true;
    fracture::FractureResult cut = fracture::fractureMesh(body.physicalMesh(), *pattern, where, cutSettings, body.fractureIndex());
    // fractureMesh times its own phases.
    timing_.placement += cut.seconds.placement;
    timing_.cutting += cut.seconds.cutting;
    timing_.islands += cut.seconds.islands;
    timing_.visualMesh += cut.seconds.assembly;
    timing_.primitivesCut += cut.primitivesCut;
    if (cut.pieces.size() + (cut.remainderEdit ? 1 : 0) < 2) {
        it->readyAt = context_.time() + s.coolDown; // nothing came off: not again at once
        return {};
    }
    if (cut.remainderEdit && !jointsStayWithRemainder(body, *cut.remainderEdit)) {
        // Undo the edit's shortcut: the rest becomes a new body like the fragments.
        geometry::PhysicalMesh mesh = body.physicalMesh();
        fracture::applyRemainderEdit(mesh, *cut.remainderEdit);
        cut.remainder = int(cut.pieces.size());
        cut.pieces.push_back(std::move(mesh));
        cut.hullIsClear.push_back(false);
        cut.remainderEdit.reset();
    }
    return breakApart(body, std::move(cut.pieces), cut.remainder, cut.remainderEdit ? &*cut.remainderEdit : nullptr,
                      cut.hullIsClear);
}

bool FractureSystem::jointsStayWithRemainder(const VisualBody& parent, const fracture::RemainderEdit& rest) const {
    const auto joints = context_.jointsOf(parent);
    if (std::none_of(joints.begin(), joints.end(), [](const Joint* j) { return !j->broken(); })) return true;
    geometry::PhysicalMesh mesh; // only the primitives matter to fragmentsTouchingBox
    std::vector<char> removed(parent.physicalMesh().primitives.size(), 0);
    for (int i : rest.removed) removed[size_t(i)] = 1;
    for (size_t i = 0; i < removed.size(); ++i)
        if (!removed[i]) mesh.primitives.push_back(parent.physicalMesh().primitives[i]);
    mesh.primitives.insert(mesh.primitives.end(), rest.added.begin(), rest.added.end());
    const std::vector<geometry::PhysicalMesh> meshes{std::move(mesh)};
    for (const Joint* joint : joints)
        if (!joint->broken() && fragmentsTouchingBox(meshes, joint->box(), parent.physicalMesh().contactTolerance).empty())
            return false;
    return true;
}

bool FractureSystem::strongestImpact(const Breakable& b, const ContactSnapshot& contacts, Impact& impact) const {
    const btCollisionObject* self = &b.body->rigidBody();
    double strongest = b.body->settings().fracture.threshold;
    bool found = false;
    for (int index : contacts.pairsOf(self)) {
        const ContactPair& pair = contacts.pairs()[size_t(index)];
        if (!carriesImpulses(pair)) continue;
        // The pair's impulse on the body, applied where its points are, weighted by their share.
        Eigen::Vector3d total = Eigen::Vector3d::Zero(), where = Eigen::Vector3d::Zero();
        double weight = 0.0;
        for (const ContactPoint& p : contacts.points(pair)) {
            const Eigen::Vector3d j = toEigen(ContactSnapshot::impulseOn(pair, p, self));
            total += j;
            where += j.norm() * toEigen(ContactSnapshot::pointOn(pair, p, self));
            weight += j.norm();
        }
        if (total.norm() <= strongest || weight <= 0.0) continue;
        strongest = total.norm();
        impact = {b.body, where / weight, total};
        found = true;
    }
    return found;
}

bool FractureSystem::budgetAllows(const VisualBody& body, double dt) const {
    return context_.time() - lastEventTime_ > (body.settings().fracture.eventSpacingSteps - 0.5) * dt;
}

void FractureSystem::step(double dt, const ContactSnapshot& contacts) {
    retired_.clear();
    ++steps_;
    // Pieces whose contact delay ended with this step's collision detection meet from the next.
    std::erase_if(apart_, [&](Apart& apart) {
        if (apart.until > steps_) return false;
        for (VisualBody* body : apart.bodies) meetAgain(*body, apart.bodies);
        return true;
    });
    auto t = SteadyClock::now();
    std::vector<Impact> impacts;
    for (const Breakable& b : breakable_) {
        Impact impact;
        if (context_.time() >= b.readyAt && strongestImpact(b, contacts, impact)) impacts.push_back(impact);
    }
    timing_.impacts += secondsSince(t);
    // Hits kept from earlier steps go first, in the order the bodies were added, as the budget
    // allows: a fresh hit must not take the budget from one that has waited (it would wait on).
    // Taken by body, as a break may add bodies to breakable_ or remove its parent from it.
    std::vector<VisualBody*> waiting, brokeNow;
    for (const Breakable& b : breakable_)
        if (b.waiting) waiting.push_back(b.body);
    for (VisualBody* body : waiting) {
        const auto it = entryOf(body);
        if (it == breakable_.end() || !it->waiting || !budgetAllows(*body, dt)) continue;
        it->waiting = false;
        const Eigen::Isometry3d toWorld = toEigen(body->meshTransform());
        const Eigen::Vector3d point = toWorld * it->waitingPoint, direction = toWorld.linear() * it->waitingDirection;
        brokeNow.push_back(body);
        breakAt(*body, point, direction, &contacts, dt);
    }
    // Then this step's hits: each body breaks once per step, in the order the bodies were
    // added (fragments, new this step, have none). A hit the event budget does not allow now
    // waits, in rest coordinates; a body's first waiting hit stays.
    for (const Impact& impact : impacts) {
        if (std::find(brokeNow.begin(), brokeNow.end(), impact.body) != brokeNow.end()) continue;
        const auto it = entryOf(impact.body);
        if (it == breakable_.end() || it->waiting) continue;
        if (budgetAllows(*impact.body, dt)) {
            breakAt(*impact.body, impact.point, impact.direction, &contacts, dt);
            continue;
        }
        const Eigen::Isometry3d toMesh = toEigen(impact.body->meshTransform()).inverse();
        it->waiting = true;
        it->waitingPoint = toMesh * impact.point;
        it->waitingDirection = toMesh.linear() * impact.direction;
    }
}

void FractureSystem::forget(VisualBody& body) {
    std::erase_if(breakable_, [&](const Breakable& b) { return b.body == &body; });
    // No sibling may keep ignoring the address of a body that leaves (a new body may get it).
    for (Apart& apart : apart_) {
        if (std::find(apart.bodies.begin(), apart.bodies.end(), &body) == apart.bodies.end()) continue;
        meetAgain(body, apart.bodies);
        std::erase(apart.bodies, &body);
    }
    std::erase_if(apart_, [](const Apart& apart) { return apart.bodies.size() < 2; });
    // The shape is still the body's until the body has left the world.
    if (const auto hull = hulls_.find(&body); hull != hulls_.end()) {
        retired_.push_back(std::move(hull->second));
        hulls_.erase(hull);
    }
    for (auto& record : records_) std::replace(record.bodies.begin(), record.bodies.end(), &body, (VisualBody*)nullptr);
}

std::vector<FractureSystem::Record> FractureSystem::takeRecords() {
    std::vector<Record> out;
    out.swap(records_);
    return out;
}

} // namespace shatter

