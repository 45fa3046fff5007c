// Ductile fracture (source 000 §3.6): a plastic body is rigid between hits; a dent moves its
// primitives to a new rest shape, and where that pulled two connected primitives' shared
// vertices more than tear.distance apart the connection breaks. What tears and what does not,
// the parts as rigid plastic bodies (names, primitives, mass, momentum), joints, a slit that
// leaves one body, and the whole chain (subdivide, dent, tear) from a real hit, twice.
#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/Joints.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/fracture/TearSystem.h>
#include <shatter/plugin/geometry/ObjFile.h>
#include "tests/fracture/SheetFixture.h"
#include "tests/bullet_ext/fracture/PlateHit.h"
#include "tests/support/EventsOf.h"
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <set>
#include <sstream>

namespace shatter {
namespace {

using test::eventsOf;

// A steel bar of 10 quads of 10 × 10 cm along x (x in [0, 1], y in [0, 0.1], facing +z,
// extruded 1 cm towards −z); with `line`, a tear line across it at x = 0.5; with `joint`, a
// static wall at x < 0 and a ball-joint box over the first quad and the wall.
geometry::PhysicalObject bar(bool line, bool joint = false) {
    std::ostringstream obj;
    obj << "o bar\n";
    for (int j = 0; j <= 1; ++j)
        for (int i = 0; i <= 10; ++i) obj << "v " << 0.1 * i << " " << 0.1 * j << " 0\n";
    for (int i = 0; i < 10; ++i) obj << "f " << i + 1 << " " << i + 2 << " " << i + 13 << " " << i + 12 << "\n";
    if (line) obj << "o tear.bar\nl 6 17\n";
    int next = 23;
    auto box = [&](const std::string& name, Eigen::Vector3d lo, Eigen::Vector3d hi) {
        obj << "o " << name << "\n";
        for (int c = 0; c < 8; ++c)
            obj << "v " << (c & 1 ? hi.x() : lo.x()) << " " << (c & 2 ? hi.y() : lo.y()) << " " << (c & 4 ? hi.z() : lo.z()) << "\n";
        const int f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        for (const auto& face : f)
            obj << "f " << next + face[0] << " " << next + face[1] << " " << next + face[2] << " " << next + face[3] << "\n";
        next += 8;
    };
    if (joint) {
        box("wall", {-0.1, -0.1, -0.1}, {0.0, 0.2, 0.1});
        box("joint.ball.wall.bar.end", {-0.02, 0.02, -0.03}, {0.04, 0.08, 0.02});
    }
    geometry::PhysicalMeshSettings settings;
    settings.thickness = 0.01;
    settings.density = 7800;
    return geometry::buildPhysicalObject(geometry::parseObj(obj.str(), "bar.obj"), settings);
}

BodySettings ductile(bool everywhere, double distance = 0.004) {
    BodySettings s;
    s.deformation = Deformation::Plastic;
    s.tear.enabled = true;
    s.tear.everywhere = everywhere;
    s.tear.distance = distance;
    return s;
}

// Pushes the primitives of `body` whose centre lies at x > `from` (mesh coordinates) in by
// `depth` along −z, as a hit would (the body out of the world meanwhile), and returns how many.
int dentBeyond(test::TestWorld& w, VisualBody& body, double from, double depth) {
    std::vector<oriented::Dent> dents;
    const auto& primitives = body.physicalMesh().primitives;
    for (int i = 0; i < int(primitives.size()); ++i)
        if (primitives[size_t(i)].bounds().center().x() > from) dents.push_back({i, Eigen::Vector3d(0, 0, -depth)});
    w.world.removeRigidBody(&body.rigidBody());
    body.dent(dents);
    w.world.addRigidBody(&body.rigidBody());
    return int(dents.size());
}

TEST(DuctileTear, NothingTearsBelowTheDistance) {
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    VisualBody& body = plugin.addVisualBody(bar(false).bodies[0], ductile(true), btTransform::getIdentity());
    EXPECT_EQ(plugin.tears().breakable(body).size(), 9u); // every neighbour pair of the row
    // Bent by 4 mm: the dented half and the three rings beside it move, shared vertices drift
    // apart by about a tenth of that, far below the 4 mm distance.
    dentBeyond(w, body, 0.5, 0.004);
    plugin.takeEvents();
    w.step(10);
    EXPECT_TRUE(eventsOf(plugin.takeEvents(), EventType::BodyTorn).empty());
    ASSERT_EQ(plugin.bodies().size(), 1u);
    EXPECT_EQ(plugin.bodies()[0]->name(), "bar");
    EXPECT_GT(body.dentDepthMax(), 0.003);
    // The same bend by 8 cm does tear it.
    dentBeyond(w, body, 0.5, 0.08);
    w.step(1);
    EXPECT_FALSE(eventsOf(plugin.takeEvents(), EventType::BodyTorn).empty());
}

TEST(DuctileTear, BarBentPastTheDistanceAtItsTearLineTearsIntoItsTwoHalves) {
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    VisualBody& body = plugin.addVisualBody(bar(true).bodies[0], ductile(false), btTransform::getIdentity());
    ASSERT_EQ(plugin.tears().breakable(body).size(), 1u); // across the line only
    const double mass = body.physicalMesh().mass.mass;
    // The right half pushed in 8 cm: the bar bends over the three rings around the push (the
    // hit quads turn with their neighbours), and the one connection across the line opens
    // about 8 mm, twice the distance.
    EXPECT_EQ(dentBeyond(w, body, 0.5, 0.08), 5);
    plugin.takeEvents();
    w.step(1);
    const auto torn = eventsOf(plugin.takeEvents(), EventType::BodyTorn);
    ASSERT_EQ(torn.size(), 1u);
    EXPECT_EQ(torn[0].count, 1);
    ASSERT_EQ(plugin.bodies().size(), 2u);
    for (int k = 0; k < 2; ++k) {
        const VisualBody& part = *plugin.bodies()[size_t(k)];
        EXPECT_EQ(part.name(), k == 0 ? "bar.1" : "bar.2");
        EXPECT_EQ(part.deformation(), Deformation::Plastic);
        ASSERT_EQ(part.physicalMesh().primitives.size(), 5u);
        // bar.1 is the left half, bar.2 the dented right half, about 8 cm in.
        for (const auto& p : part.physicalMesh().primitives) {
            EXPECT_EQ(p.bounds().center().x() > 0.5, k == 1);
            if (k == 1) {
                EXPECT_LT(p.bounds().max.z(), -0.07);
            }
        }
        EXPECT_NEAR(part.physicalMesh().mass.mass, 0.5 * mass, 1e-12 * mass);
        EXPECT_EQ(part.physicalMesh().connections.size(), 4u);
    }
    // Each half is whole: its visual mesh has the half's 5 faces and the line's two ends on both.
    EXPECT_EQ(plugin.bodies()[0]->physicalMesh().visual.faces.size(), 5u);
    EXPECT_EQ(plugin.bodies()[1]->physicalMesh().visual.faces.size(), 5u);
    const auto records = plugin.tears().takeRecords();
    ASSERT_EQ(records.size(), 1u);
    EXPECT_EQ(records[0].idsSplit, 4); // the line's two ends, on the face and behind it
}

TEST(DuctileTear, PartsCarryTheParentsMassAndMomenta) {
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    VisualBody& body = plugin.addVisualBody(bar(true).bodies[0], ductile(false), btTransform::getIdentity());
    body.rigidBody().setLinearVelocity(btVector3(1.0f, -2.0f, 0.5f));
    body.rigidBody().setAngularVelocity(btVector3(0.3f, 2.0f, -1.0f));
    dentBeyond(w, body, 0.5, 0.08);
    w.step(1);
    const auto records = plugin.tears().takeRecords();
    ASSERT_EQ(records.size(), 1u);
    const TearSystem::Record& r = records[0];
    ASSERT_EQ(r.parts.size(), 2u);
    // In double precision the parts' exact mass properties and the parent's motion at their
    // centres add up to the parent.
    EXPECT_NEAR(r.massAfter, r.massBefore, 1e-12 * r.massBefore);
    EXPECT_LT((r.momentumAfter - r.momentumBefore).norm(), 1e-9 * r.momentumBefore.norm());
    EXPECT_LT((r.angularMomentumAfter - r.angularMomentumBefore).norm(), 1e-9 * r.angularMomentumBefore.norm());
    // The Bullet bodies carry it (single precision).
    Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
    for (const auto& part : plugin.bodies())
        momentum += part->physicalMesh().mass.mass * toEigen(part->rigidBody().getLinearVelocity());
    EXPECT_LT((momentum - r.momentumBefore).norm(), 1e-5 * r.momentumBefore.norm());
}

TEST(DuctileTear, OnlyThePartInsideTheJointBoxKeepsTheJoint) {
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    BodySettings wall;
    wall.dynamic = false;
    BodySettings s = ductile(false);
    s.dynamic = false; // the dent is made by hand, out of the world: no joint may pull meanwhile
    const auto added = plugin.addObject(bar(true, true), s, btTransform::getIdentity(), {{"wall", wall}});
    VisualBody& body = *added.bodies[0];
    ASSERT_EQ(body.name(), "bar");
    dentBeyond(w, body, 0.5, 0.08);
    plugin.takeEvents();
    w.step(1);
    const auto recreated = eventsOf(plugin.takeEvents(), EventType::JointRecreated);
    ASSERT_EQ(recreated.size(), 1u);
    ASSERT_EQ(plugin.joints().size(), 1u);
    EXPECT_EQ(plugin.joints()[0]->bodyB().name(), "bar.1");
    EXPECT_EQ(recreated[0].name, "joint.ball.wall.bar.end");
    // The first quad, in the box, stays fixed in the part that kept it.
    for (const auto& part : plugin.bodies()) {
        if (part->name() == "wall") continue;
        const auto& fixed = part->solver()->particles().fixed;
        EXPECT_EQ(std::count(fixed.begin(), fixed.end(), true), part->name() == "bar.1" ? 1 : 0) << part->name();
    }
}

TEST(DuctileTear, ASlitOpensThePlasticBodyInPlace) {
    // A 10 × 10 plate with a tear line up to its middle, its right half pushed in: the line's
    // connections break, the plate stays one piece and so stays the same body, opened.
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    VisualBody& plate =
        plugin.addVisualBody(test::sheetMesh({.column = 5, .from = 0, .to = 5}), ductile(false), btTransform::getIdentity());
    const int id = plate.id(), ids = plate.physicalMesh().globalIdCount;
    const double mass = plate.physicalMesh().mass.mass;
    dentBeyond(w, plate, 0.5, 0.08);
    const size_t connections = plate.physicalMesh().connections.size();
    const btTransform meshAt = plate.meshTransform();
    plugin.takeEvents();
    w.step(1);
    const auto events = plugin.takeEvents();
    const auto torn = eventsOf(events, EventType::BodyTorn);
    ASSERT_EQ(torn.size(), 1u);
    EXPECT_TRUE(eventsOf(events, EventType::BodyRemoved).empty());
    ASSERT_EQ(plugin.bodies().size(), 1u);
    EXPECT_EQ(plate.id(), id);
    EXPECT_EQ(plate.name(), "sheet");
    EXPECT_EQ(plate.physicalMesh().connections.size(), connections - size_t(torn[0].count));
    EXPECT_GT(plate.physicalMesh().globalIdCount, ids);
    EXPECT_NEAR(plate.physicalMesh().mass.mass, mass, 1e-12 * mass);
    EXPECT_TRUE(plate.meshTransform().getOrigin().fuzzyZero() && meshAt.getOrigin().fuzzyZero());
    // Nothing is left to break on the line.
    EXPECT_TRUE(plugin.tears().breakable(plate).empty());
}

// A static plastic plate of 4 × 4 steel tiles of 25 cm that subdivides where hit and may tear
// everywhere, and a 4 kg ball dropped on it at 10 m/s.
struct DuctileHit {
    test::TestWorld w;
    Plugin plugin{w.world};
    test::FallingBall ball;
    std::vector<Event> events;
    double massBefore = 0.0;

