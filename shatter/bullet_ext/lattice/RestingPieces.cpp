#include <shatter/bullet_ext/lattice/RestingPieces.h>

#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/lattice/ImpulseTakeBack.h>

#include <BulletCollision/BroadphaseCollision/btBroadphaseInterface.h>

#include <algorithm>
#include <limits>
#include <unordered_set>

namespace shatter {

namespace {

// A contact point this close (m), or overlapping, is a touch; farther ones are Bullet's
// speculative points within its contact breaking threshold.
constexpr btScalar kTouching = btScalar(0.001);

bool touching(const ContactSnapshot& contacts, const ContactPair& pair) {
    if (pair.gone) return false;
    for (const ContactPoint& p : contacts.points(pair))
        if (p.distance <= kTouching) return true;
    return false;
}

// The unit direction from `self` toward the other body of the pair, averaged over its points
// (Bullet's normal on body B points toward body A).
btVector3 towardOther(const ContactSnapshot& contacts, const ContactPair& pair, const btCollisionObject* self) {
    btVector3 n(0, 0, 0);
    for (const ContactPoint& p : contacts.points(pair)) n += p.normalOnB;
    if (pair.a == self) n = -n;
    return n.fuzzyZero() ? n : n.normalized();
}

// Bullet's own test for a body slow enough to sleep.
bool belowSleepingThresholds(const btRigidBody& b) {
    return b.getLinearVelocity().length2() < b.getLinearSleepingThreshold() * b.getLinearSleepingThreshold() &&
           b.getAngularVelocity().length2() < b.getAngularSleepingThreshold() * b.getAngularSleepingThreshold();
}

// Frozen pieces whose broadphase boxes overlap a box.
struct OverlapCollector : btBroadphaseAabbCallback {
    const RestingPieces::FrozenIndex& frozen;
    std::vector<RestingPieces::FrozenRef> found;
    explicit OverlapCollector(const RestingPieces::FrozenIndex& f) : frozen(f) {}
    bool process(const btBroadphaseProxy* proxy) override {
        const auto it = frozen.find(static_cast<const btCollisionObject*>(proxy->m_clientObject));
        if (it != frozen.end()) found.push_back(it->second);
        return true;
    }
};

// A body's mass for the wake rules (RestSettings::wakeMassRatio): a frozen piece's own,
// infinite for other static and for kinematic bodies (fixed, or moved by the application) and
// for what is no rigid body (a soft body: as before the rule, it always counts).
double wakeMass(const btCollisionObject* o, const RestingPieces::FrozenIndex& frozen) {
    const auto it = frozen.find(o);
    if (it != frozen.end()) return double(it->second.piece->frozenAs.mass);
    const btRigidBody* r = btRigidBody::upcast(o);
    if (!r || r->getInvMass() == 0) return std::numeric_limits<double>::infinity();
    return 1.0 / double(r->getInvMass());
}

void collectOverlaps(btDiscreteDynamicsWorld& world, const btVector3& lo, const btVector3& hi,
                     const RestingPieces::FrozenIndex& frozen, std::vector<RestingPieces::FrozenRef>& out) {
    OverlapCollector overlaps(frozen);
    world.getBroadphase()->aabbTest(lo, hi, overlaps);
    out.insert(out.end(), overlaps.found.begin(), overlaps.found.end());
}

} // namespace

RestingPieces::Counts RestingPieces::step(double dt, const ContactSnapshot& contacts) {
    Counts counts;
    counts.thawed = wakeHitPieces(contacts, dt);
    counts.frozen = settle(dt, contacts);
    return counts;
}

int RestingPieces::settle(double dt, const ContactSnapshot& contacts) {
    // updateActivationState runs after this: it adds the step to the deactivation timer (or
    // clears it if the body is above its velocity thresholds right now) and marks a body whose
    // timer passed gDeactivationTime as ready (WANTS_DEACTIVATION).
    std::vector<Rested> rested;
    // What touches something: a piece in flight is never at rest, though at the top of a throw
    // it stays within sleepDrift (5 mm) for 0.05 s (g t²/8 = 3 mm), more than debris' sleepAfter.
    std::unordered_set<const btCollisionObject*> touches;
    for (const ContactPair& pair : contacts.pairs())
        if (touching(contacts, pair)) touches.insert({pair.a, pair.b});
    for (auto& body : bodies_) {
        const LatticeSettings& s = body->settings();
        for (auto& piece : body->mutablePieces()) {
            btRigidBody& rigid = piece.body->rigidBody();
            if (piece.frozen || piece.splitPending || rigid.getInvMass() == 0 || rigid.getActivationState() == ISLAND_SLEEPING ||
                rigid.getActivationState() == DISABLE_DEACTIVATION)
                continue;
            const btTransform& now = rigid.getWorldTransform();
            const btQuaternion turn = now.getRotation() * piece.restPose.getRotation().inverse();
            if (double((now.getOrigin() - piece.restPose.getOrigin()).length()) > s.rest.sleepDrift ||
                double(turn.getAngleShortestPath()) > s.rest.sleepTurn) {
                piece.restPose = now;
                piece.restFor = 0.0;
                continue;
            }
            piece.restFor += dt;
            if (piece.restFor < (piece.debris ? s.debris.sleepAfter : s.rest.sleepAfter) || !touches.count(&rigid)) continue;
            if (rigid.getDeactivationTime() <= gDeactivationTime) rigid.setDeactivationTime(gDeactivationTime);
            if (s.rest.freezeAtRest && belowSleepingThresholds(rigid))
                rested.push_back({&piece, s.rest.wakeMassRatio * double(rigid.getMass())});
        }
    }
    return freeze(rested, contacts);
}

int RestingPieces::freeze(const std::vector<Rested>& rested, const ContactSnapshot& contacts) {
    if (rested.empty()) return 0;
    std::unordered_map<const btCollisionObject*, double> freezing; // -> lightBelow
    for (const Rested& r : rested) freezing.emplace(&r.piece->body->rigidBody(), r.lightBelow);
    const FrozenIndex frozen = frozenPieces();
    const btVector3 gravity = context_.world().getGravity();
    const btVector3 up = gravity.fuzzyZero() ? btVector3(0, 0, 0) : -gravity.normalized();
    std::unordered_map<const btCollisionObject*, std::vector<LatticeBody::Piece::Support>> supports;
    for (const ContactPair& pair : contacts.pairs()) {
        if (!touching(contacts, pair)) continue;
        for (const btCollisionObject* self : {pair.a, pair.b}) {
            const auto me = freezing.find(self);
            if (me == freezing.end()) continue;
            // What it leans or lies on, unless fixed for good (the ground, an anchored part)
            // or too light to hold it: not what lies on top of it.
            const btCollisionObject* o = pair.other(self);
            const bool fixed = o->isStaticObject() && !frozen.count(o) && !freezing.count(o);
            if (!fixed && wakeMass(o, frozen) >= me->second && towardOther(contacts, pair, self).dot(up) <= btScalar(0.5))
                supports[self].push_back({o, o->getWorldTransform().getOrigin()});
        }
    }
    for (const Rested& r : rested) {
        LatticeBody::Piece* p = r.piece;
        p->supports = std::move(supports[&p->body->rigidBody()]);
        btRigidBody& rigid = p->body->rigidBody();
        context_.reshape(*p->body, [&](CollisionFilter& filter) { p->frozenAs = freezeBody(rigid, filter); });
        p->frozen = true;
    }
    return int(rested.size());
}

RestingPieces::FrozenIndex RestingPieces::frozenPieces() {
    FrozenIndex frozen;
    for (auto& body : bodies_)
        for (auto& piece : body->mutablePieces())
            if (piece.frozen) frozen.emplace(&piece.body->rigidBody(), FrozenRef{body.get(), &piece});
    return frozen;
}

bool RestingPieces::anyFrozen() const {
    return std::any_of(bodies_.begin(), bodies_.end(), [](const auto& b) { return b->frozenPieceCount() > 0; });
}

void RestingPieces::noteBrokenOff(const btRigidBody& part) {
    // The box the world sees (a fragment hull's own box is shrunk by what the world adds).
    btVector3 lo, hi;
    part.getCollisionShape()->getAabb(part.getWorldTransform(), lo, hi);
    const btVector3 grow(gContactBreakingThreshold, gContactBreakingThreshold, gContactBreakingThreshold);
    brokenOff_.emplace_back(lo - grow, hi + grow);
}

int RestingPieces::wakeHitPieces(const ContactSnapshot& contacts, double dt) {
    const FrozenIndex frozen = frozenPieces();
    const auto brokenOff = std::move(brokenOff_);
    brokenOff_.clear();
    if (frozen.empty()) return 0;
    btDiscreteDynamicsWorld& world = context_.world();
    std::vector<FrozenRef> hit;
    // Resting on (or against) a part that just broke off an anchored piece: the broken-off
    // part's box overlaps it.
    for (const auto& [lo, hi] : brokenOff) collectOverlaps(world, lo, hi, frozen, hit);
    // Hit by a dynamic body: a point of it approached the piece faster than the wake speed at
    // the start of the step.
    for (const ContactPair& pair : contacts.pairs()) {
        if (!touching(contacts, pair)) continue;
        for (const btCollisionObject* self : {pair.a, pair.b}) {
            const auto it = frozen.find(self);
            const btCollisionObject* hitter = pair.other(self);
            if (it == frozen.end() || hitter->isStaticOrKinematicObject()) continue;
            const double lightBelow = it->second.body->settings().rest.wakeMassRatio * double(it->second.piece->frozenAs.mass);
            if (wakeMass(hitter, frozen) < lightBelow) continue; // a shard bounces off it
            const btVector3 into = -towardOther(contacts, pair, self);
            double approach = 0.0;
            for (const ContactPoint& p : contacts.points(pair)) {
                const btVector3& at = ContactSnapshot::pointOn(pair, p, hitter);
                approach = std::max(approach, double(pair.before(hitter).velocityAt(at).dot(into)));
            }
            if (approach > it->second.body->settings().rest.wakeSpeed) hit.push_back(it->second);
        }
    }
    // By losing a support: something it leaned or lay on moved by more than the wake drift,
    // or left the world (a frozen support that wakes and moves counts the same).
    std::unordered_set<const btCollisionObject*> inWorld;
    for (auto& body : bodies_)
        for (auto& piece : body->mutablePieces()) {
            if (!piece.frozen || piece.supports.empty()) continue;
            if (inWorld.empty()) {
                const auto& objects = world.getCollisionObjectArray();
                for (int i = 0; i < objects.size(); ++i) inWorld.insert(objects[i]);
            }
            const double drift = body->settings().rest.wakeDrift;
            const bool lost = std::any_of(piece.supports.begin(), piece.supports.end(), [&](const auto& s) {
                return !inWorld.count(s.body) || double((s.body->getWorldTransform().getOrigin() - s.origin).length()) > drift;
            });
            if (lost) hit.push_back({body.get(), &piece});
        }
    // By a moving kinematic body: Bullet makes no pairs of kinematic and static bodies, so by
    // its box. (Kinematic bodies usually keep the static flag of their zero mass, so they are
    // looked for among all objects; Bullet sets their velocity from their motion each step.)
    const auto& objects = world.getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i) {
        const btRigidBody* k = btRigidBody::upcast(objects[i]);
        if (!k || !k->isKinematicObject() || !k->isActive() ||
            (k->getLinearVelocity().fuzzyZero() && k->getAngularVelocity().fuzzyZero()))
            continue;
        btVector3 lo, hi;
        k->getCollisionShape()->getAabb(k->getWorldTransform(), lo, hi);
        collectOverlaps(world, lo, hi, frozen, hit);
    }
    if (hit.empty()) return 0;
    // The hits were met by static bodies: take their impulses back from the hitters (the
    // frozen side got none), so the next step meets them with the pieces' own masses.
    std::unordered_set<const btCollisionObject*> waking;
    for (const FrozenRef& r : hit) waking.insert(&r.piece->body->rigidBody());
    ImpulseTakeBack takeBack;
    for (const ContactPair& pair : contacts.pairs()) {
        if (pair.gone || !pair.solved || !pair.rigidA || !pair.rigidB) continue;
        if (!waking.count(pair.a) && !waking.count(pair.b)) continue;
        for (const ContactPoint& p : contacts.points(pair))
            if (!p.impulseOnA.isZero()) takeBack.takeBack(pair, p);
    }
    takeBack.finish(dt);
    int thawed = 0;
    for (const FrozenRef& r : hit)
        if (r.piece->frozen) {
            thaw(*r.piece);
            ++thawed;
        }
    return thawed;
}

void RestingPieces::thaw(LatticeBody::Piece& piece) {
    btRigidBody& rigid = piece.body->rigidBody();
    context_.reshape(*piece.body, [&](CollisionFilter& filter) { thawBody(rigid, piece.frozenAs, filter); });
    rigid.forceActivationState(ACTIVE_TAG);
    rigid.setDeactivationTime(0);
    piece.frozen = false;
    piece.supports.clear();
    piece.restPose = piece.body->rigidBody().getWorldTransform();
    piece.restFor = 0.0;
}

bool RestingPieces::thaw(const btCollisionObject& body) {
    const FrozenIndex frozen = frozenPieces();
    const auto it = frozen.find(&body);
    if (it == frozen.end()) return false;
    thaw(*it->second.piece);
    return true;
}

} // namespace shatter
