#include <shatter/bullet_ext/lattice/LatticeSystem.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/shape/FragmentHull.h>
#include <shatter/bullet_ext/lattice/LatticeImpacts.h>
#include <shatter/bullet_ext/OutOfWorld.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/Fragments.h>

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <unordered_map>

namespace shatter {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

bool finite(const btTransform& t) { return toEigen(t).matrix().allFinite(); }

bool dynamic(const btRigidBody* b) { return b->getInvMass() > 0; }

constexpr size_t kKeptRecords = 256; // split records not taken are dropped beyond this

// Whether some particle's load moved, since the piece's last analysis, by more than `fraction`
// of the strength of its weakest unbroken link: in this lattice a link carries mostly the loads
// of its own two particles (forces fall off by about 3 per link away from a load), so smaller
// changes leave every link's force within about that fraction of where it was.
bool loadsChanged(const lattice::Lattice& lattice, const LatticeBody::Piece& piece, const Eigen::VectorXd& loads,
                  double fraction) {
    if (piece.analysedLoads.size() != loads.size()) return true;
    for (int i = 0; i < int(piece.lattice.particles.size()); ++i) {
        const double change = (loads.segment<3>(3 * i) - piece.analysedLoads.segment<3>(3 * i)).norm();
        if (change == 0.0) continue;
        double weakest = INFINITY;
        for (int k : lattice.linksOf(piece.lattice.particles[i]))
            if (!lattice.links()[k].broken) weakest = std::min(weakest, lattice.links()[k].strength);
        if (change > fraction * weakest) return true;
    }
    return false;
}

// The particles of the piece nearest to a contact point (local indices). The contact's
// primitive, when Bullet names it, is the tet touched: its particle and its face neighbours are
// the candidates, which is exact for every contact on the tet and costs O(1). Otherwise the
// piece's grid is searched.
std::vector<std::pair<double, int>> nearestParticles(LatticeBody& body, LatticeBody::Piece& piece,
                                                     const Eigen::Vector3d& point, int primitive) {
    const lattice::Lattice& lattice = body.lattice();
    const int k = body.settings().impactParticles;
    const auto& particles = piece.lattice.particles;
    if (primitive < 0 || primitive >= int(particles.size()) || k > 5) return piece.nearestParticles(lattice).nearest(point, k);
    std::vector<std::pair<double, int>> near;
    const int tet = particles[primitive];
    near.emplace_back((lattice.particles()[tet].position - point).squaredNorm(), primitive);
    for (int n : lattice.faces().neighbour[tet]) {
        if (n < 0) continue;
        const auto it = std::lower_bound(particles.begin(), particles.end(), n);
        if (it == particles.end() || *it != n) continue;
        near.emplace_back((lattice.particles()[n].position - point).squaredNorm(), int(it - particles.begin()));
    }
    std::sort(near.begin(), near.end());
    near.resize(std::min<size_t>(near.size(), size_t(k)));
    return near;
}

// Which part of a split piece keeps the piece's Bullet body, or -1 when every part gets a new
// one. The big anchored rest of a wall is split again and again as its face breaks away;
// building each of its thousands of tets' primitive, hull and tree anew every time cost most
// of the shatter frame, for a body that does not move. So the largest part keeps the body when
// it is anchored (static: no mass or velocity of the body to change), holds most of the tets
// and collides as a group (a hull would be a new shape anyway).
int keptPart(const LatticeBody& body, const LatticeBody::Piece& piece, const std::vector<std::vector<int>>& parts) {
    if (!piece.lattice.anchored || piece.hull) return -1;
    const auto largest = std::max_element(parts.begin(), parts.end(),
                                          [](const auto& a, const auto& b) { return a.size() < b.size(); });
    const lattice::Lattice& l = body.lattice();
    const LatticeSettings& s = body.settings();
    const bool anchored = std::any_of(largest->begin(), largest->end(), [&](int p) { return l.particles()[p].fixed; });
    if (!anchored || 2 * largest->size() <= piece.lattice.particles.size()) return -1;
    if (lattice::isConvexPiece(l, *largest, s.convexHullTolerance, s.convexHullMaxTets)) return -1;
    return int(largest - parts.begin());
}

} // namespace