    explicit DuctileHit(double distance = 0.004) {
        BodySettings s = ductile(true, distance);
        s.dynamic = false;
        s.fracture.enabled = true;
        s.fracture.mode = FractureMode::Subdivide;
        s.fracture.pattern = PatternKind::Voronoi;
        s.fracture.setCells(48);
        s.fracture.radius = 0.2;
        s.fracture.threshold = 1.0;
        s.fracture.seed = 7;
        VisualBody& plate = plugin.addVisualBody(test::plate(4, 4, 0.25), s, btTransform::getIdentity());
        massBefore = plate.physicalMesh().mass.mass;
        ball.drop(w, 4.0f, 20);
        events = plugin.takeEvents();
    }
    // Every body's primitives' vertices, in order.
    std::vector<Eigen::Vector3d> vertices() const {
        std::vector<Eigen::Vector3d> out;
        for (const auto& b : plugin.bodies())
            for (const auto& p : b->physicalMesh().primitives) out.insert(out.end(), p.vertices().begin(), p.vertices().end());
        return out;
    }
};

TEST(DuctileTear, AHardHitSubdividesDentsAndTearsTheSameWayTwice) {
    DuctileHit a;
    // The chain of 000 §3.6: cut finer, dented on the fine pieces, torn where it stretched.
    std::vector<EventType> order;
    for (const auto& e : a.events)
        if (e.type == EventType::BodySubdivided || e.type == EventType::BodyDented || e.type == EventType::BodyTorn)
            if (order.empty() || order.back() != e.type) order.push_back(e.type);
    ASSERT_GE(order.size(), 3u);
    EXPECT_EQ(order[0], EventType::BodySubdivided);
    EXPECT_EQ(order[1], EventType::BodyDented);
    EXPECT_EQ(order[2], EventType::BodyTorn);
    ASSERT_GE(a.plugin.bodies().size(), 2u);
    double mass = 0.0;
    std::set<std::string> names;
    for (const auto& b : a.plugin.bodies()) {
        mass += b->physicalMesh().mass.mass;
        names.insert(b->name());
    }
    EXPECT_NEAR(mass, a.massBefore, 1e-9 * a.massBefore);
    EXPECT_TRUE(names.count("plate.1") && names.count("plate.2"));
    // Same scene, same seed: the same tears, bit for bit.
    DuctileHit b;
    ASSERT_EQ(a.events.size(), b.events.size());
    for (size_t i = 0; i < a.events.size(); ++i) {
        EXPECT_EQ(a.events[i].type, b.events[i].type);
        EXPECT_EQ(a.events[i].count, b.events[i].count);
        EXPECT_EQ(a.events[i].fragments, b.events[i].fragments);
    }
    EXPECT_EQ(a.vertices(), b.vertices());
}

TEST(DuctileTear, BreakableConnectionsFollowASubdivision) {
    // Too far a distance to tear: the plate is cut finer and dented, and stays one body whose
    // breakable connections are those of its new mesh.
    DuctileHit hit(1.0);
    ASSERT_EQ(hit.plugin.bodies().size(), 1u);
    const VisualBody& plate = *hit.plugin.bodies()[0];
    EXPECT_TRUE(eventsOf(hit.events, EventType::BodyTorn).empty());
    ASSERT_FALSE(eventsOf(hit.events, EventType::BodySubdivided).empty());
    const auto breakable = hit.plugin.tears().breakable(plate);
    const auto& connections = plate.physicalMesh().connections;
    EXPECT_GT(breakable.size(), 42u); // more than the 4 × 4 plate had: 24 edge and 18 diagonal neighbour pairs
    for (const auto& c : breakable) {
        ASSERT_LT(size_t(c.connection), connections.size());
        EXPECT_EQ(connections[size_t(c.connection)], std::make_pair(c.a, c.b));
    }
}

} // namespace
} // namespace shatter
