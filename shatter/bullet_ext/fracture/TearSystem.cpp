#include <shatter/bullet_ext/fracture/TearSystem.h>
#include <shatter/plugin/common/Stopwatch.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/fracture/JointTransfer.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/RigidState.h>

#include <algorithm>
#include <chrono>

namespace shatter {

namespace {

constexpr size_t kKeptRecords = 256; // records not taken are dropped beyond this

double totalMass(const oriented::OrientedParticles& p) {
    double m = 0.0;
    for (double mi : p.mass) m += mi;
    return m;
}

// A rigid (plastic) body's mass properties `mass` (mesh coordinates) and motion in the world
// frame; a static body is at rest.
geometry::RigidState worldState(const VisualBody& body, const geometry::MassProperties& mass) {
    const btRigidBody& rigid = body.rigidBody();
    const bool moves = rigid.getInvMass() > 0;
    return geometry::rigidState(geometry::transformed(mass, toEigen(body.meshTransform())),
                                moves ? toEigen(rigid.getLinearVelocity()) : Eigen::Vector3d::Zero(),
                                moves ? toEigen(rigid.getAngularVelocity()) : Eigen::Vector3d::Zero());
}

// Adds a rigid state's mass and momenta to the record's side before or after the tear.
void addState(TearSystem::Record& record, const geometry::RigidState& state, bool after) {
    (after ? record.massAfter : record.massBefore) += state.mass;
    (after ? record.momentumAfter : record.momentumBefore) += state.linearMomentum();
    (after ? record.angularMomentumAfter : record.angularMomentumBefore) += state.angularMomentum();
}

} // namespace

void TearSystem::add(VisualBody& body) {
    const TearSettings& s = body.settings().tear;
    if (!s.enabled) throw InputError("body '" + body.name() + "': tear is not enabled in its settings");
    if (body.deformation() == Deformation::None)
        throw InputError("body '" + body.name() +
                         "': tear needs deformation Soft or Plastic (a rigid body's primitives never move apart)");
    bodies_.push_back({&body, fracture::breakableConnections(body.physicalMesh(), s.everywhere), body.plasticEvents()});
}

std::vector<fracture::BreakableConnection> TearSystem::breakable(const VisualBody& body) const {
    const auto it = std::find_if(bodies_.begin(), bodies_.end(), [&](const Tearable& t) { return t.body == &body; });
    if (it == bodies_.end()) return {};
    // A plastic body's list is refreshed only at its dents; a subdivision since replaced its mesh.
    if (body.deformation() == Deformation::Plastic)
        return fracture::breakableConnections(body.physicalMesh(), body.settings().tear.everywhere);
    return it->breakable;
}

std::vector<VisualBody*> TearSystem::tear(VisualBody& parent, const std::vector<int>& connections) {
    const auto it = std::find_if(bodies_.begin(), bodies_.end(), [&](const Tearable& t) { return t.body == &parent; });
    if (it == bodies_.end()) throw InputError("body '" + parent.name() + "': tear is not enabled in its settings");
    const geometry::PhysicalMesh& mesh = parent.physicalMesh();
    std::vector<bool> broken(mesh.connections.size(), false);
    for (int c : connections) {
        if (c < 0 || c >= int(broken.size()))
            throw InputError("body '" + parent.name() + "': connection " + std::to_string(c) + " out of range (" +
                             std::to_string(broken.size()) + " connections)");
        broken[size_t(c)] = true;
    }
    const bool soft = parent.deformation() == Deformation::Soft;
    Record record;
    record.parent = parent.id();
    record.time = context_.time();
    record.connectionsBroken = int(connections.size());
    if (soft) {
        const oriented::OrientedParticles& from = parent.solver()->particles();
        record.massBefore = totalMass(from);
        record.momentumBefore = from.linearMomentum();
        record.angularMomentumBefore = from.angularMomentum();
    } else {
        addState(record, worldState(parent, parent.physicalMesh().mass), false);
    }
    auto opened = [&](std::chrono::steady_clock::time_point start) {
        record.parts = {parent.id()};
        context_.push(Event{EventType::BodyTorn, parent.id(), -1, 0.0, parent.name(), int(connections.size()), record.parts});
        finish(std::move(record), 1, start);
        return std::vector<VisualBody*>{&parent};
    };
    auto t = SteadyClock::now();
    if (soft) {
        // A soft body that only opens stays the body it was, in place (its particles untouched,
        // so its mass and momenta are the same numbers); only what lies along the broken
        // connections changes, its breakable list too.
        if (const auto opening = parent.open(broken)) {
            fracture::updateBreakable(it->breakable, parent.physicalMesh(), *opening, parent.settings().tear.everywhere);
            timing_.tearing += secondsSince(t);
            record.idsSplit = opening->idsSplit;
            record.massAfter = record.massBefore;
            record.momentumAfter = record.momentumBefore;
            record.angularMomentumAfter = record.angularMomentumBefore;
            return opened(SteadyClock::now());
        }
    }
    // A soft body that parts becomes its largest part (keepPart, below): its primitives can move
    // into the parts.
    fracture::TearResult torn = soft ? parent.tearApart(broken) : fracture::tearMesh(mesh, broken);
    timing_.tearing += secondsSince(t);
    t = SteadyClock::now();
    record.idsSplit = torn.idsSplit;
    if (torn.parts.size() == 1) {
        // A plastic body that only opened stays the body it was (id, name, shape, joints), with
        // the new ids, faces and connections, taken as a subdivision that cut nothing: the same
        // primitives, each its own parent, all kept.
        const int count = int(torn.parents[0].size());
        context_.reshape(parent, [&](CollisionFilter&) { parent.subdivide(std::move(torn.parts[0]), torn.parents[0], count); });
        addState(record, worldState(parent, parent.physicalMesh().mass), true);
        it->breakable = fracture::breakableConnections(parent.physicalMesh(), parent.settings().tear.everywhere);
        return opened(t);
    }
    const std::string name = parent.name();
    for (size_t k = 0; k < torn.parts.size(); ++k) torn.parts[k].name = name + "." + std::to_string(k + 1);
    // A soft body keeps its largest part in place (VisualBody::keepPart): only the others are
    // built; a plastic body's parts are all new (each its own rigid motion and frame).
    const int kept = soft ? fracture::largestPart(torn) : -1;
    const std::vector<const Joint*> joints = context_.jointsOf(parent);
    const std::vector<VisualBody*> bodies = soft ? softParts(parent, torn, kept) : plasticParts(parent, torn, record);
    for (VisualBody* body : bodies) {
        record.parts.push_back(body->id());
        if (body != &parent)
            bodies_.push_back({body, fracture::breakableConnections(body->physicalMesh(), body->settings().tear.everywhere),
                               body->plasticEvents()});
    }
    // Joint copies for every part that touches a joint's box (the kept one too), as for new
    // bodies; the parent's own joints then go, as they would with it.
    // The new soft parts' meshes were moved into their bodies; the kept one is still the part.
    std::vector<const geometry::PhysicalMesh*> meshes;
    for (size_t k = 0; k < bodies.size(); ++k)
        meshes.push_back(soft && int(k) != kept ? &bodies[k]->physicalMesh() : &torn.parts[k]);
    timing_.jointsRecreated += transferJoints(context_, parent, bodies, meshes);
    context_.push(Event{EventType::BodyTorn, parent.id(), -1, 0.0, name, int(connections.size()), record.parts});
    if (kept < 0) {
        context_.removeBody(parent); // its joints go with it; forget() is called first
    } else {
        for (const Joint* joint : joints) context_.removeJoint(*joint);
        context_.reshape(parent, [&](CollisionFilter&) {
            parent.keepPart(std::move(torn.parts[size_t(kept)]), torn.parents[size_t(kept)]);
        });
        tearable(parent).breakable =
            fracture::breakableConnections(parent.physicalMesh(), parent.settings().tear.everywhere);
    }
    if (soft)
        for (const VisualBody* body : bodies) {
            const oriented::OrientedParticles& p = body->solver()->particles();
            record.massAfter += totalMass(p);
            record.momentumAfter += p.linearMomentum();
            record.angularMomentumAfter += p.angularMomentum();
        }
    finish(std::move(record), int(bodies.size()), t);
    return bodies;
}

TearSystem::Tearable& TearSystem::tearable(const VisualBody& body) {
    return *std::find_if(bodies_.begin(), bodies_.end(), [&](const Tearable& t) { return t.body == &body; });
}

std::vector<VisualBody*> TearSystem::softParts(VisualBody& parent, fracture::TearResult& torn, int kept) {
    // The new parts take the parent's particles, as they are now (the same primitives, so the
    // same masses and moments), and its hulls of them (addPart); the kept part takes its own in
    // keepPart, after the others, and drops the hulls they took.
    std::vector<VisualBody*> bodies;
    for (size_t k = 0; k < torn.parts.size(); ++k) {
        if (int(k) == kept) {
            bodies.push_back(&parent);
            continue;
        }
        bodies.push_back(&context_.addPart(parent, std::move(torn.parts[k]), torn.parents[k]));
    }
    return bodies;
}

std::vector<VisualBody*> TearSystem::plasticParts(VisualBody& parent, fracture::TearResult& torn, Record& record) {
    // The parts are in the parent's rest (mesh) coordinates: placed where the parent's mesh is,
    // each moves as the parent moved at its own centre of mass.
    const btTransform pose = parent.meshTransform();
    const Eigen::Isometry3d toWorld = toEigen(pose);
    const geometry::RigidState before = worldState(parent, parent.physicalMesh().mass);
    const bool moves = parent.rigidBody().getInvMass() > 0;
    const std::vector<bool>& fixedBefore = parent.solver()->particles().fixed;
    std::vector<VisualBody*> bodies;
    for (size_t k = 0; k < torn.parts.size(); ++k) {
        VisualBody& body = context_.addBody(torn.parts[k], parent.settings(), pose);
        std::vector<int> fixed; // joint-box primitives stay the part's boundary conditions
        for (size_t i = 0; i < torn.parents[k].size(); ++i)
            if (fixedBefore[size_t(torn.parents[k][i])]) fixed.push_back(int(i));
        body.fixPrimitives(fixed);
        const geometry::RigidState state = geometry::partState(before, geometry::transformed(torn.parts[k].mass, toWorld));
        if (moves) {
            body.rigidBody().setLinearVelocity(toBullet(state.velocity));
            body.rigidBody().setAngularVelocity(toBullet(state.angularVelocity));
        }
        addState(record, moves ? state : worldState(body, torn.parts[k].mass), true);
        bodies.push_back(&body);
    }
    return bodies;
}

void TearSystem::finish(Record record, int parts, std::chrono::steady_clock::time_point start) {
    timing_.connectionsBroken += record.connectionsBroken;
    records_.push_back(std::move(record));
    if (records_.size() > kKeptRecords) records_.erase(records_.begin());
    ++timing_.events;
    timing_.parts += parts;
    timing_.bodies += secondsSince(start);
}

std::vector<int> TearSystem::stretched(Tearable& tearable) {
    const VisualBody& body = *tearable.body;
    const geometry::PhysicalMesh& mesh = body.physicalMesh();
    const TearSettings& s = body.settings().tear;
    std::vector<int> over;
    if (body.deformation() == Deformation::Soft) {
        over = fracture::stretchedConnections(tearable.breakable, mesh.primitives, body.softPoses(), s.distance);
    } else {
        // A plastic body's primitives move only when it is dented; the rest shape is its
        // primitives as they are (mesh coordinates).
        if (body.plasticEvents() == tearable.dentsMeasured) return {};
        tearable.dentsMeasured = body.plasticEvents();
        tearable.breakable = fracture::breakableConnections(mesh, s.everywhere); // subdivided since?
        const std::vector<Eigen::Isometry3d> rest(mesh.primitives.size(), Eigen::Isometry3d::Identity());
        over = fracture::stretchedConnections(tearable.breakable, mesh.primitives, rest, s.distance);
    }
    for (int& k : over) k = tearable.breakable[size_t(k)].connection;
    return over;
}

void TearSystem::step(double, const ContactSnapshot&) {
    const auto t = SteadyClock::now();
    struct Stretched {
        VisualBody* body;
        std::vector<int> connections;
    };
    std::vector<Stretched> stretchedNow;
    for (Tearable& tearable : bodies_) {
        std::vector<int> over = stretched(tearable);
        if (!over.empty()) stretchedNow.push_back({tearable.body, std::move(over)});
    }
    timing_.stretch += secondsSince(t);
    // Parts made here are new bodies: they are measured from the next step on.
    for (const Stretched& s : stretchedNow) tear(*s.body, s.connections);
}

void TearSystem::forget(VisualBody& body) {
    std::erase_if(bodies_, [&](const Tearable& t) { return t.body == &body; });
}

std::vector<TearSystem::Record> TearSystem::takeRecords() {
    std::vector<Record> out;
    out.swap(records_);
    return out;
}

} // namespace shatter