LatticeSystem::LatticeSystem(Plugin& plugin) : plugin_(plugin) {}

LatticeSystem::~LatticeSystem() {
    // The Plugin removes the pieces' bodies after this; give them back their group shapes
    // first, so that no body in the world points to a hull that is gone.
    for (auto& body : bodies_)
        for (auto& piece : body->mutablePieces())
            if (piece.hull)
                replaceCollisionShape(plugin_.world(), piece.body->rigidBody(),
                                      const_cast<GroupShape&>(piece.body->shape()));
}

LatticeBody::Piece LatticeSystem::makePiece(LatticeBody& body, std::vector<int> particles, const btTransform& pose) {
    LatticeBody::Piece piece;
    piece.lattice = lattice::makePiece(body.lattice(), std::move(particles));
    geometry::PhysicalMesh mesh = body.physicalMesh(piece.lattice.particles, body.nextPieceName());
    piece.mass = mesh.mass;
    piece.body = &plugin_.addVisualBody(mesh, body.bodySettings(piece.lattice.anchored), pose);
    const LatticeSettings& s = body.settings();
    if (lattice::isConvexPiece(body.lattice(), piece.lattice.particles, s.convexHullTolerance, s.convexHullMaxTets)) {
        piece.hull = makeFragmentHull(piece.body->shape(), s.collisionMargin);
        replaceCollisionShape(plugin_.world(), piece.body->rigidBody(), *piece.hull);
    }
    btRigidBody& rigid = piece.body->rigidBody();
    // Bullet's angular sleeping threshold (1 rad/s by default) is meant for bodies of about a
    // metre; on a 10 cm fragment it means a rim speed of a few cm/s, which the tets of a heap
    // exceed every few steps as contacts nudge them, each time restarting the timer of the
    // whole heap's island, so it never sleeps (measured: 270 loose tets, awake after 10 s).
    // A piece counts as slow instead when no point of it (within its bounding sphere) moves
    // faster than the linear threshold; never below Bullet's own angular threshold.
    if (!piece.lattice.anchored) {
        btVector3 centre;
        btScalar radius;
        rigid.getCollisionShape()->getBoundingSphere(centre, radius);
        const btScalar linear = rigid.getLinearSleepingThreshold();
        if (radius > 0) rigid.setSleepingThresholds(linear, btMax(rigid.getAngularSleepingThreshold(), linear / radius));
    }
    piece.restPose = rigid.getWorldTransform();
    return piece;
}

LatticeBody::Piece LatticeSystem::shrinkPiece(LatticeBody& body, const LatticeBody::Piece& old,
                                              std::vector<int> particles) {
    // A fresh piece on the old body: solver state, nearest-particle grid, analysed loads and
    // rest tracking start over, as for any new piece.
    LatticeBody::Piece piece;
    piece.lattice = lattice::makePiece(body.lattice(), std::move(particles));
    piece.body = old.body;
    // Primitive i of the body is tet old.lattice.particles[i] (both sorted); those not in the
    // part leave, and the rest keep their order, so the map stays index <-> sorted position.
    const std::vector<int>& kept = piece.lattice.particles;
    std::vector<int> removed;
    for (size_t i = 0, k = 0; i < old.lattice.particles.size(); ++i) {
        if (k < kept.size() && kept[k] == old.lattice.particles[i]) ++k;
        else removed.push_back(int(i));
    }
    std::vector<std::vector<int>> surface = body.surfaceIn(old.body->physicalMesh(), old.lattice.particles, kept);
    piece.mass = lattice::pieceMassProperties(body.lattice(), kept);
    // Out of the world while the shape shrinks: Bullet's pairs cache algorithms keyed by
    // primitive index. Coming back with its filter, it makes fresh pairs next step.
    outOfWorldWhile(plugin_.world(), piece.body->rigidBody(),
                    [&] { piece.body->removePrimitives(removed, std::move(surface), piece.mass); });
    piece.restPose = piece.body->rigidBody().getWorldTransform();
    return piece;
}

