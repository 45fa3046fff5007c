// The Bullet side of fracture, with fragments made by hand (no cutting): bodies, conservation,
// no energy from pieces created touching, joints handed on, events, settings.
#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/fracture/FractureSystem.h>
#include <shatter/bullet_ext/shape/FragmentHull.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/fracture/FractureMesh.h>
#include "tests/bullet_ext/fracture/FractureFixtures.h"
#include "tests/bullet_ext/shape/same_shape.h"
#include "tests/fracture/FractureFixtures.h"
#include "tests/support/PartsConserve.h"
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <set>

namespace shatter {
namespace {

using test::cubeBlock;
using test::partition;
using test::at;

// An open sheet of n × n quads 5 cm wide in the z = 0 plane, extruded 1 cm.
geometry::PhysicalMesh quadSheet(int n) {
    std::vector<Eigen::Vector3d> positions;
    std::vector<std::vector<int>> faces;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) positions.emplace_back(0.05 * i, 0.05 * j, 0.0);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            faces.push_back({(n + 1) * j + i, (n + 1) * j + i + 1, (n + 1) * (j + 1) + i + 1, (n + 1) * (j + 1) + i});
    geometry::PhysicalMeshSettings how;
    how.thickness = 0.01;
    return geometry::buildPhysicalMesh("sheet", positions, faces, how);
}

BodySettings breakable() {
    BodySettings s;
    s.fracture.enabled = true;
    return s;
}


TEST(FractureSystem, FragmentsCarryTheMassAndMomentaOfTheirParent) {
    // A 4×3×2 block of 5 cm cubes, moving and spinning without gravity, is split into a single
    // cube (a hull), an L and the rest. Computed in double (the record): mass to 1e-12 and
    // momenta to 1e-9 of the terms summed; as Bullet holds them (single precision
    // velocities, masses and inertia): 1e-6.
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    const auto mesh = cubeBlock("block", 4, 3, 2, 0.05);
    const btTransform pose(btQuaternion(btVector3(1, 2, 3).normalized(), 0.7f), btVector3(0.3f, 1.2f, -0.4f));
    VisualBody& body = plugin.addVisualBody(mesh, breakable(), pose);
    body.rigidBody().setLinearVelocity(btVector3(0.5f, -1.0f, 2.0f));
    body.rigidBody().setAngularVelocity(btVector3(3.0f, -1.0f, 2.0f));
    w.step(3);
    test::BulletMomenta before;
    before.add(body.rigidBody());
    std::vector<int> group(24, 2);
    group[0] = 0;
    for (int p : {1, 2, 3, 7, 11}) group[p] = 1;
    const auto fragments = plugin.fractures().replace(body, partition(mesh, group), -1);
    ASSERT_EQ(fragments.size(), 3u);
    EXPECT_NE(dynamic_cast<const btConvexHullShape*>(fragments[0]->rigidBody().getCollisionShape()), nullptr)
        << "a single primitive collides as a hull";
    EXPECT_NE(dynamic_cast<const GroupShape*>(fragments[1]->rigidBody().getCollisionShape()), nullptr);
    const auto records = plugin.fractures().takeRecords();
    ASSERT_EQ(records.size(), 1u);
    const auto& r = records[0];
    const auto scale = test::expectPartsConserveTheWhole(r.before, r.parts);
    test::BulletMomenta after;
    for (const VisualBody* f : fragments) after.add(f->rigidBody());
    EXPECT_NEAR(after.mass, before.mass, 1e-6 * before.mass);
    EXPECT_LT((after.linear - before.linear).norm(), 1e-6 * scale.linear);
    EXPECT_LT((after.angular - before.angular).norm(), 1e-6 * scale.angular);
    // Each fragment moves as the parent did at its centre: the velocity field is the parent's.
    for (const VisualBody* f : fragments) {
        const btVector3 c = f->rigidBody().getCenterOfMassPosition();
        const Eigen::Vector3d expected = r.before.velocity + r.before.angularVelocity.cross(toEigen(c) - r.before.centre);
        EXPECT_LT((toEigen(f->rigidBody().getLinearVelocity()) - expected).norm(), 1e-5);
    }
}

TEST(FractureSystem, AnOpenBodyStaysItselfAsTheRestOfABreak) {
    // A sheet of 16 × 16 quads (extruded 1 cm), moving and spinning without gravity, is hit in
    // the middle: the pieces cut free become new bodies, and the body itself, edited in place,
    // is the rest (same id, fewer primitives, the rest's exact mass). Mass and momenta add up
    // as for any break (double record to 1e-9; as Bullet holds them to 1e-6).
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    const auto mesh = quadSheet(16);
    BodySettings s = breakable();
    s.fracture.radius = 0.15;
    s.fracture.setCells(16);
    const btTransform pose(btQuaternion(btVector3(1, 0, 1).normalized(), 0.4f), btVector3(0.1f, 0.5f, 0.2f));
    VisualBody& body = plugin.addVisualBody(mesh, s, pose);
    body.rigidBody().setLinearVelocity(btVector3(0.3f, 0.2f, -1.0f));
    body.rigidBody().setAngularVelocity(btVector3(1.0f, -2.0f, 0.5f));
    w.step(2);
    test::BulletMomenta before;
    before.add(body.rigidBody());
    const int id = body.id();
    const btVector3 centre = body.meshTransform() * btVector3(0.4f, 0.4f, 0.0f);
    const auto fragments = plugin.fracture(body, centre, body.meshTransform().getBasis() * btVector3(0, 0, -1));
    ASSERT_GE(fragments.size(), 3u);
    EXPECT_EQ(fragments.back(), &body) << "the rest is the body itself, last";
    EXPECT_EQ(body.id(), id);
    EXPECT_LT(body.physicalMesh().primitives.size(), mesh.primitives.size());
    EXPECT_EQ(body.physicalMesh().componentCount(), 1);
    const auto records = plugin.fractures().takeRecords();
    ASSERT_EQ(records.size(), 1u);
    const auto scale = test::expectPartsConserveTheWhole(records[0].before, records[0].parts);
    EXPECT_NEAR(records[0].parts.back().mass, body.physicalMesh().mass.mass, 1e-12 * mesh.mass.mass);
    test::BulletMomenta after;
    for (const VisualBody* f : fragments) after.add(f->rigidBody());
    EXPECT_NEAR(after.mass, before.mass, 1e-6 * before.mass);
    EXPECT_LT((after.linear - before.linear).norm(), 1e-6 * scale.linear);
    EXPECT_LT((after.angular - before.angular).norm(), 1e-6 * scale.angular);
    int crack = 0;
    for (size_t f = 0; f < body.physicalMesh().visual.faces.size(); ++f) crack += body.physicalMesh().visual.isCrackFace(f);
    EXPECT_GT(crack, 0) << "the rest shows the crack faces around the hole";
    EXPECT_EQ(body.visualMesh().faces.size(), body.physicalMesh().visual.faces.size());
}

TEST(FractureSystem, TheRestsVerticesNoPrimitiveCarriesStayWhereTheBreakFoundThem) {
    // A sheet broken in place: its visual vertices that no primitive of the rest carries any
    // more (their primitives went to fragments) are shown where the body held them at the
    // break, its mesh transform times their rest position, bit for bit (keepRemainder places
    // only those; the weld places the carried ones). Once with the body welded where it was
    // before it moved (stale positions there), once never welded.
    for (const bool weldedBefore : {true, false}) {
        test::TestWorld w;
        w.world.setGravity(btVector3(0, 0, 0));
        Plugin plugin(w.world);
        const auto mesh = quadSheet(12);
        BodySettings s = breakable();
        s.fracture.radius = 0.12;
        s.fracture.setCells(16);
        VisualBody& body = plugin.addVisualBody(mesh, s, at(0.1, 0.5, 0.2));
        body.rigidBody().setLinearVelocity(btVector3(0.3f, 0.2f, -1.0f));
        body.rigidBody().setAngularVelocity(btVector3(1.0f, -2.0f, 0.5f));
        if (weldedBefore) (void)body.visualMesh();
        w.step(2);
        const Eigen::Isometry3d toWorld = toEigen(body.meshTransform());
        const btVector3 centre = body.meshTransform() * btVector3(0.3f, 0.3f, 0.0f);
        const auto pieces = plugin.fracture(body, centre, body.meshTransform().getBasis() * btVector3(0, 0, -1));
        ASSERT_GE(pieces.size(), 2u);
        ASSERT_EQ(pieces.back(), &body) << "the rest is the body itself";
        const geometry::PhysicalMesh& rest = body.physicalMesh();
        std::vector<char> carried(rest.visual.positions.size(), 0);
        for (const auto& p : rest.primitives)
            for (const int id : p.globalIds())
                if (id >= 0 && size_t(id) < carried.size()) carried[size_t(id)] = 1;
        const std::vector<Eigen::Vector3d>& shown = body.visualMesh().positions;
        ASSERT_EQ(shown.size(), rest.visual.positions.size());
        int uncarried = 0;
        for (size_t id = 0; id < carried.size(); ++id) {
            if (carried[id]) continue;
            ++uncarried;
            EXPECT_EQ(shown[id], toWorld * rest.visual.positions[id]) << "vertex " << id << (weldedBefore ? ", welded before" : "");
        }
        EXPECT_GT(uncarried, 0) << "the break leaves some vertices to no primitive of the rest";
    }
}

TEST(FractureSystem, EveryBodyOfAClosedShellBrokenTwiceMovesItsWholeVisualMesh) {
    // A closed square ring shell (4 m, 1 m quads extruded 10 cm) is broken, and the rest of
    // it (a new body: a closed surface shows its inner side on every fragment) is broken again
    // at once; then everything falls and spins for a quarter of a second. Every body's visual
    // mesh must move rigidly with it: each face edge as long as in the body's rest shape
    // (welded the same way, the mean of the primitives' copies of an id), to 1e-5 m (the
    // world mesh is welded through Bullet's single-precision transform, about 1e-7 relative on
    // coordinates of a few metres), and each face corner inside the bounding box of its primitives. A face
    // left on ids that no primitive carries stays where the break left it: the streaks of
    // shatter-vase --mesh spot.obj.
    test::TestWorld w;
    Plugin plugin(w.world);
    BodySettings s = breakable();
    s.fracture.radius = 0.8;
    s.fracture.setCells(16);
    s.fracture.coolDown = 0.0;
    s.fracture.seed = 3;
    plugin.addVisualBody(test::ringShellBody(0.1), s, at(0, 2, 0));
    auto largest = [&] {
        VisualBody* big = nullptr;
        for (const auto& b : plugin.bodies())
            if (!big || b->physicalMesh().primitives.size() > big->physicalMesh().primitives.size()) big = b.get();
        return big;
    };
    auto breakAt = [&](const btVector3& point, const btVector3& direction) {
        VisualBody& body = *largest();
        const btTransform t = body.meshTransform();
        EXPECT_GE(plugin.fracture(body, t * point, t.getBasis() * direction).size(), 2u);
    };
    breakAt(btVector3(2.0f, 0.0f, 0.5f), btVector3(0, 1, 0));
    breakAt(btVector3(0.0f, 2.0f, 0.5f), btVector3(1, 0, 0));
    for (const auto& b : plugin.bodies()) b->rigidBody().setAngularVelocity(btVector3(1.0f, 3.0f, -2.0f));
    w.step(60);

    for (const auto& b : plugin.bodies()) {
        const geometry::PhysicalMesh& mesh = b->physicalMesh();
        std::vector<Eigen::Vector3d> rest(mesh.visual.positions.size(), Eigen::Vector3d::Zero());
        std::vector<int> copies(rest.size(), 0);
        for (const auto& p : mesh.primitives)
            for (size_t v = 0; v < p.vertices().size(); ++v)
                if (const int id = p.globalIds()[v]; id < int(rest.size())) {
                    rest[size_t(id)] += p.vertices()[v];
                    ++copies[size_t(id)];
                }
        geometry::Aabb bounds; // of the primitives at rest, in mesh coordinates
        for (const auto& p : mesh.primitives) bounds.extend(p.bounds());
        bounds = bounds.inflated(1e-5);
        const Eigen::Isometry3d toMesh = toEigen(b->meshTransform()).inverse();
        const geometry::VisualMesh& world = b->visualMesh();
        int uncarried = 0, stretched = 0, outside = 0;
        for (const auto& face : world.faces)
            for (size_t k = 0; k < face.size(); ++k) {
                const int a = face[k], c = face[(k + 1) % face.size()];
                if (copies[size_t(a)] == 0 || copies[size_t(c)] == 0) {
                    ++uncarried;
                    continue;
                }
                const double restLength = (rest[size_t(a)] / copies[size_t(a)] - rest[size_t(c)] / copies[size_t(c)]).norm();
                stretched += std::abs((world.positions[size_t(a)] - world.positions[size_t(c)]).norm() - restLength) > 1e-5;
                const Eigen::Vector3d p = toMesh * world.positions[size_t(a)];
                outside += (p.array() < bounds.min.array()).any() || (p.array() > bounds.max.array()).any();
            }
        EXPECT_EQ(uncarried, 0) << b->name() << ": face edges on ids no primitive carries";
        EXPECT_EQ(stretched, 0) << b->name() << ": face edges longer or shorter than at rest";
        EXPECT_EQ(outside, 0) << b->name() << ": face corners outside the body's bounds";
    }
}

// Kinetic plus potential energy (gravity along -y) of every Shatter body.
double energy(const Plugin& plugin) {
    double e = 0;
    for (const auto& b : plugin.bodies()) {
        const btRigidBody& r = b->rigidBody();
        e += test::kineticEnergy(r);
        if (r.getInvMass() > 0) e += 9.81 / double(r.getInvMass()) * double(r.getCenterOfMassPosition().y());
    }
    return e;
}

TEST(FractureSystem, PiecesMadeTouchingAtRestGainNoEnergy) {
    // A 4×4×2 block of 5 cm cubes (4 high) settles on the ground and is split into its 32
    // cubes, each touching its neighbours face to face with Bullet's margins (1 mm each)
    // overlapping. Bullet's hull-hull clipping measures the depth between the hulls
    // themselves (zero here), so neighbours do not push each other; the new contacts start
    // without warm-starting and the cubes settle into their margins by a few millimetres.
    // Measured: kinetic plus potential energy never rises above the settled block's (the
    // sinking turns potential into a little kinetic energy, at most 7e-5 J per cube), while
    // moving the crack faces in by the margin (so the margins touched exactly) opened 2 mm gaps
    // between the layers, and ignoring the sibling pairs let the layers sink into each other.
    test::TestWorld w;
    w.addGround();
    Plugin plugin(w.world);
    const auto mesh = cubeBlock("block", 4, 4, 2, 0.05);
    VisualBody& body = plugin.addVisualBody(mesh, breakable(), at(0, 0.0005, 0));
    w.step(240);
    const double settled = energy(plugin);
    std::vector<int> group(32);
    for (int p = 0; p < 32; ++p) group[p] = p;
    const auto fragments = plugin.fractures().replace(body, partition(mesh, group), -1);
    EXPECT_NEAR(energy(plugin), settled, 1e-6 * std::abs(settled));
    std::vector<btVector3> start;
    for (const VisualBody* f : fragments) start.push_back(f->rigidBody().getCenterOfMassPosition());
    double gain = -1e9, kinetic = 0;
    for (int i = 0; i < 480; ++i) {
        w.step(1);
        gain = std::max(gain, energy(plugin) - settled);
        kinetic = 0;
        for (const VisualBody* f : fragments) kinetic += test::kineticEnergy(f->rigidBody());
    }
    double drift = 0;
    for (size_t k = 0; k < fragments.size(); ++k)
        drift = std::max(drift, double((fragments[k]->rigidBody().getCenterOfMassPosition() - start[k]).length()));
    // The energy is a sum of float positions times 4 kg g: rounding is below 1e-6 J.
    EXPECT_LT(gain, 1e-6);
    // At rest again after 2 s, up to the jitter of a stack in Bullet (4 kg: 5e-5 J is 5 mm/s).
    EXPECT_LT(kinetic, 5e-5);
    EXPECT_LT(drift, 0.006) << "settling into the margins: 1 mm per layer, 4 layers, and a little sliding";
}

// The closed ring shell's settings for the hull-fragment tests: 24 cells over the whole ring,
// fragments whose hull is clear collide as that hull (hullBelow larger than any fragment).
BodySettings ringShellHullSettings() {
    BodySettings s = breakable();
    s.fracture.radius = 3.0;
    s.fracture.setCells(24);
    s.fracture.seed = 5;
    s.fracture.hullBelow = 100.0;
    return s;
}

// The ring shell (10 cm walls) added at rest and broken where it is, on its outer side.
std::vector<VisualBody*> breakRingShellWhereItFloats(Plugin& plugin, const BodySettings& s) {
    VisualBody& ring = plugin.addVisualBody(test::ringShellBody(0.1), s, at(0, 2, 0));
    const btTransform t = ring.meshTransform();
    return plugin.fracture(ring, t * btVector3(2.0f, 0.0f, 0.5f), t.getBasis() * btVector3(0, 1, 0));
}

TEST(FractureSystem, FragmentsThatCollideAsTheirHullDoNotPushEachOtherApart) {
    // The closed ring shell (10 cm walls, so a cell often holds a piece of both the outer and
    // the inner wall: two fragments whose hulls may overlap) floats at rest without gravity
    // and is broken where it is; fragments whose hull is clear collide as that hull
    // (hullBelow larger than any fragment). Nothing may push the pieces apart: for a second,
    // no body's kinetic energy rises above what the group shapes' own touching pairs give
    // (up to 9e-7 J with no hull at all: float rounding of the bodies' frames). Measured:
    // 5.6e-7 J. Hulls not shrunk (FractureSystem::makeFragment) gave 6e-3 J: Bullet's
    // contacts between a hull and a group's primitive touching along a crack face.
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    BodySettings s = ringShellHullSettings();
    const auto fragments = breakRingShellWhereItFloats(plugin, s);
    int hulls = 0, groups = 0;
    for (const VisualBody* f : fragments) {
        const bool hull = isFragmentHull(f->rigidBody().getCollisionShape());
        if (hull && f->physicalMesh().primitives.size() > 1) ++hulls;
        if (!hull) ++groups;
    }
    EXPECT_GE(hulls, 3) << "fragments of several primitives collide as one hull";
    EXPECT_GE(groups, 2) << "fragments whose hulls could overlap, and the rest, stay group shapes";
    double kinetic = 0.0;
    for (int i = 0; i < 240; ++i) {
        w.step(1);
        for (const VisualBody* f : fragments) kinetic = std::max(kinetic, test::kineticEnergy(f->rigidBody()));
    }
    EXPECT_LT(kinetic, 2e-6);
}

// Whether two of `bodies` have a manifold with contact points in the world.
bool siblingsTouch(btDiscreteDynamicsWorld& world, const std::vector<VisualBody*>& bodies) {
    std::set<const btCollisionObject*> objects;
    for (const VisualBody* b : bodies) objects.insert(&b->rigidBody());
    btDispatcher& d = *world.getDispatcher();
    for (int m = 0; m < d.getNumManifolds(); ++m) {
        const btPersistentManifold& pm = *d.getManifoldByIndexInternal(m);
        if (pm.getNumContacts() > 0 && objects.count(pm.getBody0()) && objects.count(pm.getBody1())) return true;
    }
    return false;
}

TEST(FractureSystem, ThePiecesOfABreakMeetAgainAfterTheirContactDelay) {
    // The ring shell, floating at rest without gravity, is broken where it is with a contact
    // delay of 3 steps: in the 3 steps' collision detection no two of its pieces collide
    // (Bullet's ignore lists hold exactly the other pieces, and no manifold between two pieces
    // has a point), from the 4th they do again (the pieces touch along their crack faces: some
    // pair has points) and the ignore lists are empty. Nothing moves them meanwhile: no body's
    // kinetic energy rises above the 2e-6 J of the test without a delay
    // (FragmentsThatCollideAsTheirHullDoNotPushEachOtherApart).
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    BodySettings s = ringShellHullSettings();
    s.fracture.contactDelaySteps = 3;
    const auto pieces = breakRingShellWhereItFloats(plugin, s);
    ASSERT_GE(pieces.size(), 5u);
    const auto ignoresExactlyTheOthers = [&] {
        for (VisualBody* a : pieces) {
            btRigidBody& r = a->rigidBody();
            if (r.getNumObjectsWithoutCollision() != int(pieces.size()) - 1) return false;
            for (const VisualBody* b : pieces)
                if (a != b && r.checkCollideWith(&b->rigidBody())) return false;
        }
        return true;
    };
    double kinetic = 0.0;
    for (int step = 1; step <= 3; ++step) {
        EXPECT_TRUE(ignoresExactlyTheOthers()) << "before step " << step;
        w.step(1);
        EXPECT_FALSE(siblingsTouch(w.world, pieces)) << "step " << step;
        for (const VisualBody* f : pieces) kinetic = std::max(kinetic, test::kineticEnergy(f->rigidBody()));
    }
    for (const VisualBody* a : pieces) {
        EXPECT_EQ(a->rigidBody().getNumObjectsWithoutCollision(), 0) << a->name();
        for (const VisualBody* b : pieces) EXPECT_TRUE(a->rigidBody().checkCollideWith(&b->rigidBody()));
    }
    w.step(1);
    EXPECT_TRUE(siblingsTouch(w.world, pieces)) << "the pieces touch along their crack faces";
    for (int i = 0; i < 236; ++i) {
        w.step(1);
        for (const VisualBody* f : pieces) kinetic = std::max(kinetic, test::kineticEnergy(f->rigidBody()));
    }
    EXPECT_LT(kinetic, 2e-6);
}

TEST(FractureSystem, APieceThatLeavesDuringTheContactDelayIsForgottenByTheOthers) {
    // A body that leaves the world while its siblings still ignore it must leave no address in
    // their ignore lists (a new body could be given it).
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    BodySettings s = ringShellHullSettings();
    s.fracture.contactDelaySteps = 10;
    const auto pieces = breakRingShellWhereItFloats(plugin, s);
    ASSERT_GE(pieces.size(), 3u);
    const btCollisionObject* gone = &pieces[0]->rigidBody();
    plugin.removeBody(*pieces[0]);
    for (size_t k = 1; k < pieces.size(); ++k) {
        btRigidBody& r = pieces[k]->rigidBody();
        EXPECT_EQ(r.getNumObjectsWithoutCollision(), int(pieces.size()) - 2);
        for (int i = 0; i < r.getNumObjectsWithoutCollision(); ++i) EXPECT_NE(r.getObjectWithoutCollision(i), gone);
    }
    w.step(10);
    for (size_t k = 1; k < pieces.size(); ++k) EXPECT_EQ(pieces[k]->rigidBody().getNumObjectsWithoutCollision(), 0);
}

TEST(FractureSystem, AHullFragmentsGroupShapeIsTheShapeOfAFreshBodyAndItBreaksAgain) {
    // A fragment that collides as its hull builds its group shape only when asked (VisualBody):
    // the shape it then builds is, bit for bit, the one a new body of its mesh has, the
    // fragment still collides as its hull, and it can break again (the group shape edited as
    // the rest of that break), the second break conserving mass and momenta.
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    BodySettings s = ringShellHullSettings();
    s.fracture.depth = 2;
    s.fracture.coolDown = 0.0;
    const auto fragments = breakRingShellWhereItFloats(plugin, s);
    VisualBody* shard = nullptr;
    for (VisualBody* f : fragments)
        if (isFragmentHull(f->rigidBody().getCollisionShape()) &&
            (!shard || f->physicalMesh().primitives.size() > shard->physicalMesh().primitives.size()))
            shard = f;
    ASSERT_NE(shard, nullptr);
    ASSERT_GE(shard->physicalMesh().primitives.size(), 4u);
    const btCollisionShape* hull = shard->rigidBody().getCollisionShape();
    BodySettings plain;
    VisualBody& fresh = plugin.addVisualBody(shard->physicalMesh(), plain, shard->meshTransform());
    ASSERT_EQ(shard->shapePrimitives().size(), fresh.shape().primitives().size());
    for (size_t i = 0; i < fresh.shape().primitives().size(); ++i) {
        const auto& corners = shard->shapePrimitives()[i].vertices();
        EXPECT_EQ(corners, fresh.shape().primitives()[i].vertices());
        const auto& rest = shard->physicalMesh().primitives[i].vertices(); // body frame = meshToBody · rest
        for (size_t v = 0; v < rest.size(); ++v) EXPECT_LT((corners[v] - shard->meshToBody() * rest[v]).norm(), 1e-12);
    }
    test::expectSameShape(shard->shape(), fresh.shape());
    EXPECT_EQ(shard->rigidBody().getCollisionShape(), hull) << "asking for the group shape changes no collision";
    plugin.removeBody(fresh);
    plugin.fractures().takeRecords();
    shard->rigidBody().setLinearVelocity(btVector3(0.5f, -1.0f, 2.0f)); // momenta for the break to share
    shard->rigidBody().setAngularVelocity(btVector3(3.0f, -1.0f, 2.0f));
    const btTransform u = shard->meshTransform();
    const Eigen::Vector3d centre = shard->physicalMesh().mass.centerOfMass;
    const auto again = plugin.fracture(*shard, u * toBullet(centre), u.getBasis() * btVector3(0, 1, 0));
    ASSERT_GE(again.size(), 2u) << "the shard breaks again";
    const auto records = plugin.fractures().takeRecords();
    ASSERT_EQ(records.size(), 1u);
    test::expectPartsConserveTheWhole(records[0].before, records[0].parts);
    // And the world steps with its pieces. No gravity and no ground: the bodies' total momentum
    // stays (measured: to 3e-7 of it, float sums), and their contacts (restitution 0) add no
    // kinetic energy (measured: 9,242 J before, 7,964 J after).
    const auto motion = [&w](double& kinetic) {
        btVector3 momentum(0, 0, 0);
        kinetic = 0;
        const auto& bodies = w.world.getNonStaticRigidBodies();
        for (int i = 0; i < bodies.size(); ++i) {
            EXPECT_TRUE(std::isfinite(bodies[i]->getCenterOfMassPosition().length2()));
            momentum += bodies[i]->getLinearVelocity() / bodies[i]->getInvMass();
            kinetic += test::kineticEnergy(*bodies[i]);
        }
        return momentum;
    };
    double kineticBefore = 0, kineticAfter = 0;
    const btVector3 before = motion(kineticBefore);
    w.step(10);
    const btVector3 after = motion(kineticAfter);
    EXPECT_LT((after - before).length(), 1e-5 * before.length());
    EXPECT_LE(kineticAfter, kineticBefore);
}

TEST(FractureSystem, FragmentsTouchingAJointBoxTakeOverTheJoint) {
    // A 4×4 pane of 5 cm cubes hangs on a static frame by a hinge box against its left edge,
    // over the lower two cubes of the first column (y from 2 to 8 cm). Split into the first
    // column's three lower cubes one by one and the rest: exactly the two cubes the box
    // touches get a copy of the hinge to the frame; the old joint goes with the pane.
    test::TestWorld w;
    Plugin plugin(w.world);
    geometry::PhysicalObject object;
    object.bodies.push_back(cubeBlock("pane", 4, 4, 1, 0.05));
    object.bodies.push_back(cubeBlock("frame", 1, 4, 1, 0.05, Eigen::Vector3d(-0.06, 0, 0)));
    geometry::JointBox hinge;
    hinge.name = "joint.hinge.pane.frame";
    hinge.type = geometry::JointType::Hinge;
    hinge.bodyA = "pane";
    hinge.bodyB = "frame";
    hinge.pose.linear() << 0, 1, 0, 1, 0, 0, 0, 0, -1; // axis 0 (the hinge) along y
    hinge.pose.translation() = Eigen::Vector3d(-0.005, 0.05, 0.025);
    hinge.halfExtents = Eigen::Vector3d(0.03, 0.025, 0.005);
    object.joints.push_back(hinge);
    BodySettings frame;
    frame.dynamic = false;
    const auto added = plugin.addObject(object, breakable(), at(0, 1, 0), {{"frame", frame}});
    const int oldJoint = added.joints[0]->id();
    plugin.takeEvents();
    std::vector<int> group(16, 3);
    group[0] = 0;  // (0, 0): touches the box
    group[4] = 1;  // (0, 1): touches the box
    group[8] = 2;  // (0, 2): above it (y from 10 cm)
    const auto fragments = plugin.fractures().replace(*added.bodies[0], partition(object.bodies[0], group), -1);
    ASSERT_EQ(plugin.joints().size(), 2u);
    std::set<const VisualBody*> held;
    for (const auto& joint : plugin.joints()) {
        EXPECT_EQ(&joint->bodyB(), added.bodies[1]);
        EXPECT_EQ(joint->box().type, geometry::JointType::Hinge);
        EXPECT_TRUE(joint->box().pose.isApprox(hinge.pose));
        held.insert(&joint->bodyA());
    }
    EXPECT_EQ(held, (std::set<const VisualBody*>{fragments[0], fragments[1]}));
    int recreated = 0, fractured = 0;
    for (const Event& e : plugin.takeEvents()) {
        if (e.type == EventType::JointRecreated) {
            ++recreated;
            EXPECT_EQ(e.count, oldJoint);
            EXPECT_TRUE(e.body == fragments[0]->id() || e.body == fragments[1]->id());
        }
        if (e.type == EventType::BodyFractured) {
            ++fractured;
            ASSERT_EQ(e.fragments.size(), 4u);
            for (size_t k = 0; k < 4; ++k) EXPECT_EQ(e.fragments[k], fragments[k]->id());
            EXPECT_EQ(e.name, "pane");
        }
    }
    EXPECT_EQ(recreated, 2);
    EXPECT_EQ(fractured, 1);
    // The held cubes hang on the hinge (gravity along its axis; Bullet's hinge gives a few
    // millimetres under their weight); the free ones fall 30 cm in 0.5 s.
    std::vector<btVector3> start;
    for (const VisualBody* f : fragments) start.push_back(f->rigidBody().getCenterOfMassPosition());
    w.step(120);
    for (int k : {0, 1}) EXPECT_LT((fragments[k]->rigidBody().getCenterOfMassPosition() - start[k]).length(), 0.01f);
    for (int k : {2, 3}) EXPECT_GT(start[k].y() - fragments[k]->rigidBody().getCenterOfMassPosition().y(), 0.1f);
}

TEST(FractureSystem, DepthAndCoolDownDecideWhenFragmentsMayBreakAgain) {
    for (const int depth : {0, 1}) {
        test::TestWorld w;
        w.world.setGravity(btVector3(0, 0, 0));
        Plugin plugin(w.world);
        BodySettings s = breakable();
        s.fracture.depth = depth;
        s.fracture.coolDown = 0.05;
        const auto mesh = cubeBlock("bar", 2, 1, 1, 0.05);
        VisualBody& body = plugin.addVisualBody(mesh, s, at(0, 0, 0));
        EXPECT_TRUE(plugin.fractures().breakable(body));
        const auto fragments = plugin.fractures().replace(body, partition(mesh, {0, 1}), -1);
        EXPECT_FALSE(plugin.fractures().breakable(*fragments[0])) << "cooling down (depth " << depth << ")";
        w.step(13); // 54 ms
        EXPECT_EQ(plugin.fractures().breakable(*fragments[0]), depth > 0) << "depth " << depth;
    }
}

TEST(FractureSystem, BadSettingsAreRejectedNamingTheBodyAndField) {
    test::TestWorld w;
    Plugin plugin(w.world);
    const auto mesh = cubeBlock("vase", 1, 1, 1, 0.05);
    auto rejects = [&](auto change, const std::string& field) {
        BodySettings s = breakable();
        change(s.fracture);
        try {
            plugin.addVisualBody(mesh, s, at(0, 0, 0));
            ADD_FAILURE() << field << " was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("body 'vase': " + field), std::string::npos) << e.what();
        }
    };
    const double nan = std::nan("");
    rejects([](FractureSettings& f) { f.voronoi.cells = 0; }, "Voronoi pattern cells must be >= 1");
    rejects([](FractureSettings& f) {
        f.pattern = PatternKind::Glass;
        f.glass.sectors = 2;
    }, "glass pattern sectors must be >= 3");
    rejects([](FractureSettings& f) { f.threshold = 0; }, "fracture threshold must be positive");
    rejects([&](FractureSettings& f) { f.threshold = nan; }, "fracture threshold must be positive");
    rejects([](FractureSettings& f) { f.radius = -1; }, "fracture radius must be positive");
    rejects([](FractureSettings& f) { f.minimumPieceSize = 0; }, "fracture minimum piece size must be positive");
    rejects([](FractureSettings& f) { f.depth = -1; }, "fracture depth must be >= 0");
    rejects([](FractureSettings& f) { f.coolDown = -0.1; }, "fracture cool-down must be >= 0");
    rejects([](FractureSettings& f) { f.hullBelow = -0.01; }, "fracture hull size must be >= 0");
    rejects([&](FractureSettings& f) { f.hullBelow = nan; }, "fracture hull size must be >= 0");
    rejects([](FractureSettings& f) { f.contactDelaySteps = -1; }, "fracture contact delay (steps) must be >= 0");
    rejects([](FractureSettings& f) { f.eventSpacingSteps = -1; }, "fracture event spacing (steps) must be >= 0");
    rejects([](FractureSettings& f) { f.pattern = PatternKind::File; }, "fracture pattern file is empty");
    BodySettings plastic = breakable();
    plastic.deformation = Deformation::Plastic;
    EXPECT_THROW(plugin.addVisualBody(mesh, plastic, at(0, 0, 0)), InputError);
    EXPECT_THROW(patternKindNamed("voronoy"), InputError);
    EXPECT_TRUE(plugin.bodies().empty());
    BodySettings off; // fracture off: nothing is checked
    off.fracture.voronoi.cells = 0;
    EXPECT_NO_THROW(plugin.addVisualBody(mesh, off, at(0, 0, 0)));
}

// A 20 cm block of 4 cm cubes falling 30 cm onto the ground, breakable above `threshold`.
struct FallingBlock {
    test::TestWorld w;
    Plugin plugin{w.world};
    VisualBody* body = nullptr;
    explicit FallingBlock(double threshold, std::uint64_t seed = 1, int contactDelaySteps = 0) {
        w.addGround();
        BodySettings s = breakable();
        s.fracture.threshold = threshold;
        s.fracture.contactDelaySteps = contactDelaySteps;
        s.fracture.radius = 0.12;
        s.fracture.setCells(24);
        s.fracture.seed = seed;
        body = &plugin.addVisualBody(cubeBlock("block", 5, 5, 5, 0.04), s, at(-0.1, 0.3, -0.1));
    }
    int breaks() {
        int n = 0;
        for (const Event& e : plugin.takeEvents()) n += e.type == EventType::BodyFractured;
        return n;
    }
};

TEST(FractureSystem, BreaksWhereAContactStrikesAboveTheThreshold) {
    // 8 kg landing at 2.4 m/s (after 60 steps): the floor's impulse in the landing step is
    // about 20 N·s.
    FallingBlock soft(1000.0);
    soft.w.step(80);
    EXPECT_EQ(soft.breaks(), 0) << "below the threshold the block lands whole";
    FallingBlock hard(5.0);
    hard.w.step(80);
    EXPECT_GE(hard.breaks(), 1);
    EXPECT_GT(hard.plugin.bodies().size(), 3u);
    double lowest = 1e9;
    for (const auto& b : hard.plugin.bodies()) lowest = std::min(lowest, double(b->rigidBody().getCenterOfMassPosition().y()));
    EXPECT_LT(lowest, 0.05) << "the pieces reached the ground";
}

TEST(FractureSystem, TheSameBreakGivesTheSamePieces) {
    // Scripted: the same body, settings, point and direction twice give bit-identical pieces;
    // another seed gives others.
    auto pieces = [](std::uint64_t seed) {
        FallingBlock b(5.0, seed);
        const auto fragments = b.plugin.fracture(*b.body, btVector3(0, 0.4f, 0), btVector3(0, -1, 0));
        std::vector<double> out;
        for (const VisualBody* f : fragments) {
            out.push_back(f->physicalMesh().mass.volume);
            for (const auto& p : f->physicalMesh().primitives)
                for (const auto& v : p.vertices()) out.insert(out.end(), {v.x(), v.y(), v.z()});
        }
        return out;
    };
    const auto a = pieces(1), b = pieces(1), c = pieces(2);
    ASSERT_GT(a.size(), 10u);
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
}

// An open 16 x 16 sheet that breaks with its rest edited in place, again and again.
VisualBody& addSheetBrokenInPlace(Plugin& plugin) {
    BodySettings s = breakable();
    s.fracture.radius = 0.15;
    s.fracture.setCells(16);
    s.fracture.depth = 8;
    s.fracture.coolDown = 0;
    return plugin.addVisualBody(test::sheetBody(16, 16, 0.05, 0.01), s, at(0.0, 1.0, 0.0));
}

TEST(FractureSystem, TheRestKeepsAnIndexThatGivesItsNextBreakBitForBit) {
    // An open sheet's rest is edited in place, break after break; its fracture index (the group
    // shape's tree, edited with it, not built again, and its surface index, patched) must still
    // hold every primitive and be the surface's: a cut of the rest with it is the cut without
    // it, bit for bit.
    test::TestWorld w;
    Plugin plugin{w.world};
    VisualBody& body = addSheetBrokenInPlace(plugin);
    const geometry::AabbTree* const tree = body.fractureIndex().tree;
    ASSERT_NE(tree, nullptr);
    // Its surface index too: built when the body became breakable, patched by each break.
    const fracture::SurfaceIndex* const surface = body.fractureIndex().surface;
    ASSERT_NE(surface, nullptr);
    fracture::VoronoiPatternSettings pattern;
    pattern.cells = 32;
    pattern.radius = 0.2;
    fracture::CutSettings cut;
    cut.remainderInPlace = true;
    int edits = 0;
    for (const btVector3 hit : {btVector3(0.3f, 1.3f, 0.0f), btVector3(0.5f, 1.5f, 0.0f), btVector3(0.2f, 1.6f, 0.0f)}) {
        const size_t before = body.physicalMesh().primitives.size();
        ASSERT_FALSE(plugin.fracture(body, hit, btVector3(0, 0, -1)).empty());
        const geometry::PhysicalMesh& rest = body.physicalMesh();
        if (rest.primitives.size() != before) ++edits;
        const fracture::PrimitiveIndex index = body.fractureIndex();
        EXPECT_EQ(index.tree, tree); // the same tree, edited
        ASSERT_EQ(index.tree->itemCount(), int(rest.primitives.size()));
        EXPECT_EQ(index.surface, surface); // the same index, patched
        EXPECT_TRUE(*index.surface == fracture::SurfaceIndex(rest));
        for (const Eigen::Vector3d& point : {Eigen::Vector3d(0.35, 0.3, 0.0), Eigen::Vector3d(0.6, 0.6, 0.0)}) {
            const fracture::Placement where{.point = point, .normal = {0.1, 0.2, -1.0}};
            const auto plain = fracture::fractureMesh(rest, fracture::voronoiPattern(pattern, 3), where, cut);
            const auto indexed = fracture::fractureMesh(rest, fracture::voronoiPattern(pattern, 3), where, cut, index);
            ASSERT_GT(plain.primitivesCut, 0);
            test::expectSameResult(plain, indexed);
        }
    }
    EXPECT_GE(edits, 2); // the rest really changed between the cuts
}

// The faces and crack marks a body shows, and whether they are its mesh's.
struct ShownFaces {
    std::vector<std::vector<int>> faces;
    std::vector<bool> crack;
    std::vector<Eigen::Vector3d> carried; // the positions of the vertices its primitives carry
};
ShownFaces shownFaces(VisualBody& body) {
    const geometry::VisualMesh& shown = body.visualMesh();
    EXPECT_EQ(shown.faces, body.physicalMesh().visual.faces) << body.name();
    EXPECT_EQ(shown.crackFace, body.physicalMesh().visual.crackFace) << body.name();
    std::vector<char> isCarried(shown.positions.size(), 0);
    for (const auto& p : body.physicalMesh().primitives)
        for (const int id : p.globalIds())
            if (id >= 0 && size_t(id) < isCarried.size()) isCarried[size_t(id)] = 1;
    ShownFaces out{shown.faces, shown.crackFace, {}};
    for (size_t id = 0; id < isCarried.size(); ++id)
        if (isCarried[id]) out.carried.push_back(shown.positions[id]);
    return out;
}

TEST(FractureSystem, AFragmentBrokenBeforeItIsShownShowsTheFacesOfOneShownBefore) {
    // A new body copies its mesh's faces into its world mesh and builds its vertex welder at
    // its first visualMesh(), not when it is made (VisualBody::settleWorldFaces, settleWelder);
    // a fragment broken again before that has only its mesh's faces edited, and its welder is
    // built at the break. Once shown, its faces, crack marks and welded vertices are those of
    // the same fragment shown before its break (whose world faces the break edited in place,
    // and whose welder followed the edit), and every body of the break shows its mesh's faces.
    ShownFaces rest[2];
    for (const bool shownBefore : {false, true}) {
        test::TestWorld w;
        Plugin plugin{w.world};
        VisualBody& sheet = addSheetBrokenInPlace(plugin);
        const auto pieces = plugin.fracture(sheet, btVector3(0.3f, 1.3f, 0.0f), btVector3(0, 0, -1));
        VisualBody* largest = nullptr;
        for (VisualBody* p : pieces)
            if (p != &sheet && (!largest || p->physicalMesh().primitives.size() > largest->physicalMesh().primitives.size()))
                largest = p;
        ASSERT_NE(largest, nullptr);
        if (shownBefore) (void)shownFaces(*largest);
        // Hit beside it: the cells reach part of it, and the part beyond stays as the fragment.
        const btTransform u = largest->meshTransform();
        const btVector3 centre = u * toBullet(largest->physicalMesh().mass.centerOfMass);
        const auto again = plugin.fracture(*largest, centre + btVector3(0.14f, 0.0f, 0.0f), btVector3(0, 0, -1));
        ASSERT_GE(again.size(), 2u);
        ASSERT_EQ(again.back(), largest) << "the fragment stays as the rest of its break";
        for (VisualBody* body : again) (void)shownFaces(*body);
        rest[shownBefore] = shownFaces(*largest);
    }
    EXPECT_EQ(rest[0].faces, rest[1].faces);
    EXPECT_EQ(rest[0].crack, rest[1].crack);
    EXPECT_EQ(rest[0].carried, rest[1].carried);
    EXPECT_GT(std::count(rest[0].crack.begin(), rest[0].crack.end(), true), 0) << "the break showed crack faces";
}

TEST(FractureSystem, ARigidFragmentsMeshPlacedByItsTransformIsItsVisualMesh) {
    // The README's cheap way to draw rigid bodies: upload physicalMesh().visual once (mesh
    // coordinates, crack faces marked) and place it by meshTransform() each frame, with no
    // visualMesh() (which welds in world coordinates, and for a new fragment makes its welder
    // and world faces first). Both must show the same surface, here after the pieces fell for
    // a while. Tolerance 1 µm (far below a pixel): meshTransform() is Bullet's single
    // precision, where visualMesh() composes the body's transform with its mesh offset in
    // double; float rounding of a metre-sized placement is ~1e-7 m (seen: 3e-8 m).
    test::TestWorld w;
    Plugin plugin{w.world};
    VisualBody& sheet = addSheetBrokenInPlace(plugin);
    const auto pieces = plugin.fracture(sheet, btVector3(0.3f, 1.3f, 0.0f), btVector3(0, 0, -1));
    ASSERT_GE(pieces.size(), 3u);
    w.step(60);
    int drawn = 0;
    for (VisualBody* body : pieces) {
        const geometry::VisualMesh& rest = body->physicalMesh().visual;
        const Eigen::Isometry3d place = toEigen(body->meshTransform());
        const geometry::VisualMesh& shown = body->visualMesh();
        ASSERT_EQ(shown.faces, rest.faces) << body->name();
        ASSERT_EQ(shown.crackFace, rest.crackFace) << body->name();
        for (const auto& face : rest.faces)
            for (const int id : face) {
                ASSERT_LT(size_t(id), rest.positions.size()) << body->name();
                EXPECT_LT((place * rest.positions[size_t(id)] - shown.positions[size_t(id)]).norm(), 1e-6) << body->name();
            }
        drawn += int(!rest.faces.empty());
    }
    EXPECT_EQ(drawn, int(pieces.size())) << "every piece has a surface to draw";
}

TEST(FractureSystem, TheRestsSleepingRadiusFromItsTreeIsTheRadiusOfEveryPrimitiveBox) {
    // A moving rest's sleeping radius (the farthest primitive box corner from its centre of
    // mass) is found with its primitive tree, leaving out subtrees that cannot hold a farther
    // corner: the same radius, bit for bit, as from every primitive's box.
    test::TestWorld w;
    Plugin plugin{w.world};
    VisualBody& body = addSheetBrokenInPlace(plugin);
    ASSERT_GT(body.rigidBody().getInvMass(), 0); // the rest moves: its radius is set
    for (const btVector3 hit : {btVector3(0.3f, 1.3f, 0.0f), btVector3(0.5f, 1.5f, 0.0f), btVector3(0.2f, 1.6f, 0.0f)}) {
        const btScalar before = body.rigidBody().getAngularSleepingThreshold();
        ASSERT_FALSE(plugin.fracture(body, hit, btVector3(0, 0, -1)).empty());
        ASSERT_NE(body.fractureIndex().tree, nullptr); // the tree was there to walk,
        const geometry::PhysicalMesh& rest = body.physicalMesh();
        ASSERT_EQ(body.fractureIndex().tree->itemCount(), int(rest.primitives.size())); // and was walked, not the loop
        const Eigen::Vector3d& centre = rest.mass.centerOfMass;
        double farthest = 0.0;
        for (const auto& p : rest.primitives)
            farthest = std::max(farthest, (p.bounds().min - centre).cwiseAbs().cwiseMax((p.bounds().max - centre).cwiseAbs()).squaredNorm());
        const btScalar linear = body.rigidBody().getLinearSleepingThreshold();
        EXPECT_EQ(body.rigidBody().getAngularSleepingThreshold(), btMax(before, linear / btScalar(std::sqrt(farthest))));
    }
}

TEST(FractureSystem, ScriptedBreaksRejectBadInput) {
    FallingBlock b(5.0);
    const btScalar nan = std::numeric_limits<btScalar>::quiet_NaN();
    EXPECT_THROW(b.plugin.fracture(*b.body, btVector3(nan, 0, 0), btVector3(0, -1, 0)), InputError);
    EXPECT_THROW(b.plugin.fracture(*b.body, btVector3(0, 1, 0), btVector3(0, 0, 0)), InputError);
    VisualBody& plain = b.plugin.addVisualBody(cubeBlock("plain", 1, 1, 1, 0.05), {}, at(2, 0, 0));
    try {
        b.plugin.fracture(plain, btVector3(2, 0, 0), btVector3(0, -1, 0));
        ADD_FAILURE() << "a body without fracture broke";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("body 'plain': fracture is not enabled"), std::string::npos) << e.what();
    }
    BodySettings s = breakable();
    s.fracture.pattern = PatternKind::File;
    s.fracture.patternFile = "/nonexistent/cells.obj";
    EXPECT_THROW(b.plugin.addVisualBody(cubeBlock("vase", 1, 1, 1, 0.05), s, at(3, 0, 0)), InputError);
}

