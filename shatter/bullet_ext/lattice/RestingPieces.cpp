// How LatticeSystem lets resting pieces sleep or freeze, and wakes frozen pieces that are hit
// (LatticeSettings: sleepAfter, sleepDrift, sleepTurn, freezeAtRest, wakeSpeed).
#include <shatter/bullet_ext/lattice/LatticeImpacts.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/bullet_ext/Plugin.h>

#include <BulletCollision/BroadphaseCollision/btBroadphaseInterface.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include <algorithm>
#include <unordered_set>

namespace shatter {

namespace {

// A manifold point this close (m), or overlapping, is a touch; farther ones are Bullet's
// speculative points within its contact breaking threshold.
constexpr btScalar kTouching = btScalar(0.001);

bool touching(const btPersistentManifold& m) {
    for (int k = 0; k < m.getNumContacts(); ++k)
        if (m.getContactPoint(k).getDistance() <= kTouching) return true;
    return false;
}

// The unit direction from `self` toward the other body of the manifold, averaged over its
// points (Bullet's normal on body 1 points toward body 0).
btVector3 towardOther(const btPersistentManifold& m, const btCollisionObject* self) {
    btVector3 n(0, 0, 0);
    for (int k = 0; k < m.getNumContacts(); ++k) n += m.getContactPoint(k).m_normalWorldOnB;
    if (m.getBody0() == self) n = -n;
    return n.fuzzyZero() ? n : n.normalized();
}

const btCollisionObject* other(const btPersistentManifold& m, const btCollisionObject* self) {
    return m.getBody0() == self ? m.getBody1() : m.getBody0();
}

// Bullet's own test for a body slow enough to sleep.
bool belowSleepingThresholds(const btRigidBody& b) {
    return b.getLinearVelocity().length2() < b.getLinearSleepingThreshold() * b.getLinearSleepingThreshold() &&
           b.getAngularVelocity().length2() < b.getAngularSleepingThreshold() * b.getAngularSleepingThreshold();
}

// Frozen pieces whose broadphase boxes overlap a box.
struct OverlapCollector : btBroadphaseAabbCallback {
    const LatticeSystem::FrozenIndex& frozen;
    std::vector<LatticeSystem::FrozenRef> found;
    explicit OverlapCollector(const LatticeSystem::FrozenIndex& f) : frozen(f) {}
    bool process(const btBroadphaseProxy* proxy) override {
        const auto it = frozen.find(static_cast<const btCollisionObject*>(proxy->m_clientObject));
        if (it != frozen.end()) found.push_back(it->second);
        return true;
    }
};

} // namespace

void LatticeSystem::settle(double dt) {
    // Runs inside the step after integration and before the world's updateActivationState,
    // which adds the step to the deactivation timer (or clears it if the body is above its
    // velocity thresholds right now) and marks a body whose timer passed gDeactivationTime
    // as ready (WANTS_DEACTIVATION).
    std::vector<LatticeBody::Piece*> rested;
    for (auto& body : bodies_) {
        const LatticeSettings& s = body->settings();
        for (auto& piece : body->mutablePieces()) {
            btRigidBody& rigid = piece.body->rigidBody();
            if (piece.frozen || rigid.getInvMass() == 0 || rigid.getActivationState() == ISLAND_SLEEPING ||
                rigid.getActivationState() == DISABLE_DEACTIVATION)
                continue;
            const btTransform& now = rigid.getWorldTransform();
            const btQuaternion turn = now.getRotation() * piece.restPose.getRotation().inverse();
            if (double((now.getOrigin() - piece.restPose.getOrigin()).length()) > s.sleepDrift ||
                double(turn.getAngleShortestPath()) > s.sleepTurn) {
                piece.restPose = now;
                piece.restFor = 0.0;
                continue;
            }
            piece.restFor += dt;
            if (piece.restFor < s.sleepAfter) continue;
            if (rigid.getDeactivationTime() <= gDeactivationTime) rigid.setDeactivationTime(gDeactivationTime);
            if (s.freezeAtRest && belowSleepingThresholds(rigid)) rested.push_back(&piece);
        }
    }
    freeze(rested);
}

void LatticeSystem::freeze(const std::vector<LatticeBody::Piece*>& rested) {
    if (rested.empty()) return;
    std::unordered_set<const btCollisionObject*> freezing;
    for (LatticeBody::Piece* p : rested) freezing.insert(&p->body->rigidBody());
    const FrozenIndex frozen = frozenPieces();
    const btVector3 gravity = plugin_.world().getGravity();
    const btVector3 up = gravity.fuzzyZero() ? btVector3(0, 0, 0) : -gravity.normalized();
    std::unordered_map<const btCollisionObject*, std::vector<LatticeBody::Piece::Support>> supports;
    btDispatcher& dispatcher = *plugin_.world().getDispatcher();
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
        const btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(m);
        if (!touching(manifold)) continue;
        for (const btCollisionObject* self : {manifold.getBody0(), manifold.getBody1()}) {
            if (!freezing.count(self)) continue;
            // What it leans or lies on, unless fixed for good (the ground, an anchored part):
            // not what lies on top of it.
            const btCollisionObject* o = other(manifold, self);
            const bool fixed = o->isStaticObject() && !frozen.count(o) && !freezing.count(o);
            if (!fixed && towardOther(manifold, self).dot(up) <= btScalar(0.5))
                supports[self].push_back({o, o->getWorldTransform().getOrigin()});
        }
    }
    for (LatticeBody::Piece* p : rested) {
        p->supports = std::move(supports[&p->body->rigidBody()]);
        p->frozenAs = freezeBody(plugin_.world(), p->body->rigidBody());
        p->frozen = true;
        ++timing_.frozen;
    }
}