LatticeBody& LatticeSystem::add(lattice::TetMesh mesh, const LatticeSettings& settings, const btTransform& pose) {
    if (!finite(pose)) throw InputError(settings.name + ": pose has a non-finite value");
    auto body = std::make_unique<LatticeBody>(nextId_++, std::move(mesh), settings);
    std::vector<int> all(body->tetCount());
    for (int i = 0; i < body->tetCount(); ++i) all[i] = i;
    body->mutablePieces().push_back(makePiece(*body, std::move(all), pose));
    bodies_.push_back(std::move(body));
    return *bodies_.back();
}

Eigen::VectorXd LatticeSystem::loadsOn(const PieceRef& ref, const std::vector<const ContactImpulse*>& contacts,
                                       double dt) {
    LatticeBody& body = *ref.body;
    LatticeBody::Piece& piece = body.mutablePieces()[ref.piece];
    const lattice::Lattice& lattice = body.lattice();
    const btRigidBody& rigid = piece.body->rigidBody();
    const Eigen::Isometry3d toMesh = toEigen(piece.body->meshTransform()).inverse();
    const int n = int(piece.lattice.particles.size());
    Eigen::VectorXd loads = Eigen::VectorXd::Zero(3 * n);
    // Gravity on every free particle; fixed ones take any load.
    const Eigen::Vector3d g = toMesh.linear() * toEigen(plugin_.world().getGravity());
    for (int i = 0; i < n; ++i) {
        const lattice::Particle& p = lattice.particles()[piece.lattice.particles[i]];
        if (!p.fixed) loads.segment<3>(3 * i) = p.mass * g;
    }
    // Each contact's impulse over the step, at its point, on the nearest particles.
    for (const ContactImpulse* c : contacts) {
        const Eigen::Vector3d force = toMesh.linear() * impulseOn(*c, &rigid) / dt;
        const Eigen::Vector3d point = toMesh * pointOn(*c, &rigid);
        addPointForce(nearestParticles(body, piece, point, primitiveOn(*c, &rigid)), force, loads);
    }
    return loads;
}

void LatticeSystem::compareWithCholesky(lattice::LatticePiece& piece, const Eigen::VectorXd& loads,
                                        const Eigen::Vector3d& omega, const lattice::SolverSettings& settings) {
    const lattice::ConstraintSystem& system = *piece.system;
    if (system.rowCount() == 0) return;
    const Eigen::VectorXd b = system.rightHandSide(loads, omega);
    auto t = Clock::now();
    Eigen::VectorXd cg = piece.lambda;
    system.solve(b, cg, settings);
    timing_.cgSeconds += since(t);
    t = Clock::now();
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(system.assemble());
    const Eigen::VectorXd direct = ldlt.solve(b);
    timing_.choleskySeconds += since(t);
    ++timing_.choleskySolves;
    if (ldlt.info() == Eigen::Success && direct.norm() > 0)
        timing_.largestDifference = std::max(timing_.largestDifference, (cg - direct).norm() / direct.norm());
}

