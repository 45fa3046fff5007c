#include <shatter/bullet_ext/fracture/TearSystem.h>
#include <shatter/plugin/common/Stopwatch.h>

#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/fracture/JointTransfer.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/fracture/Tearing.h>

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

} // namespace

void TearSystem::add(VisualBody& body) {
    const TearSettings& s = body.settings().tear;
    if (!s.enabled) throw InputError("body '" + body.name() + "': tear is not enabled in its settings");
    if (body.deformation() != Deformation::Soft)
        throw InputError("body '" + body.name() + "': tear needs deformation Soft (only a soft body stretches)");
    bodies_.push_back({&body, fracture::breakableConnections(body.physicalMesh(), s.everywhere)});
}

std::vector<fracture::BreakableConnection> TearSystem::breakable(const VisualBody& body) const {
    const auto it = std::find_if(bodies_.begin(), bodies_.end(), [&](const Tearable& t) { return t.body == &body; });
    return it == bodies_.end() ? std::vector<fracture::BreakableConnection>{} : it->breakable;
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
    auto t = SteadyClock::now();
    fracture::TearResult torn = fracture::tearMesh(mesh, broken);
    timing_.tearing += secondsSince(t);
    t = SteadyClock::now();

    const oriented::OrientedParticles& from = parent.solver()->particles();
    Record record;
    record.parent = parent.id();
    record.time = context_.time();
    record.connectionsBroken = int(connections.size());
    record.idsSplit = torn.idsSplit;
    record.massBefore = totalMass(from);
    record.momentumBefore = from.linearMomentum();
    record.angularMomentumBefore = from.angularMomentum();
    if (torn.parts.size() == 1) {
        // The body only opened: it stays the body it was (id, name, shape, joints, particles),
        // with the new ids, faces and connections.
        parent.reconnect(std::move(torn.parts[0]));
        it->breakable = fracture::breakableConnections(parent.physicalMesh(), parent.settings().tear.everywhere);
        record.massAfter = record.massBefore;
        record.momentumAfter = parent.solver()->particles().linearMomentum();
        record.angularMomentumAfter = parent.solver()->particles().angularMomentum();
        record.parts = {parent.id()};
        context_.push(Event{EventType::BodyTorn, parent.id(), -1, 0.0, parent.name(), int(connections.size()), record.parts});
        finish(std::move(record), 1, t);
        return {&parent};
    }
    std::vector<VisualBody*> bodies;
    for (size_t k = 0; k < torn.parts.size(); ++k) {
        torn.parts[k].name = parent.name() + "." + std::to_string(k + 1);
        VisualBody& body = context_.addBody(torn.parts[k], parent.settings(), btTransform::getIdentity());
        // The part's particles are the parent's, as they are now (the same primitives, so the
        // same masses and moments).
        oriented::OrientedParticles& to = body.solver()->particles();
        const std::vector<int>& parents = torn.parents[k];
        for (int i = 0; i < to.size(); ++i) {
            const int j = parents[size_t(i)];
            to.position[size_t(i)] = from.position[size_t(j)];
            to.orientation[size_t(i)] = from.orientation[size_t(j)];
            to.velocity[size_t(i)] = from.velocity[size_t(j)];
            to.angularVelocity[size_t(i)] = from.angularVelocity[size_t(j)];
            to.fixed[size_t(i)] = from.fixed[size_t(j)];
        }
        body.refitSoft();
        context_.world().updateSingleAabb(&body.rigidBody());
        record.massAfter += totalMass(to);
        record.momentumAfter += to.linearMomentum();
        record.angularMomentumAfter += to.angularMomentum();
        record.parts.push_back(body.id());
        bodies.push_back(&body);
        bodies_.push_back({&body, fracture::breakableConnections(body.physicalMesh(), body.settings().tear.everywhere)});
    }
    timing_.jointsRecreated += transferJoints(context_, parent, bodies, torn.parts);
    Event event{EventType::BodyTorn, parent.id(), -1, 0.0, parent.name(), int(connections.size()), record.parts};
    context_.push(std::move(event));
    context_.removeBody(parent); // its joints go with it; forget() is called first
    finish(std::move(record), int(bodies.size()), t);
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

void TearSystem::step(double, const ContactSnapshot&) {
    const auto t = SteadyClock::now();
    struct Stretched {
        VisualBody* body;
        std::vector<int> connections;
    };
    std::vector<Stretched> stretched;
    for (const Tearable& tearable : bodies_) {
        const VisualBody& body = *tearable.body;
        const auto over = fracture::stretchedConnections(tearable.breakable, body.physicalMesh().primitives,
                                                         body.softPoses(), body.settings().tear.distance);
        if (over.empty()) continue;
        Stretched s{tearable.body, {}};
        for (int k : over) s.connections.push_back(tearable.breakable[size_t(k)].connection);
        stretched.push_back(std::move(s));
    }
    timing_.stretch += secondsSince(t);
    // Parts made here are new bodies: they are measured from the next step on.
    for (const Stretched& s : stretched) tear(*s.body, s.connections);
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
