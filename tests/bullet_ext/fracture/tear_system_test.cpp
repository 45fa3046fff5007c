// The Bullet side of tearing: a soft 10 × 10 sheet with a tear line down its middle, hung from
// a static rail by two ball-joint boxes or floating free. What tears and what does not, the
// parts as bodies (names, primitives, particles handed on exactly), joints, determinism and
// bad settings.
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/fracture/TearSystem.h>
#include <shatter/plugin/common/InputError.h>
#include "tests/bullet_ext/shape/same_shape.h"
#include "tests/fracture/SheetFixture.h"
#include "tests/support/EventsOf.h"
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <limits>
#include <set>

namespace shatter {
namespace {

using test::eventsOf;
using test::SheetSpec;

// The sheet (x, y in [0, 1], z = 0) with its tear line at x = 0.5, a rail above it and ball
// joints: one box over the top-left quads (x in [0.05, 0.25]), one over the top-right ones.
geometry::PhysicalObject hangingSheet(const SheetSpec& spec = {.column = 5, .from = 0, .to = 10}) {
    std::string obj = test::sheetObj(spec);
    int next = (spec.n + 1) * (spec.n + 1) + 1;
    auto box = [&](const std::string& name, Eigen::Vector3d lo, Eigen::Vector3d hi) {
        obj += "o " + name + "\n";
        for (int c = 0; c < 8; ++c)
            obj += "v " + std::to_string(c & 1 ? hi.x() : lo.x()) + " " + std::to_string(c & 2 ? hi.y() : lo.y()) + " " +
                   std::to_string(c & 4 ? hi.z() : lo.z()) + "\n";
        const int f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        for (const auto& face : f)
            obj += "f " + std::to_string(next + face[0]) + " " + std::to_string(next + face[1]) + " " +
                   std::to_string(next + face[2]) + " " + std::to_string(next + face[3]) + "\n";
        next += 8;
    };
    box("rail", {-0.1, 1.02, -0.05}, {1.1, 1.08, 0.05});
    box("joint.ball.rail.sheet.left", {0.05, 0.97, -0.03}, {0.25, 1.04, 0.02});
    box("joint.ball.rail.sheet.right", {0.75, 0.97, -0.03}, {0.95, 1.04, 0.02});
    geometry::PhysicalMeshSettings settings;
    settings.thickness = 0.01;
    settings.density = 200;
    return geometry::buildPhysicalObject(geometry::parseObj(obj, "sheet.obj"), settings);
}

BodySettings cloth(double distance = 0.01) {
    BodySettings s;
    s.deformation = Deformation::Soft;
    s.solver.stiffness = 0.5;
    s.tear.enabled = true;
    s.tear.distance = distance;
    return s;
}

BodySettings staticRail() {
    BodySettings s;
    s.dynamic = false;
    return s;
}

VisualBody* named(const Plugin& plugin, const std::string& name) {
    for (const auto& b : plugin.bodies())
        if (b->name() == name) return b.get();
    return nullptr;
}

// Gives the particles of the sheet's left half (x < 0.5) velocity −v x̂ and the right half +v x̂.
void pullApart(VisualBody& sheet, double v) {
    auto& p = sheet.solver()->particles();
    for (int i = 0; i < p.size(); ++i) p.velocity[size_t(i)] = Eigen::Vector3d(p.restPosition[size_t(i)].x() < 0.5 ? -v : v, 0, 0);
}

TEST(TearSystem, HangingSheetDoesNotTearBelowTheDistance) {
    test::TestWorld w;
    Plugin plugin(w.world);
    const auto added = plugin.addObject(hangingSheet(), cloth(), btTransform::getIdentity(), {{"rail", staticRail()}});
    plugin.takeEvents();
    EXPECT_EQ(plugin.tears().breakable(*added.bodies[0]).size(), 28u);
    w.step(240);
    EXPECT_TRUE(eventsOf(plugin.takeEvents(), EventType::BodyTorn).empty());
    EXPECT_NE(named(plugin, "sheet"), nullptr);
    // It did hang and swing: the sheet moved (its lowest particle dropped or swung).
    const auto& p = named(plugin, "sheet")->solver()->particles();
    EXPECT_GT(p.velocity[0].norm() + (p.position[0] - p.restPosition[0]).norm(), 0.0);
}

TEST(TearSystem, PulledApartSheetBecomesTwoBodiesOf50AlongItsLine) {
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    VisualBody& sheet = plugin.addVisualBody(hangingSheet().bodies[0], cloth(0.002), btTransform::getIdentity());
    pullApart(sheet, 10.0);
    plugin.takeEvents();
    w.step(60);
    const auto torn = eventsOf(plugin.takeEvents(), EventType::BodyTorn);
    ASSERT_FALSE(torn.empty());
    std::multiset<size_t> sizes;
    std::set<std::string> names;
    for (const auto& b : plugin.bodies()) {
        sizes.insert(b->physicalMesh().primitives.size());
        names.insert(b->name());
    }
    EXPECT_EQ(sizes, (std::multiset<size_t>{50, 50}));
    EXPECT_EQ(names, (std::set<std::string>{"sheet.1", "sheet.2"}));
    // Only tear-line connections broke: 28 in all, whatever the number of events.
    int broken = 0;
    for (const auto& e : torn) broken += e.count;
    EXPECT_EQ(broken, 28);
    for (const auto& b : plugin.bodies()) {
        const bool left = b->solver()->particles().restPosition[0].x() < 0.5;
        for (const auto& r : b->solver()->particles().restPosition) EXPECT_EQ(r.x() < 0.5, left);
    }
}

TEST(TearSystem, PartsTakeTheParticlesAsTheyAreAndMomentumIsKept) {
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    VisualBody& sheet = plugin.addVisualBody(hangingSheet().bodies[0], cloth(), btTransform::getIdentity());
    auto& p = sheet.solver()->particles();
    for (int i = 0; i < p.size(); ++i) {
        p.velocity[size_t(i)] = Eigen::Vector3d(std::sin(i), std::cos(3.0 * i), 0.5 + 0.01 * i);
        p.angularVelocity[size_t(i)] = Eigen::Vector3d(0.1 * i, -1.0, 2.0);
    }
    w.step(5);
    const Eigen::Vector3d momentum = sheet.solver()->particles().linearMomentum();
    const Eigen::Vector3d angular = sheet.solver()->particles().angularMomentum();
    std::vector<int> all;
    for (const auto& c : plugin.tears().breakable(sheet)) all.push_back(c.connection);
    const auto parts = plugin.tears().tear(sheet, all);
    ASSERT_EQ(parts.size(), 2u);
    Eigen::Vector3d pAfter = Eigen::Vector3d::Zero(), lAfter = Eigen::Vector3d::Zero();
    for (const VisualBody* part : parts) {
        pAfter += part->solver()->particles().linearMomentum();
        lAfter += part->solver()->particles().angularMomentum();
    }
    EXPECT_LT((pAfter - momentum).norm(), 1e-9 * momentum.norm());
    EXPECT_LT((lAfter - angular).norm(), 1e-9 * angular.norm());
    const auto records = plugin.tears().takeRecords();
    ASSERT_EQ(records.size(), 1u);
    EXPECT_EQ(records[0].connectionsBroken, 28);
    EXPECT_EQ(records[0].idsSplit, 22);
    EXPECT_NEAR(records[0].massAfter, records[0].massBefore, 1e-12 * records[0].massBefore);
    EXPECT_LT((records[0].momentumAfter - records[0].momentumBefore).norm(), 1e-9 * momentum.norm());
}

TEST(TearSystem, JointsAreRecreatedOnlyForPartsInsideTheirBoxes) {
    test::TestWorld w;
    Plugin plugin(w.world);
    const auto added = plugin.addObject(hangingSheet(), cloth(), btTransform::getIdentity(), {{"rail", staticRail()}});
    VisualBody& sheet = *added.bodies[0];
    plugin.takeEvents();
    std::vector<int> all;
    for (const auto& c : plugin.tears().breakable(sheet)) all.push_back(c.connection);
    const auto parts = plugin.tears().tear(sheet, all);
    ASSERT_EQ(parts.size(), 2u);
    const auto recreated = eventsOf(plugin.takeEvents(), EventType::JointRecreated);
    ASSERT_EQ(recreated.size(), 2u);
    for (const auto& e : recreated) {
        const VisualBody* part = e.body == parts[0]->id() ? parts[0] : parts[1];
        const bool left = part->solver()->particles().restPosition[0].x() < 0.5;
        EXPECT_EQ(e.name, left ? "joint.ball.rail.sheet.left" : "joint.ball.rail.sheet.right");
    }
    EXPECT_NE(recreated[0].body, recreated[1].body);
    EXPECT_EQ(plugin.joints().size(), 2u); // the parent's went with it
    // The parts still hang: their fixed particles are the parent's attachments.
    for (const VisualBody* part : parts) {
        const auto& fixed = part->solver()->particles().fixed;
        EXPECT_GT(std::count(fixed.begin(), fixed.end(), true), 0);
    }
}

TEST(TearSystem, SlitOpensTheBodyItselfKeepingItsJointsAndParticles) {
    // A tear line from the top edge to the middle: all its connections break, the sheet stays
    // one piece, so it stays the same body with the slit opened in its visual mesh.
    test::TestWorld w;
    Plugin plugin(w.world);
    const auto added = plugin.addObject(hangingSheet({.column = 5, .from = 5, .to = 10}), cloth(),
                                        btTransform::getIdentity(), {{"rail", staticRail()}});
    VisualBody& sheet = *added.bodies[0];
    w.step(10);
    const auto before = sheet.solver()->particles();
    const int ids = sheet.physicalMesh().globalIdCount;
    const size_t connections = sheet.physicalMesh().connections.size();
    std::vector<int> all;
    for (const auto& c : plugin.tears().breakable(sheet)) all.push_back(c.connection);
    plugin.takeEvents();
    const auto parts = plugin.tears().tear(sheet, all);
    ASSERT_EQ(parts.size(), 1u);
    EXPECT_EQ(parts[0], &sheet);
    EXPECT_EQ(sheet.name(), "sheet");
    EXPECT_EQ(sheet.physicalMesh().globalIdCount, ids + 10); // 5 vertices of the slit and their inner copies
    EXPECT_EQ(sheet.physicalMesh().connections.size(), connections - all.size());
    EXPECT_EQ(sheet.solver()->particles().position, before.position);
    EXPECT_EQ(sheet.solver()->particles().velocity, before.velocity);
    EXPECT_EQ(sheet.solver()->particles().fixed, before.fixed);
    EXPECT_EQ(plugin.joints().size(), 2u);
    const auto events = plugin.takeEvents();
    EXPECT_EQ(eventsOf(events, EventType::BodyTorn).size(), 1u);
    EXPECT_TRUE(eventsOf(events, EventType::BodyRemoved).empty());
    EXPECT_EQ(sheet.visualMesh().faces.size(), 100u);
    // Nothing left to break on the line: the slit's connections are gone.
    EXPECT_TRUE(plugin.tears().breakable(sheet).empty());
    // It steps on as the slit body: still hanging by the same particles, where they were.
    w.step(10);
    const auto& after = sheet.solver()->particles();
    for (const Eigen::Vector3d& x : after.position) EXPECT_TRUE(x.allFinite());
    int hanging = 0;
    for (size_t i = 0; i < after.fixed.size(); ++i) {
        if (!after.fixed[i]) continue;
        EXPECT_EQ(after.position[i], before.position[i]) << "fixed particle " << i;
        ++hanging;
    }
    EXPECT_GT(hanging, 0);
    EXPECT_EQ(sheet.visualMesh().faces.size(), 100u);
}

// A tear running down the line a row at a time while the sheet hangs and swings: after every
// tear in place, what the body keeps up to date around the tear (its breakable list, its
// solver's groups, its visual faces) is what a full recomputation from its mesh gives, bit for
// bit; then the last row parts the halves.
TEST(TearSystem, TearsInPlaceKeepTheBodyAsAFullRecomputationMakesIt) {
    test::TestWorld w;
    Plugin plugin(w.world);
    const auto added = plugin.addObject(hangingSheet(), cloth(), btTransform::getIdentity(), {{"rail", staticRail()}});
    VisualBody& sheet = *added.bodies[0];
    for (int row = 9; row >= 1; --row) {
        w.step(3);
        std::vector<int> torn;
        for (const auto& c : plugin.tears().breakable(sheet))
            if (sheet.physicalMesh().primitives[size_t(c.a)].bounds().max.y() > 0.1 * row + 0.05) torn.push_back(c.connection);
        ASSERT_FALSE(torn.empty());
        ASSERT_EQ(plugin.tears().tear(sheet, torn).size(), 1u) << "row " << row;
        const geometry::PhysicalMesh& mesh = sheet.physicalMesh();
        const auto kept = plugin.tears().breakable(sheet);
        const auto rebuilt = fracture::breakableConnections(mesh, false);
        ASSERT_EQ(kept.size(), rebuilt.size()) << "row " << row;
        for (size_t k = 0; k < kept.size(); ++k) {
            EXPECT_EQ(kept[k].connection, rebuilt[k].connection);
            EXPECT_EQ(kept[k].vertices, rebuilt[k].vertices);
        }
        const oriented::OrientedParticles& p = sheet.solver()->particles();
        const oriented::ShapeMatchingGroups& groups = sheet.solver()->groups();
        const oriented::ShapeMatchingGroups fresh(p, mesh.connections);
        ASSERT_EQ(groups.size(), fresh.size());
        for (int g = 0; g < groups.size(); ++g) {
            const auto a = groups.members(g), b = fresh.members(g);
            EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << "row " << row << " group " << g;
            const Eigen::Matrix3d Da = groups.deformation(g, p, p.position, p.orientation);
            const Eigen::Matrix3d Db = fresh.deformation(g, p, p.position, p.orientation);
            EXPECT_TRUE((Da.array() == Db.array()).all()) << "row " << row << " group " << g;
        }
        EXPECT_EQ(sheet.visualMesh().faces, mesh.visual.faces);
        if (testing::Test::HasFailure()) return;
    }
    std::vector<int> rest;
    for (const auto& c : plugin.tears().breakable(sheet)) rest.push_back(c.connection);
    const auto parts = plugin.tears().tear(sheet, rest);
    ASSERT_EQ(parts.size(), 2u);
    EXPECT_EQ(parts[0]->name(), "sheet.1");
    EXPECT_EQ(parts[1]->name(), "sheet.2");
    w.step(3);
}

TEST(TearSystem, SplitKeepsItsLargerPartInPlaceAsTheFullRebuildMakesIt) {
    // A tear line at x = 0.3 parts the hanging sheet into 30 and 70 quads: the 70 stay in the
    // sheet's own body (same id, named sheet.2), only the 30 are a new body; both are what a
    // body built from scratch for each part (tearMesh's part holding the parent's particles)
    // would be: mesh (welded ids as tearMesh numbers them), mass properties, particles, shape.
    test::TestWorld w;
    Plugin plugin(w.world);
    const auto added = plugin.addObject(hangingSheet({.column = 3, .from = 0, .to = 10}), cloth(),
                                        btTransform::getIdentity(), {{"rail", staticRail()}});
    VisualBody& sheet = *added.bodies[0];
    auto& moving = sheet.solver()->particles();
    for (int i = 0; i < moving.size(); ++i) {
        moving.velocity[size_t(i)] = Eigen::Vector3d(std::sin(i), std::cos(3.0 * i), 0.5 + 0.01 * i);
        moving.angularVelocity[size_t(i)] = Eigen::Vector3d(0.1 * i, -1.0, 2.0);
    }
    w.step(3);
    const int id = sheet.id();
    std::vector<int> all;
    for (const auto& c : plugin.tears().breakable(sheet)) all.push_back(c.connection);
    std::vector<bool> broken(sheet.physicalMesh().connections.size(), false);
    for (int c : all) broken[size_t(c)] = true;
    fracture::TearResult expected = fracture::tearMesh(sheet.physicalMesh(), broken);
    const oriented::OrientedParticles before = sheet.solver()->particles();
    plugin.takeEvents();
    const auto parts = plugin.tears().tear(sheet, all);
    ASSERT_EQ(parts.size(), 2u);
    ASSERT_EQ(expected.parts.size(), 2u);
    EXPECT_EQ(parts[1], &sheet);
    EXPECT_EQ(sheet.id(), id);
    EXPECT_EQ(parts[0]->name(), "sheet.1");
    EXPECT_EQ(parts[1]->name(), "sheet.2");
    const auto events = plugin.takeEvents();
    EXPECT_TRUE(eventsOf(events, EventType::BodyRemoved).empty());
    ASSERT_EQ(eventsOf(events, EventType::BodyAdded).size(), 1u);
    EXPECT_EQ(eventsOf(events, EventType::BodyAdded)[0].body, parts[0]->id());
    const auto torn = eventsOf(events, EventType::BodyTorn);
    ASSERT_EQ(torn.size(), 1u);
    EXPECT_EQ(torn[0].body, id);
    EXPECT_EQ(torn[0].name, "sheet");
    EXPECT_EQ(torn[0].fragments, (std::vector<int>{parts[0]->id(), id}));
    EXPECT_EQ(eventsOf(events, EventType::JointRecreated).size(), 2u);
    EXPECT_EQ(plugin.joints().size(), 2u); // one copy per part; the sheet's own two went

    test::TestWorld w2;
    Plugin rebuilt(w2.world);
    for (size_t k = 0; k < 2; ++k) {
        expected.parts[k].name = "sheet." + std::to_string(k + 1);
        VisualBody& fresh = rebuilt.addVisualBody(expected.parts[k], cloth(), btTransform::getIdentity());
        fresh.takeParticles(before, expected.parents[k]);
        VisualBody& part = *parts[k];
        const geometry::PhysicalMesh &a = part.physicalMesh(), &b = fresh.physicalMesh();
        EXPECT_EQ(part.name(), fresh.name());
        ASSERT_EQ(a.primitives.size(), b.primitives.size());
        for (size_t i = 0; i < a.primitives.size(); ++i) {
            EXPECT_EQ(a.primitives[i].vertices(), b.primitives[i].vertices());
            EXPECT_EQ(a.primitives[i].globalIds(), b.primitives[i].globalIds());
            EXPECT_EQ(part.shape().primitives()[i].vertices(), fresh.shape().primitives()[i].vertices());
        }
        // The new part took the sheet's hulls instead of building its own: they, the trees
        // and the box must be those of the shape built from scratch.
        if (k == 0) test::expectSameShape(part.shape(), fresh.shape());
        EXPECT_EQ(a.globalIdCount, b.globalIdCount);
        EXPECT_EQ(a.connections, b.connections);
        EXPECT_EQ(a.visual.faces, b.visual.faces);
        EXPECT_EQ(a.visual.positions, b.visual.positions);
        EXPECT_EQ(a.mass.mass, b.mass.mass);
        EXPECT_EQ(a.mass.centerOfMass, b.mass.centerOfMass);
        EXPECT_EQ(a.mass.inertia, b.mass.inertia);
        EXPECT_TRUE(part.meshToBody().isApprox(fresh.meshToBody(), 0.0));
        const oriented::OrientedParticles &p = part.solver()->particles(), &q = fresh.solver()->particles();
        EXPECT_EQ(p.position, q.position);
        EXPECT_EQ(p.velocity, q.velocity);
        EXPECT_EQ(p.angularVelocity, q.angularVelocity);
        EXPECT_EQ(p.fixed, q.fixed);
        EXPECT_EQ(p.mass, q.mass);
        EXPECT_EQ(p.restPosition, q.restPosition);
        EXPECT_LT((p.linearMomentum() - q.linearMomentum()).norm(), 1e-9 * q.linearMomentum().norm());
        EXPECT_LT((p.angularMomentum() - q.angularMomentum()).norm(), 1e-9 * q.angularMomentum().norm());
        const oriented::ShapeMatchingGroups &g = part.solver()->groups(), &h = fresh.solver()->groups();
        ASSERT_EQ(g.size(), h.size());
        for (int i = 0; i < g.size(); ++i) {
            const auto x = g.members(i), y = h.members(i);
            EXPECT_TRUE(std::equal(x.begin(), x.end(), y.begin(), y.end())) << "part " << k << " group " << i;
        }
        EXPECT_EQ(part.visualMesh().positions, fresh.visualMesh().positions);
        EXPECT_EQ(part.visualMesh().faces, fresh.visualMesh().faces);
        const auto kb = plugin.tears().breakable(part);
        const auto fb = fracture::breakableConnections(b, false);
        ASSERT_EQ(kb.size(), fb.size());
        for (size_t c = 0; c < kb.size(); ++c) EXPECT_EQ(kb[c].connection, fb[c].connection);
    }
    const auto records = plugin.tears().takeRecords();
    ASSERT_EQ(records.size(), 1u);
    EXPECT_NEAR(records[0].massAfter, records[0].massBefore, 1e-12 * records[0].massBefore);
    EXPECT_LT((records[0].momentumAfter - records[0].momentumBefore).norm(), 1e-9 * records[0].momentumBefore.norm());
    EXPECT_LT((records[0].angularMomentumAfter - records[0].angularMomentumBefore).norm(),
              1e-9 * records[0].angularMomentumBefore.norm());
    w.step(3); // both parts go on stepping
    for (const VisualBody* part : parts)
        for (const auto& x : part->solver()->particles().position) EXPECT_TRUE(x.allFinite());
}

TEST(TearSystem, SameSceneSameTears) {
    auto run = [] {
        test::TestWorld w;
        w.world.setGravity(btVector3(0, 0, 0));
        Plugin plugin(w.world);
        BodySettings s = cloth(0.002);
        s.tear.everywhere = true;
        VisualBody& sheet = plugin.addVisualBody(hangingSheet().bodies[0], s, btTransform::getIdentity());
        pullApart(sheet, 10.0);
        w.step(30);
        std::vector<double> state;
        for (const auto& e : plugin.takeEvents())
            if (e.type == EventType::BodyTorn) state.push_back(e.time), state.push_back(e.count);
        for (const auto& b : plugin.bodies())
            for (const auto& x : b->solver()->particles().position) state.insert(state.end(), {x.x(), x.y(), x.z()});
        return state;
    };
    const auto a = run();
    EXPECT_GT(a.size(), 300u);
    EXPECT_EQ(a, run());
}

TEST(TearSystem, BadSettingsNameTheBody) {
    test::TestWorld w;
    Plugin plugin(w.world);
    const auto mesh = hangingSheet().bodies[0];
    for (double bad : {0.0, -0.01, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        try {
            plugin.addVisualBody(mesh, cloth(bad), btTransform::getIdentity());
            FAIL() << "no error for distance " << bad;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("body 'sheet': tear distance must be positive and finite"),
                      std::string::npos)
                << e.what();
        }
    }
    BodySettings rigid = cloth();
    rigid.deformation = Deformation::None;
    EXPECT_THROW(plugin.addVisualBody(mesh, rigid, btTransform::getIdentity()), InputError);
    VisualBody& plain = plugin.addVisualBody(mesh, BodySettings{}, btTransform::getIdentity());
    EXPECT_THROW(plugin.tears().tear(plain, {0}), InputError);
    VisualBody& soft = plugin.addVisualBody(mesh, cloth(), btTransform::getIdentity());
    EXPECT_THROW(plugin.tears().tear(soft, {int(mesh.connections.size())}), InputError);

    // A part taking the soft body's hulls needs one parent primitive each, strictly
    // increasing, of a soft body; the error names the part, and nothing is taken.
    std::vector<bool> broken(mesh.connections.size(), false);
    for (const auto& c : plugin.tears().breakable(soft)) broken[size_t(c.connection)] = true;
    fracture::TearResult torn = fracture::tearMesh(mesh, broken);
    ASSERT_EQ(torn.parts.size(), 2u);
    torn.parts[0].name = "sheet.1";
    std::vector<int> swapped = torn.parents[0];
    std::swap(swapped[0], swapped[1]);
    const std::vector<int> shorter(torn.parents[0].begin() + 1, torn.parents[0].end());
    for (const std::vector<int>& bad : {swapped, shorter}) {
        try {
            VisualBody(99, soft, torn.parts[0], bad, cloth());
            FAIL() << "no error";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("body 'sheet.1': needs one primitive of body 'sheet'"), std::string::npos)
                << e.what();
        }
    }
    EXPECT_THROW(VisualBody(99, plain, torn.parts[0], torn.parents[0], cloth()), InputError);
    EXPECT_THROW(VisualBody(99, soft, torn.parts[0], torn.parents[0], BodySettings{}), InputError);
    for (int i = 0; i < soft.shape().primitiveCount(); ++i) EXPECT_GT(soft.shape().child(i).getNumPoints(), 0);
}

} // namespace
} // namespace shatter