TEST(FractureSystem, ABlockBrokenOnLandingWithAContactDelayGainsNoEnergyAndRepeats) {
    // The 20 cm block of 4 cm cubes lands and breaks, its pieces not colliding with each other
    // for 3 steps. Nothing holds them together meanwhile (they fall by g (3 dt)² / 2 = 0.8 mm
    // onto those the ground stopped); their contacts then undo that without energy. The
    // landing itself gains some in the steps after the break (the ground's contacts push the
    // pieces out of the depth they landed at: 0.098 J of 7.83 J, with or without the delay),
    // so the delay may add nothing to that: kinetic plus potential energy rises over 0.5 s
    // by no more than without the delay (measured: 0.0972 J against 0.0979 J), and the
    // deepest overlap of two pieces stays below 2 mm (measured 0.5 mm; 0.1 mm without the
    // delay). The same run twice gives the same bits.
    struct Landing {
        double energy = 0.0;  // kinetic plus potential, just after the break
        double highest = 0.0; // the most it reached after
        double deepest = 0.0; // the deepest contact between two pieces (m, negative: overlap)
        std::vector<double> state; // positions and velocities at the end
    };
    const auto run = [](int delay) {
        FallingBlock b(5.0, 1, delay);
        Landing out;
        int step = 0;
        while (b.breaks() == 0 && step < 120) {
            b.w.step(1);
            ++step;
        }
        EXPECT_LT(step, 120) << "the block broke on landing";
        out.energy = out.highest = energy(b.plugin);
        for (int i = 0; i < 120; ++i) {
            b.w.step(1);
            out.highest = std::max(out.highest, energy(b.plugin));
            btDispatcher& d = *b.w.world.getDispatcher();
            for (int m = 0; m < d.getNumManifolds(); ++m) {
                const btPersistentManifold& pm = *d.getManifoldByIndexInternal(m);
                if (pm.getBody0()->isStaticObject() || pm.getBody1()->isStaticObject()) continue; // the ground
                for (int k = 0; k < pm.getNumContacts(); ++k)
                    out.deepest = std::min(out.deepest, double(pm.getContactPoint(k).getDistance()));
            }
        }
        for (const auto& body : b.plugin.bodies()) {
            const btRigidBody& r = body->rigidBody();
            for (int k = 0; k < 3; ++k)
                out.state.insert(out.state.end(), {r.getCenterOfMassPosition()[k], r.getLinearVelocity()[k]});
        }
        return out;
    };
    const Landing delayed = run(3), again = run(3), plain = run(0);
    EXPECT_EQ(delayed.energy, plain.energy) << "the same break";
    EXPECT_LT(delayed.highest - delayed.energy, plain.highest - plain.energy + 1e-3) << "no energy from the delay";
    EXPECT_GT(delayed.deepest, -0.002) << "overlap: the 0.8 mm fall and the contacts' own depth";
    EXPECT_EQ(delayed.state, again.state) << "same scene, same bits";
    EXPECT_NE(delayed.state, plain.state) << "the delay changed the contacts";
}