LatticeSystem::FrozenIndex LatticeSystem::frozenPieces() {
    FrozenIndex frozen;
    for (auto& body : bodies_)
        for (auto& piece : body->mutablePieces())
            if (piece.frozen) frozen.emplace(&piece.body->rigidBody(), FrozenRef{body.get(), &piece});
    return frozen;
}

void LatticeSystem::noteBrokenOff(const btRigidBody& part) {
    btVector3 lo, hi;
    part.getCollisionShape()->getAabb(part.getWorldTransform(), lo, hi);
    brokenOff_.emplace_back(lo, hi);
}

void LatticeSystem::wakeHitPieces() {
    const FrozenIndex frozen = frozenPieces();
    const auto brokenOff = std::move(brokenOff_);
    brokenOff_.clear();
    if (frozen.empty()) return;
    std::vector<FrozenRef> hit;
    // Resting on (or against) a part that just broke off an anchored piece: the broken-off
    // part's box overlaps it. (Anchored parts are fixed for good until they break, so they are
    // not among the supports below.)
    for (const auto& [lo, hi] : brokenOff) {
        OverlapCollector overlaps(frozen);
        plugin_.world().getBroadphase()->aabbTest(lo, hi, overlaps);
        hit.insert(hit.end(), overlaps.found.begin(), overlaps.found.end());
    }
    // Hit by a dynamic body: a point of it approached the piece faster than the wake speed at
    // the start of the step.
    btDispatcher& dispatcher = *plugin_.world().getDispatcher();
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
        const btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(m);
        if (!touching(manifold)) continue;
        for (const btCollisionObject* self : {manifold.getBody0(), manifold.getBody1()}) {
            const auto it = frozen.find(self);
            const btCollisionObject* hitter = other(manifold, self);
            if (it == frozen.end() || hitter->isStaticOrKinematicObject()) continue;
            const btVector3 into = -towardOther(manifold, self);
            double approach = 0.0;
            for (int k = 0; k < manifold.getNumContacts(); ++k) {
                const btManifoldPoint& pt = manifold.getContactPoint(k);
                const btVector3 at = manifold.getBody0() == hitter ? pt.getPositionWorldOnA() : pt.getPositionWorldOnB();
                approach = std::max(approach, double(before_.velocityAt(*hitter, at).dot(into)));
            }
            if (approach > it->second.body->settings().wakeSpeed) hit.push_back(it->second);
        }
    }
    // By losing a support: something it leaned or lay on moved by more than the wake drift,
    // or left the world (a frozen support that wakes and moves counts the same).
    std::unordered_set<const btCollisionObject*> inWorld;
    for (auto& body : bodies_)
        for (auto& piece : body->mutablePieces()) {
            if (!piece.frozen || piece.supports.empty()) continue;
            if (inWorld.empty()) {
                const auto& objects = plugin_.world().getCollisionObjectArray();
                for (int i = 0; i < objects.size(); ++i) inWorld.insert(objects[i]);
            }
            const double drift = body->settings().wakeDrift;
            const bool lost = std::any_of(piece.supports.begin(), piece.supports.end(), [&](const auto& s) {
                return !inWorld.count(s.body) || double((s.body->getWorldTransform().getOrigin() - s.origin).length()) > drift;
            });
            if (lost) hit.push_back({body.get(), &piece});
        }
    // By a moving kinematic body: Bullet makes no pairs of kinematic and static bodies, so by
    // its box. (Kinematic bodies usually keep the static flag of their zero mass, so they are
    // looked for among all objects; Bullet sets their velocity from their motion each step.)
    const auto& objects = plugin_.world().getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i) {
        const btRigidBody* k = btRigidBody::upcast(objects[i]);
        if (!k || !k->isKinematicObject() || !k->isActive() ||
            (k->getLinearVelocity().fuzzyZero() && k->getAngularVelocity().fuzzyZero()))
            continue;
        btVector3 lo, hi;
        k->getCollisionShape()->getAabb(k->getWorldTransform(), lo, hi);
        OverlapCollector overlaps(frozen);
        plugin_.world().getBroadphase()->aabbTest(lo, hi, overlaps);
        hit.insert(hit.end(), overlaps.found.begin(), overlaps.found.end());
    }
    if (hit.empty()) return;
    // The hits were met by static bodies: take their impulses back from the hitters (the
    // frozen side got none), so the next step meets them with the pieces' own masses.
    std::unordered_set<const LatticeBody::Piece*> waking;
    std::unordered_map<const btCollisionObject*, int> watched;
    for (const FrozenRef& r : hit)
        if (waking.insert(r.piece).second) watched.emplace(&r.piece->body->rigidBody(), 0);
    for (const ContactImpulse& c : collectContactImpulses(dispatcher, watched)) undoContactImpulse(c);
    for (const FrozenRef& r : hit)
        if (r.piece->frozen) thaw(*r.piece);
}

void LatticeSystem::thaw(LatticeBody::Piece& piece) {
    thawBody(plugin_.world(), piece.body->rigidBody(), piece.frozenAs);
    piece.frozen = false;
    piece.supports.clear();
    piece.restPose = piece.body->rigidBody().getWorldTransform();
    piece.restFor = 0.0;
    ++timing_.thawed;
}

bool LatticeSystem::thaw(const btCollisionObject& body) {
    const FrozenIndex frozen = frozenPieces();
    const auto it = frozen.find(&body);
    if (it == frozen.end()) return false;
    thaw(*it->second.piece);
    return true;
}

void LatticeSystem::recordVelocities() {
    // Only frozen pieces need the velocities of the step before (wakeHitPieces).
    const bool anyFrozen = std::any_of(bodies_.begin(), bodies_.end(), [](const auto& b) { return b->frozenPieceCount() > 0; });
    if (anyFrozen) before_.record(plugin_.world());
}

} // namespace shatter