void LatticeSystem::analyse(const PieceRef& ref, const std::vector<const ContactImpulse*>& contacts, double dt,
                            std::vector<Split>& splits) {
    LatticeBody& body = *ref.body;
    LatticeBody::Piece& piece = body.mutablePieces()[ref.piece];
    const btRigidBody& rigid = piece.body->rigidBody();
    auto t = Clock::now();
    Eigen::VectorXd loads = loadsOn(ref, contacts, dt);
    const Eigen::Matrix3d toMesh = toEigen(piece.body->meshTransform().getBasis()).transpose();
    const Eigen::Vector3d omega = toMesh * toEigen(rigid.getAngularVelocity());
    const bool changed = loadsChanged(body.lattice(), piece, loads, body.settings().reanalysisFraction);
    timing_.assembly += since(t);
    if (!changed) return;
    piece.analysedLoads = loads;
    if (compareCholesky_) {
        piece.lattice.constraintSystem(body.lattice());
        compareWithCholesky(piece.lattice, loads, omega, body.settings().fracture.solver);
    }
    const lattice::FractureReport r = lattice::analyseFracture(body.mutableLattice(), piece.lattice, loads, omega,
                                                               body.settings().fracture, body.random());
    timing_.assembly += r.assemblySeconds;
    timing_.solve += r.solveSeconds;
    timing_.breaking += r.breakingSeconds;
    ++timing_.analyses;
    timing_.solves += r.solves;
    timing_.iterations += r.iterations;
    timing_.converged = timing_.converged && r.converged;
    if (r.broken.empty()) return;
    timing_.linksBroken += int(r.broken.size());
    Event e{EventType::LinksBroken, piece.body->id(), -1, plugin_.time(), piece.body->name()};
    e.count = int(r.broken.size());
    plugin_.events_.push_back(e);
    t = Clock::now();
    auto parts = lattice::connectedComponents(body.lattice(), piece.lattice.particles);
    timing_.fragments += since(t);
    if (parts.size() > 1) splits.push_back({ref, std::move(parts)});
}