TEST(FractureSystem, TheEventBudgetKeepsASecondBreakForLaterStepsAndItConserves) {
    // Two 20 cm blocks of 4 cm cubes land side by side in the same step, hard enough to break.
    // Without a budget both break in that step. With one event per 4 steps the first block
    // breaks then and the second exactly 4 steps later, where its kept hit now lies, with its
    // motion of then: mass and momenta conserved at that event (1e-9 of the terms), and as
    // many fragments as it breaks into at once (within 10%).
    struct Breaks {
        std::vector<double> times;
        std::vector<int> fragments;
        std::vector<FractureSystem::Record> records;
    };
    const auto land = [](int spacing) {
        test::TestWorld w;
        w.addGround();
        Plugin plugin(w.world);
        BodySettings s = breakable();
        s.fracture.threshold = 5.0;
        s.fracture.radius = 0.12;
        s.fracture.setCells(24);
        s.fracture.eventSpacingSteps = spacing;
        for (const double x : {-0.4, 0.4}) plugin.addVisualBody(cubeBlock("block", 5, 5, 5, 0.04), s, at(x, 0.3, -0.1));
        Breaks out;
        for (int i = 0; i < 90; ++i) {
            w.step(1);
            for (const Event& e : plugin.takeEvents())
                if (e.type == EventType::BodyFractured) {
                    out.times.push_back(e.time);
                    out.fragments.push_back(e.count);
                }
            for (auto& r : plugin.fractures().takeRecords()) out.records.push_back(std::move(r));
        }
        return out;
    };
    const Breaks atOnce = land(0), spaced = land(4);
    ASSERT_EQ(atOnce.times.size(), 2u);
    EXPECT_EQ(atOnce.times[0], atOnce.times[1]) << "both land in one step";
    ASSERT_EQ(spaced.times.size(), 2u);
    EXPECT_EQ(spaced.times[0], atOnce.times[0]);
    EXPECT_NEAR(spaced.times[1] - spaced.times[0], 4.0 / 240, 1e-9) << "the second waits exactly 4 steps";
    ASSERT_EQ(spaced.records.size(), 2u);
    for (const auto& r : spaced.records) test::expectPartsConserveTheWhole(r.before, r.parts);
    EXPECT_LE(std::abs(spaced.fragments[1] - atOnce.fragments[1]), 0.1 * atOnce.fragments[1]);
}

