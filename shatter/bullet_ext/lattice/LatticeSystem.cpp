#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/plugin/common/Stopwatch.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/SleepingThreshold.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/lattice/ImpulseTakeBack.h>
#include <shatter/bullet_ext/shape/FragmentHull.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/FractureAnalysis.h>
#include <shatter/plugin/lattice/FragmentClusters.h>
#include <shatter/plugin/lattice/Fragments.h>
#include <shatter/plugin/lattice/PieceLoads.h>

#include <algorithm>
#include <cassert>
#include <unordered_map>
#include <unordered_set>

namespace shatter {

namespace {

bool dynamic(const btRigidBody* b) { return b->getInvMass() > 0; }

constexpr size_t kKeptRecords = 256; // split records not taken are dropped beyond this

// The pairs whose impulses Bullet's solver applied in this step between two rigid bodies: a
// pair of two sleeping (or static) bodies still holds the impulses of the step they fell
// asleep in, which must not load a lattice again every step.
bool carriesImpulses(const ContactPair& pair) { return !pair.gone && pair.solved && pair.rigidA && pair.rigidB; }

} // namespace

LatticeSystem::LatticeSystem(SystemContext& context) : context_(context), resting_(context, bodies_) {}

LatticeBody::Piece LatticeSystem::makePiece(LatticeBody& body, std::vector<int> particles, geometry::PhysicalMesh mesh,
                                            const btTransform& pose, bool fragment) {
    LatticeBody::Piece piece;
    piece.lattice = lattice::makePiece(body.lattice(), std::move(particles));
    piece.mass = mesh.mass;
    const LatticeSettings& s = body.settings();
    const DebrisSettings& debris = s.debris;
    piece.debris = fragment && !piece.lattice.anchored && debris.maxSize > 0.0 &&
                   lattice::pieceSize(body.lattice(), piece.lattice.particles, piece.mass.centerOfMass) <= debris.maxSize;
    const bool convex =
        lattice::isConvexPiece(body.lattice(), piece.lattice.particles, s.convexHullTolerance, s.convexHullMaxTets);
    // Shape and filter are set before the body enters the world (SystemContext::addBody).
    auto prepare = [&](VisualBody& made, CollisionFilter& filter) {
        if (convex) { // its group shape is built only if something asks for it
            piece.hull = makeFragmentHull(made.shapePrimitives(), s.rigidBody.collisionMargin);
            made.collideAs(*piece.hull);
        }
        // Debris leave each other out of their masks: their pairs never reach the narrowphase.
        if (piece.debris && !debris.collideWithEachOther) {
            filter.group = int(btBroadphaseProxy::DebrisFilter);
            filter.mask &= ~int(btBroadphaseProxy::DebrisFilter);
        }
    };
    piece.body = &context_.addBody(std::move(mesh), body.bodySettings(piece.lattice.anchored), pose, prepare);
    btRigidBody& rigid = piece.body->rigidBody();
    if (!piece.lattice.anchored) { // SleepingThreshold.h, within the shape's bounding sphere
        btVector3 centre;
        btScalar radius;
        rigid.getCollisionShape()->getBoundingSphere(centre, radius);
        sleepWhenNoPointIsFast(rigid, radius);
    }
    piece.restPose = rigid.getWorldTransform();
    if (piece.debris) piece.madeAt = context_.time();
    return piece;
}

LatticeBody::Piece LatticeSystem::shrinkPiece(LatticeBody& body, LatticeBody::Piece& old, std::vector<int> particles) {
    // A fresh piece on the old body: nearest-particle grid, analysed loads and rest tracking
    // start over, as for any new piece. The solver starts from the old piece's λ: a cold solve
    // of a 50,000-tet rest took 600 iterations over every link after each chip broke off.
    LatticeBody::Piece piece;
    piece.lattice = lattice::makePiece(body.lattice(), std::move(particles));
    if (old.lattice.system) piece.lattice.inheritSolver(old.lattice, body.lattice());
    piece.body = old.body;
    // Primitive i of the body is tet old.lattice.particles[i] (both sorted); those not in the
    // part leave, and the rest keep their order, so the map stays index <-> sorted position.
    const std::vector<int>& kept = piece.lattice.particles;
    std::vector<int> removed;
    for (size_t i = 0, k = 0; i < old.lattice.particles.size(); ++i) {
        if (k < kept.size() && kept[k] == old.lattice.particles[i]) ++k;
        else removed.push_back(int(i));
    }
    const geometry::FaceList surface = body.surfaceIn(old.body->physicalMesh(), old.lattice.particles, kept);
    piece.mass = body.massOf(kept);
    // Out of the world while the shape shrinks: Bullet's pairs cache algorithms keyed by
    // primitive index. Coming back with its filter, it makes fresh pairs next step. Or in the
    // world, its pairs following the removal (LatticeSettings::keepPairsOnShrink).
    const auto shrink = [&] { piece.body->removePrimitives(removed, surface, piece.mass); };
    if (body.settings().keepPairsOnShrink && !old.hull) // a piece colliding as its hull gets its group now
        timing_.shrinksInWorld += context_.removeInWorld(*piece.body, shrink);
    else
        context_.reshape(*piece.body, [&](CollisionFilter&) { shrink(); });
    piece.restPose = piece.body->rigidBody().getWorldTransform();
    return piece;
}

LatticeBody& LatticeSystem::add(lattice::TetMesh mesh, const LatticeSettings& settings, const btTransform& pose) {
    if (!finite(pose)) throw InputError("body '" + settings.name + "': pose has a non-finite value");
    auto body = std::make_unique<LatticeBody>(nextId_++, std::move(mesh), settings);
    std::vector<int> all(body->tetCount());
    for (int i = 0; i < body->tetCount(); ++i) all[i] = i;
    geometry::PhysicalMesh physical = body->physicalMesh(all, body->nextPieceName());
    body->mutablePieces().push_back(makePiece(*body, std::move(all), std::move(physical), pose, false));
    bodies_.push_back(std::move(body));
    return *bodies_.back();
}

void LatticeSystem::forget(VisualBody& body) {
    if (&body == removing_) return; // the system's own removal: the piece is already gone
    for (auto& lattice : bodies_) {
        auto& pieces = lattice->mutablePieces();
        const auto it = std::find_if(pieces.begin(), pieces.end(), [&](const auto& p) { return p.body == &body; });
        if (it == pieces.end()) continue;
        // Removed by someone else (the application): the piece leaves its body, with its mass.
        pieces.erase(it);
        return;
    }
}

void LatticeSystem::removeOwn(VisualBody& body) {
    removing_ = &body;
    context_.removeBody(body);
    removing_ = nullptr;
}

bool LatticeSystem::needsMotionBefore() const {
    // limitSpeeds reads every piece's speed before the step; waking frozen pieces reads the hitters'.
    for (const auto& body : bodies_)
        for (const auto& piece : body->pieces())
            if (piece.frozen || piece.body->rigidBody().getInvMass() > 0) return true;
    return false;
}

bool LatticeSystem::thaw(const btCollisionObject& body) {
    if (!resting_.thaw(body)) return false;
    ++timing_.thawed;
    return true;
}

std::vector<lattice::Impact> LatticeSystem::impactsOn(const LatticeBody::Piece& piece, const ContactSnapshot& contacts,
                                                      const std::vector<int>& pairs, double dt) const {
    const btRigidBody* rigid = &piece.body->rigidBody();
    const Eigen::Isometry3d toMesh = toEigen(piece.body->meshTransform()).inverse();
    std::vector<lattice::Impact> impacts;
    for (int index : pairs) {
        const ContactPair& pair = contacts.pairs()[index];
        for (const ContactPoint& p : contacts.points(pair)) {
            if (p.impulseOnA.isZero()) continue;
            const Eigen::Vector3d impulse = toEigen(ContactSnapshot::impulseOn(pair, p, rigid));
            impacts.push_back({toMesh * toEigen(ContactSnapshot::pointOn(pair, p, rigid)), toMesh.linear() * impulse / dt,
                               ContactSnapshot::primitiveOn(pair, p, rigid)});
        }
    }
    return impacts;
}

void LatticeSystem::analyse(const PieceRef& ref, const std::vector<lattice::Impact>& impacts, std::vector<Split>& splits) {
    LatticeBody& body = *ref.body;
    LatticeBody::Piece& piece = body.mutablePieces()[ref.piece];
    const btRigidBody& rigid = piece.body->rigidBody();
    const LatticeSettings& s = body.settings();
    auto t = SteadyClock::now();
    const Eigen::Matrix3d toMesh = toEigen(piece.body->meshTransform().getBasis()).transpose();
    const Eigen::Vector3d gravity = toMesh * toEigen(context_.world().getGravity());
    const Eigen::VectorXd& loads = lattice::pieceLoads(body.lattice(), piece.lattice, gravity, impacts, s.impactParticles);
    const Eigen::Vector3d omega = toMesh * toEigen(rigid.getAngularVelocity());
    const bool changed = lattice::loadsChanged(body.lattice(), piece.lattice, loads, s.reanalysisFraction);
    timing_.assembly += secondsSince(t);
    if (!changed) return;
    piece.lattice.analysedLoads = loads;
    if (observer_) observer_(body.lattice(), piece.lattice, loads, omega, s);
    const lattice::FractureReport r =
        lattice::analyseFracture(body.mutableLattice(), piece.lattice, loads, omega, s.analysis, body.random());
    timing_.assembly += r.assemblySeconds;
    timing_.solve += r.solveSeconds;
    timing_.breaking += r.breakingSeconds;
    ++timing_.analyses;
    timing_.solves += r.solves;
    timing_.iterations += r.iterations;
    timing_.converged = timing_.converged && r.converged;
    if (r.broken.empty()) return;
    timing_.linksBroken += int(r.broken.size());
    context_.push(EventType::LinksBroken, *piece.body, int(r.broken.size()));
    t = SteadyClock::now();
    auto parts = lattice::fragmentParts(body.mutableLattice(), piece.lattice, s.minFragmentSize);
    timing_.fragments += secondsSince(t);
    if (parts.size() > 1) splits.push_back({ref, std::move(parts)});
}

void LatticeSystem::replayImpacts(const ContactSnapshot& contacts, const std::vector<Split>& splits, double dt) {
    // Which splitting bodies' contacts are replayed and, for each static one, the part (free or
    // anchored) that every particle ends up in, and where a contact point lies in its mesh.
    struct Breaking {
        const Split* split;
        std::vector<char> freeParticle; // lattice particle -> in a part that will move (static pieces)
        std::vector<Eigen::AlignedBox3d> freeBoxes; // around each such part's particles, mesh coordinates
        Eigen::Isometry3d toMesh = Eigen::Isometry3d::Identity();
    };
    std::unordered_map<const btCollisionObject*, Breaking> breaking;
    for (const Split& s : splits) {
        LatticeBody& body = *s.ref.body;
        if (!body.settings().replayImpacts) continue;
        const LatticeBody::Piece& piece = body.pieces()[s.ref.piece];
        Breaking b{&s, {}, {}};
        if (!dynamic(&piece.body->rigidBody())) { // every contact of a dynamic piece loosens
            b.freeParticle.assign(size_t(body.lattice().particleCount()), 0);
            for (const auto& part : s.parts) {
                const bool free =
                    std::none_of(part.begin(), part.end(), [&](int p) { return body.lattice().particles()[p].fixed; });
                for (int p : part) b.freeParticle[size_t(p)] = free;
                if (!free) continue;
                Eigen::AlignedBox3d box;
                for (int p : part) box.extend(body.lattice().particles()[p].position);
                b.freeBoxes.push_back(box);
            }
            b.toMesh = toEigen(piece.body->meshTransform()).inverse();
        }
        breaking.emplace(&piece.body->rigidBody(), std::move(b));
    }
    // A contact on a part of an anchored piece that stays anchored did stop what hit it there;
    // one on a part that comes loose did not, and no contact of a free piece did (its supports
    // pushed back only because of the loads it no longer holds together against).
    // The point's part is that of the piece's particle nearest to it.
    auto loosens = [&](const btRigidBody* rigid, const btVector3& point, int primitive) {
        const auto it = breaking.find(rigid);
        if (it == breaking.end()) return false;
        if (dynamic(rigid)) return true;
        const Breaking& b = it->second;
        LatticeBody::Piece& piece = b.split->ref.body->mutablePieces()[b.split->ref.piece];
        const lattice::Lattice& lattice = b.split->ref.body->lattice();
        const Eigen::Vector3d local = b.toMesh * toEigen(point);
        // The touched tet (the body's primitive i is particle i of the piece; any particle of
        // the piece would do) bounds that distance: when every free part's box lies further
        // away (with a margin for rounding), the nearest particle is anchored, and the search
        // is skipped.
        if (primitive >= 0 && primitive < int(piece.lattice.particles.size())) {
            const double bound = (lattice.particles()[piece.lattice.particles[primitive]].position - local).squaredNorm();
            if (std::all_of(b.freeBoxes.begin(), b.freeBoxes.end(),
                            [&](const Eigen::AlignedBox3d& box) { return box.squaredExteriorDistance(local) > bound * (1 + 1e-9); }))
                return false;
        }
        const auto nearest = piece.lattice.nearestGrid(lattice).nearest(local, 1);
        return b.freeParticle[size_t(piece.lattice.particles[nearest[0].second])] != 0;
    };
    // Those impulses are taken back from both bodies of their pairs. A dynamic lattice piece
    // that loses one then loses every contact impulse of the step, and so on through the
    // dynamic bodies it touches: each of them leaves the step with the motion it came in with
    // (ImpulseTakeBack::finish removes gravity's step), and none keeps an unbalanced part of
    // the step's contact forces. Taking back only some of a piece's impulses made energy: a
    // shard between the ball and a half of the table top that had just split kept its push on
    // the half while its push from the ball was taken back (the halves gained 36 J in a step);
    // a loose tet at the bottom of a heap lost the ground's impulse and kept the heap's, and
    // flew off at 37-64 m/s. A body that is no piece (the application's ball) keeps its
    // contacts with static bodies, the part of a breaking wall that stays among them: they did
    // stop it. (Taking those back too let the ball plough on through the wall in every step
    // something broke: the wall demo made 884-913 fragments instead of 352-462.)
    std::vector<const btCollisionObject*> pieces; // sorted
    for (const auto& body : bodies_)
        for (const auto& piece : body->pieces()) pieces.push_back(&piece.body->rigidBody());
    std::sort(pieces.begin(), pieces.end());
    enum : char { Kept, Loosened, TakenBack }; // a pair's points: as solved, its loosened ones taken back, all taken back
    std::vector<char> state(contacts.pairs().size(), Kept);
    std::unordered_set<const btCollisionObject*> held;
    std::vector<const btCollisionObject*> toVisit;
    auto hold = [&](btRigidBody* rigid) {
        if (rigid && dynamic(rigid) && held.insert(rigid).second) toVisit.push_back(rigid);
    };
    // Per point of the step (pair.firstPoint + i): whether it loosened, found once (the nearest
    // particle search is most of this function's time) and read again below.
    size_t pointCount = 0;
    for (const ContactPair& pair : contacts.pairs()) pointCount = std::max(pointCount, size_t(pair.firstPoint + pair.pointCount));
    enum : char { Unknown, Loose, Firm };
    std::vector<char> pointState(pointCount, Unknown);
    auto loosened = [&](const ContactPair& pair, int i) {
        const ContactPoint& p = contacts.points(pair)[size_t(i)];
        char& known = pointState[size_t(pair.firstPoint + i)];
        if (known == Unknown) known = loosens(pair.rigidA, p.onA, p.primitiveA) || loosens(pair.rigidB, p.onB, p.primitiveB) ? Loose : Firm;
        return known == Loose;
    };
    ImpulseTakeBack takeBack;
    for (int k = 0; k < int(contacts.pairs().size()); ++k) {
        const ContactPair& pair = contacts.pairs()[k];
        if (!carriesImpulses(pair) || (!breaking.count(pair.a) && !breaking.count(pair.b))) continue;
        const auto points = contacts.points(pair);
        for (int i = 0; i < int(points.size()); ++i)
            if (!points[size_t(i)].impulseOnA.isZero() && loosened(pair, i)) {
                takeBack.takeBack(pair, points[size_t(i)]);
                state[k] = Loosened;
            }
        if (state[k] == Loosened) {
            hold(pair.rigidA);
            hold(pair.rigidB);
        }
    }
    while (!toVisit.empty()) {
        const btCollisionObject* body = toVisit.back();
        toVisit.pop_back();
        for (int k : contacts.pairsOf(body)) {
            const ContactPair& pair = contacts.pairs()[k];
            if (state[k] == TakenBack || !carriesImpulses(pair)) continue;
            const btRigidBody* other = pair.rigid(pair.other(body));
            if (!std::binary_search(pieces.begin(), pieces.end(), body) && !(other && dynamic(other))) continue;
            const auto points = contacts.points(pair);
            for (int i = 0; i < int(points.size()); ++i)
                if (!points[size_t(i)].impulseOnA.isZero() && !(state[k] == Loosened && loosened(pair, i)))
                    takeBack.takeBack(pair, points[size_t(i)]);
            state[k] = TakenBack;
            hold(pair.rigidA);
            hold(pair.rigidB);
        }
    }
    takeBack.finish(dt);
}

void LatticeSystem::addPendingSplits(std::vector<Split>& splits) const {
    for (const auto& body : bodies_)
        for (int i = 0; i < body->pieceCount(); ++i) {
            const LatticeBody::Piece& piece = body->pieces()[i];
            // A frozen piece waits until it wakes (it rests only once its parts are made).
            if (!piece.splitPending || piece.frozen) continue;
            // (step() never analyses a pending piece, so none of them is in `splits` yet.)
            splits.push_back({{body.get(), i}, lattice::connectedComponents(body->lattice(), piece.lattice.particles)});
        }
}

void LatticeSystem::budgetSplits(std::vector<Split>& splits) {
    std::unordered_map<const LatticeBody*, int> left; // new bodies each body may still make this step
    std::vector<Split> kept;
    for (Split& s : splits) {
        LatticeBody& body = *s.ref.body;
        LatticeBody::Piece& piece = body.mutablePieces()[s.ref.piece];
        const LatticeSettings& settings = body.settings();
        const int budget = settings.fragmentBudget;
        piece.splitPending = false;
        if (s.parts.size() < 2) continue; // a pending piece whose parts are all made
        s.kept = piece.hull ? -1
                            : lattice::partKeepingTheBody(body.lattice(), piece.lattice, s.parts,
                                                          settings.convexHullTolerance, settings.convexHullMaxTets);
        const int made = int(s.parts.size()) - (s.kept >= 0 ? 1 : 0);
        int& free = left.try_emplace(&body, budget).first->second;
        if (budget == 0 || made <= free) {
            free -= made;
            kept.push_back(std::move(s));
            continue;
        }
        // The first parts within the budget, one body less; the others join into one: the
        // kept part of a moving piece (carried with it), else a new body (a static piece's
        // would stand still in it).
        const int alone = free - 1;
        const bool intoKept = !piece.lattice.anchored && !piece.hull;
        if (intoKept && s.kept < 0) s.kept = lattice::largestPart(s.parts); // (a kept part is the largest already)
        if (free == 0 || (alone == 0 && (intoKept || s.kept < 0))) { // nothing would come apart: it waits whole
            piece.splitPending = true;
            continue;
        }
        std::vector<std::vector<int>> parts;
        std::vector<int> rest;
        for (int k = 0; k < int(s.parts.size()); ++k) {
            if (k == s.kept) continue;
            if (int(parts.size()) < alone) parts.push_back(std::move(s.parts[k]));
            else rest.insert(rest.end(), s.parts[k].begin(), s.parts[k].end());
        }
        if (s.kept >= 0 && intoKept) rest.insert(rest.end(), s.parts[s.kept].begin(), s.parts[s.kept].end());
        else if (s.kept >= 0) parts.push_back(std::move(s.parts[s.kept]));
        std::sort(rest.begin(), rest.end());
        s.holding = int(parts.size());
        s.kept = intoKept ? s.holding : s.kept >= 0 ? s.holding - 1 : -1;
        parts.push_back(std::move(rest));
        s.parts = std::move(parts);
        free -= int(s.parts.size()) - (s.kept >= 0 ? 1 : 0);
        kept.push_back(std::move(s));
    }
    splits = std::move(kept);
}

void LatticeSystem::split(LatticeBody& body, std::vector<Split>& splits) {
    std::vector<LatticeBody::Piece> next;
    auto& pieces = body.mutablePieces();
    for (int i = 0; i < int(pieces.size()); ++i) {
        const auto s = std::find_if(splits.begin(), splits.end(),
                                    [&](const Split& x) { return x.ref.body == &body && x.ref.piece == i; });
        if (s == splits.end()) {
            next.push_back(std::move(pieces[i]));
            continue;
        }
        // The parent's motion in world coordinates, exact mass properties from its tets; an
        // anchored piece is held still.
        VisualBody* parentBody = pieces[i].body;
        const btTransform pose = parentBody->meshTransform();
        const Eigen::Isometry3d toWorld = toEigen(pose);
        const bool anchored = pieces[i].lattice.anchored;
        const btRigidBody& parentRigid = parentBody->rigidBody();
        const geometry::RigidState parent = geometry::rigidState(
            geometry::transformed(pieces[i].mass, toWorld),
            anchored ? Eigen::Vector3d::Zero() : toEigen(parentRigid.getLinearVelocity()),
            anchored ? Eigen::Vector3d::Zero() : toEigen(parentRigid.getAngularVelocity()));
        SplitRecord record{parent, {}, {}};
        const int kept = s->kept;
        // The new bodies' meshes, cut from the parent's before the kept part shrinks it.
        std::vector<geometry::PhysicalMesh> meshes(s->parts.size());
        for (int k = 0; k < int(s->parts.size()); ++k) {
            if (k == kept) continue;
            assert(std::is_sorted(s->parts[k].begin(), s->parts[k].end())); // fragmentParts sorts them; partMesh needs it
            meshes[k] = body.partMesh(parentBody->physicalMesh(), pieces[i].lattice.particles, s->parts[k],
                                      body.nextPieceName());
        }
        for (int k = 0; k < int(s->parts.size()); ++k) {
            auto& part = s->parts[k];
            LatticeBody::Piece piece = k == kept ? shrinkPiece(body, pieces[i], std::move(part))
                                                 : makePiece(body, std::move(part), std::move(meshes[k]), pose, true);
            piece.splitPending = k == s->holding;
            const geometry::RigidState state = geometry::partState(parent, geometry::transformed(piece.mass, toWorld));
            record.parts.push_back(state);
            record.bodies.push_back(piece.body);
            btRigidBody& rigid = piece.body->rigidBody();
            if (!piece.lattice.anchored) {
                rigid.setLinearVelocity(toBullet(state.velocity));
                rigid.setAngularVelocity(toBullet(state.angularVelocity));
            }
            if (anchored && !piece.lattice.anchored) resting_.noteBrokenOff(rigid);
            if (k != kept) { // the part that kept its body is no new fragment
                context_.push(EventType::FragmentCreated, *piece.body, int(piece.lattice.particles.size()));
                ++timing_.fragmentsCreated;
            }
            next.push_back(std::move(piece));
        }
        if (kept < 0) removeOwn(*parentBody);
        records_.push_back(std::move(record));
        if (records_.size() > kKeptRecords) records_.erase(records_.begin());
    }
    pieces = std::move(next);
}

std::vector<LatticeSystem::SplitRecord> LatticeSystem::takeSplitRecords() {
    std::vector<SplitRecord> out;
    out.swap(records_);
    return out;
}

void LatticeSystem::removeExpiredDebris() {
    for (auto& body : bodies_) {
        const DebrisSettings& s = body->settings().debris;
        if (s.lifetime <= 0.0 && s.budget <= 0) continue;
        auto& pieces = body->mutablePieces();
        // Oldest first (pieces made in the same step: in piece order).
        std::vector<int> debris;
        for (int i = 0; i < int(pieces.size()); ++i)
            if (pieces[i].debris) debris.push_back(i);
        std::stable_sort(debris.begin(), debris.end(), [&](int a, int b) { return pieces[a].madeAt < pieces[b].madeAt; });
        const int overBudget = s.budget > 0 ? std::max(0, int(debris.size()) - s.budget) : 0;
        std::vector<int> expired;
        for (int k = 0; k < int(debris.size()); ++k)
            if (k < overBudget || (s.lifetime > 0.0 && context_.time() - pieces[debris[k]].madeAt >= s.lifetime))
                expired.push_back(debris[k]);
        std::sort(expired.begin(), expired.end(), std::greater<int>()); // erase from the back
        for (int i : expired) {
            VisualBody& gone = *pieces[i].body;
            context_.push(EventType::DebrisExpired, gone, int(pieces[i].lattice.particles.size()));
            body->noteDebrisRemoved(pieces[i].mass.mass);
            ++timing_.debrisExpired;
            pieces.erase(pieces.begin() + i);
            removeOwn(gone);
        }
    }
}

void LatticeSystem::limitSpin(double dt) {
    for (auto& body : bodies_) {
        const double most = body->settings().maxRotationPerStep / dt;
        for (auto& piece : body->mutablePieces()) {
            btRigidBody& rigid = piece.body->rigidBody();
            const double spin = double(rigid.getAngularVelocity().length());
            if (spin > most) rigid.setAngularVelocity(rigid.getAngularVelocity() * btScalar(most / spin));
        }
    }
}

void LatticeSystem::limitSpeeds(double dt, const ContactSnapshot& contacts) {
    // Per piece in contact: its own speed before the step, and the fastest point of anything
    // touching it then.
    struct Bound {
        double own = 0.0, hit = 0.0;
        const LatticeSettings* settings = nullptr;
    };
    std::unordered_map<btRigidBody*, Bound> bounds;
    for (auto& body : bodies_)
        for (auto& piece : body->mutablePieces())
            if (!piece.frozen && piece.body->rigidBody().getInvMass() > 0)
                bounds[&piece.body->rigidBody()].settings = &body->settings();
    if (bounds.empty()) return;
    for (const ContactPair& pair : contacts.pairs()) {
        if (pair.gone) continue;
        for (const btCollisionObject* self : {pair.a, pair.b}) {
            const auto it = bounds.find(pair.rigid(self));
            if (it == bounds.end()) continue;
            it->second.own = double(pair.before(self).linear.length());
            const btCollisionObject* other = pair.other(self);
            for (const ContactPoint& p : contacts.points(pair)) {
                const double speed = double(pair.before(other).velocityAt(ContactSnapshot::pointOn(pair, p, other)).length());
                it->second.hit = std::max(it->second.hit, speed);
            }
        }
    }
    const double fall = double(context_.world().getGravity().length()) * dt;
    for (auto& [rigid, b] : bounds) {
        const double cap = std::max(b.own + fall, b.settings->hitSpeedFactor * b.hit);
        const double speed = double(rigid->getLinearVelocity().length());
        if (speed > cap && b.own + b.hit > 0.0) { // a piece never in contact falls freely
            rigid->setLinearVelocity(rigid->getLinearVelocity() * btScalar(cap / speed));
            ++timing_.speedsLimited;
        }
    }
}

void LatticeSystem::step(double dt, const ContactSnapshot& contacts) {
    if (bodies_.empty() || dt <= 0) return;
    limitSpin(dt);
    limitSpeeds(dt, contacts);
    auto t = SteadyClock::now();
    // Every piece, and the contact pairs that touch it.
    std::vector<PieceRef> refs;
    std::unordered_map<const btCollisionObject*, int> watched;
    for (auto& body : bodies_)
        for (int i = 0; i < body->pieceCount(); ++i) {
            watched.emplace(&body->pieces()[i].body->rigidBody(), int(refs.size()));
            refs.push_back({body.get(), i});
        }
    std::vector<std::vector<int>> pairsOf(refs.size());
    for (int k = 0; k < int(contacts.pairs().size()); ++k) {
        const ContactPair& pair = contacts.pairs()[k];
        if (!carriesImpulses(pair)) continue;
        for (const btCollisionObject* o : {pair.a, pair.b}) {
            const auto it = watched.find(o);
            if (it != watched.end()) pairsOf[it->second].push_back(k);
        }
    }
    timing_.impacts += secondsSince(t);
    std::vector<Split> splits;
    for (size_t r = 0; r < refs.size(); ++r) {
        if (pairsOf[r].empty()) continue; // free flight: gravity alone loads no link
        const LatticeBody::Piece& piece = refs[r].body->pieces()[refs[r].piece];
        if (piece.lattice.particles.size() < 2) continue; // a lone tet has no link
        if (dynamic(&piece.body->rigidBody()) && !piece.body->rigidBody().isActive()) continue; // asleep: nothing new
        if (piece.frozen) continue; // woken below if hit
        // Parts held together only by the fragment budget: the loads of the clump are not
        // theirs (a heavy clump takes a far harder hit than its parts would); they split below.
        if (piece.splitPending) continue;
        t = SteadyClock::now();
        const auto impacts = impactsOn(piece, contacts, pairsOf[r], dt);
        timing_.impacts += secondsSince(t);
        if (impacts.empty()) continue;
        analyse(refs[r], impacts, splits);
    }
    t = SteadyClock::now();
    addPendingSplits(splits);
    budgetSplits(splits);
    timing_.fragments += secondsSince(t);
    if (!splits.empty()) {
        t = SteadyClock::now();
        replayImpacts(contacts, splits, dt);
        for (auto& body : bodies_) split(*body, splits);
        timing_.fragments += secondsSince(t);
    }
    t = SteadyClock::now();
    removeExpiredDebris();
    const RestingPieces::Counts counts = resting_.step(dt, contacts);
    timing_.frozen += counts.frozen;
    timing_.thawed += counts.thawed;
    timing_.resting += secondsSince(t);
}

} // namespace shatter