void LatticeSystem::replayImpacts(const std::vector<ContactImpulse>& contacts, const std::vector<Split>& splits) {
    // Which splitting bodies' contacts are replayed, and for each the part (free or anchored)
    // that every particle ends up in.
    struct Breaking {
        const Split* split;
        std::unordered_map<int, bool> freeParticle; // lattice particle -> in a part that will move
    };
    std::unordered_map<const btRigidBody*, Breaking> breaking;
    for (const Split& s : splits) {
        LatticeBody& body = *s.ref.body;
        if (!body.settings().replayImpacts) continue;
        Breaking b{&s, {}};
        for (const auto& part : s.parts) {
            const bool free = std::none_of(part.begin(), part.end(), [&](int p) { return body.lattice().particles()[p].fixed; });
            for (int p : part) b.freeParticle.emplace(p, free);
        }
        breaking.emplace(&body.pieces()[s.ref.piece].body->rigidBody(), std::move(b));
    }
    // A contact whose point lies on a part that stays anchored keeps its impulse: the
    // remaining wall did stop the ball there. One on a part that comes loose is taken back,
    // and so is every contact of a piece that was free (its supports pushed back only because
    // of the loads it no longer holds together against).
    auto loosens = [&](const btRigidBody* rigid, const Eigen::Vector3d& point) {
        const auto it = breaking.find(rigid);
        if (it == breaking.end()) return false;
        if (dynamic(rigid)) return true;
        const Split& s = *it->second.split;
        LatticeBody::Piece& piece = s.ref.body->mutablePieces()[s.ref.piece];
        const Eigen::Vector3d local = toEigen(piece.body->meshTransform()).inverse() * point;
        const auto nearest = piece.nearestParticles(s.ref.body->lattice()).nearest(local, 1);
        return it->second.freeParticle.at(piece.lattice.particles[nearest[0].second]);
    };
    for (const ContactImpulse& c : contacts) {
        if (loosens(c.bodyA, c.pointA) || loosens(c.bodyB, c.pointB)) undoContactImpulse(c);
    }
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
        // The parent's motion in world coordinates, exact mass properties from its tets.
        VisualBody* parentBody = pieces[i].body;
        const btTransform pose = parentBody->meshTransform();
        // Bullet's rotation is orthonormal only to float precision; the parallel-axis sums that
        // make the parts' momenta add up to the parent's need an exact one.
        Eigen::Isometry3d toWorld = toEigen(pose);
        toWorld.linear() = Eigen::Quaterniond(toWorld.linear()).normalized().toRotationMatrix();
        lattice::RigidState parent;
        parent.mass = pieces[i].mass.mass;
        parent.centre = toWorld * pieces[i].mass.centerOfMass;
        parent.velocity = toEigen(parentBody->rigidBody().getLinearVelocity());
        parent.angularVelocity = toEigen(parentBody->rigidBody().getAngularVelocity());
        parent.inertia = toWorld.linear() * pieces[i].mass.inertia * toWorld.linear().transpose();
        if (pieces[i].lattice.anchored) parent.velocity = parent.angularVelocity = Eigen::Vector3d::Zero();
        SplitRecord record{parent, {}, {}};
        const int kept = keptPart(body, pieces[i], s->parts);
        for (int k = 0; k < int(s->parts.size()); ++k) {
            auto& part = s->parts[k];
            LatticeBody::Piece piece = k == kept ? shrinkPiece(body, pieces[i], std::move(part))
                                                 : makePiece(body, std::move(part), pose);
            geometry::MassProperties world = piece.mass;
            world.centerOfMass = toWorld * world.centerOfMass;
            world.inertia = toWorld.linear() * world.inertia * toWorld.linear().transpose();
            const lattice::RigidState state = lattice::fragmentState(parent, world);
            record.parts.push_back(state);
            record.bodies.push_back(piece.body);
            btRigidBody& rigid = piece.body->rigidBody();
            if (!piece.lattice.anchored) {
                rigid.setLinearVelocity(toBullet(state.velocity));
                rigid.setAngularVelocity(toBullet(state.angularVelocity));
            }
            if (pieces[i].lattice.anchored && !piece.lattice.anchored) noteBrokenOff(rigid);
            if (k != kept) { // the part that kept its body is no new fragment
                Event e{EventType::FragmentCreated, piece.body->id(), -1, plugin_.time(), piece.body->name()};
                e.count = int(piece.lattice.particles.size());
                plugin_.events_.push_back(e);
                ++timing_.fragmentsCreated;
            }
            next.push_back(std::move(piece));
        }
        if (kept < 0) plugin_.removeBody(*parentBody);
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

void LatticeSystem::step(double dt) {
    if (bodies_.empty() || dt <= 0) return;
    limitSpin(dt);
    auto t = Clock::now();
    std::vector<PieceRef> refs;
    std::unordered_map<const btCollisionObject*, int> watched;
    for (auto& body : bodies_)
        for (int i = 0; i < body->pieceCount(); ++i) {
            watched.emplace(&body->pieces()[i].body->rigidBody(), int(refs.size()));
            refs.push_back({body.get(), i});
        }
    const std::vector<ContactImpulse> contacts = collectContactImpulses(*plugin_.world().getDispatcher(), watched);
    std::vector<std::vector<const ContactImpulse*>> onPiece(refs.size());
    for (const ContactImpulse& c : contacts) {
        for (const btCollisionObject* o : {static_cast<const btCollisionObject*>(c.bodyA),
                                           static_cast<const btCollisionObject*>(c.bodyB)}) {
            const auto it = watched.find(o);
            if (it != watched.end()) onPiece[it->second].push_back(&c);
        }
    }
    timing_.impacts += since(t);
    std::vector<Split> splits;
    for (size_t r = 0; r < refs.size(); ++r) {
        if (onPiece[r].empty()) continue; // free flight: gravity alone loads no link
        if (refs[r].body->pieces()[refs[r].piece].lattice.particles.size() < 2) continue; // a lone tet has no link
        const btRigidBody& rigid = refs[r].body->pieces()[refs[r].piece].body->rigidBody();
        if (dynamic(&rigid) && !rigid.isActive()) continue; // asleep: nothing new
        if (refs[r].body->pieces()[refs[r].piece].frozen) continue; // woken below if hit
        analyse(refs[r], onPiece[r], dt, splits);
    }
    if (!splits.empty()) {
        t = Clock::now();
        replayImpacts(contacts, splits);
        for (auto& body : bodies_) split(*body, splits);
        timing_.fragments += since(t);
    }
    t = Clock::now();
    wakeHitPieces();
    settle(dt);
    recordVelocities();
    timing_.resting += since(t);
}

} // namespace shatter