TEST(FractureSystem, AHitKeptByTheEventBudgetBreaksBeforeAFreshOne) {
    // Blocks a and b land in one step, c (dropped from a little higher) exactly 4 steps later.
    // With one event per 4 steps, a breaks first and b's hit waits; when the budget opens again,
    // b's kept hit goes before c's fresh one (which then waits its turn), or b could wait on
    // behind every later hit.
    const auto land = [](int spacing) {
        test::TestWorld w;
        w.addGround();
        Plugin plugin(w.world);
        BodySettings s = breakable();
        s.fracture.threshold = 5.0;
        s.fracture.radius = 0.12;
        s.fracture.setCells(24);
        s.fracture.eventSpacingSteps = spacing;
        plugin.addVisualBody(cubeBlock("a", 5, 5, 5, 0.04), s, at(-0.6, 0.3, -0.1));
        plugin.addVisualBody(cubeBlock("b", 5, 5, 5, 0.04), s, at(0.0, 0.3, -0.1));
        plugin.addVisualBody(cubeBlock("c", 5, 5, 5, 0.04), s, at(0.6, 0.342, -0.1));
        std::map<std::string, long> stepOf; // body -> the step it broke in
        for (int i = 0; i < 90; ++i) {
            w.step(1);
            for (const Event& e : plugin.takeEvents())
                if (e.type == EventType::BodyFractured) stepOf.emplace(e.name, std::lround(e.time * 240));
        }
        return stepOf;
    };
    const auto atOnce = land(0), spaced = land(4);
    ASSERT_EQ(atOnce.size(), 3u);
    ASSERT_EQ(atOnce.at("b"), atOnce.at("a"));
    ASSERT_EQ(atOnce.at("c"), atOnce.at("a") + 4) << "c lands when the budget opens again";
    ASSERT_EQ(spaced.size(), 3u);
    EXPECT_EQ(spaced.at("a"), atOnce.at("a"));
    EXPECT_EQ(spaced.at("b"), atOnce.at("a") + 4) << "the kept hit goes first";
    EXPECT_EQ(spaced.at("c"), atOnce.at("a") + 8);
}
} // namespace
} // namespace shatter
