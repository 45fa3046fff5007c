// Public meshes a user might bring (demos/assets/README.md gives origin and licence), dropped
// the way `shatter-drop --mesh` drops them: each comes to rest on the ground, its visual mesh
// stays above it, and its mass is its density times the volume of its primitives.
#include <shatter/bullet_ext/Plugin.h>
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

using namespace shatter;

namespace {

// Volume of a closed polyhedron as a fan of tetrahedra from its first vertex: computed here
// from the faces, independently of geometry::MassProperties.
double fanVolume(const geometry::ConvexPolyhedron& p) {
    const auto& v = p.vertices();
    double volume = 0.0;
    for (const auto& face : p.faces())
        for (size_t k = 1; k + 1 < face.size(); ++k)
            volume += (v[face[0]] - v[0]).dot((v[face[k]] - v[0]).cross(v[face[k + 1]] - v[0])) / 6.0;
    return volume;
}

struct Drop {
    double restSpeed = 0, restSpin = 0, lowestVisual = 0, mass = 0, primitiveVolume = 0, density = 0;
    int primitives = 0;
};

// Drops the mesh from 0.3 m above the ground, tilted 20°, and steps `seconds` at 240 Hz.
Drop dropMesh(const std::string& file, double seconds) {
    test::TestWorld w;
    w.world.getSolverInfo().m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
    w.addGround();
    Plugin plugin(w.world);
    const auto object = geometry::buildPhysicalObject(geometry::loadObj(std::string(SHATTER_SOURCE_DIR) + "/" + file));
    geometry::Aabb box;
    for (const auto& body : object.bodies)
        for (const auto& p : body.primitives) box.extend(p.bounds());
    const btQuaternion tilt(btVector3(1, 0, 1).normalized(), btScalar(0.35));
    btTransform pose(tilt, btVector3(0, 0, 0));
    pose.setOrigin(btVector3(0, btScalar(0.3 + box.diagonal()), 0) - pose.getBasis() * btVector3(0, btScalar(box.center().y()), 0));
    BodySettings settings;
    settings.rigidBody.rollingFriction = 0.001; // round bodies stop rocking (README)
    VisualBody& body = *plugin.addObject(object, settings, pose).bodies.front();
    w.step(int(seconds * 240));

    Drop d;
    d.restSpeed = body.rigidBody().getLinearVelocity().length();
    d.restSpin = body.rigidBody().getAngularVelocity().length();
    const auto& visual = body.visualMesh();
    d.lowestVisual = std::min_element(visual.positions.begin(), visual.positions.end(),
                                      [](const auto& a, const auto& b) { return a.y() < b.y(); })->y();
    d.mass = 1.0 / body.rigidBody().getInvMass();
    for (const auto& p : body.physicalMesh().primitives) d.primitiveVolume += fanVolume(p);
    d.density = body.physicalMesh().density;
    d.primitives = int(body.physicalMesh().primitives.size());
    return d;
}

} // namespace

// Spot (Keenan Crane, CC0): a closed surface of 5,856 triangles in a 1.7 m box, extruded inward
// into as many prisms. Rest: after 6 s the body is asleep or slower than 1 cm/s and 0.05 rad/s
// (it falls about 2.5 m; Bullet's sleeping thresholds are 0.8 m/s and 1 rad/s held for
// 2 s, so a body still moving faster is not at rest). Above the ground: no visual vertex lower
// than Bullet's default collision margin of the group shape (4 mm) plus 1 mm of contact slop.
// Mass: float mass in Bullet (7 significant digits), so 1e-6 relative.
TEST(PublicMeshGallery, SpotTheCowComesToRestOnTheGroundWithTheMassOfItsPrimitives) {
    const Drop d = dropMesh("demos/assets/spot.obj", 6.0);
    EXPECT_EQ(d.primitives, 5856);
    EXPECT_LT(d.restSpeed, 0.01);
    EXPECT_LT(d.restSpin, 0.05);
    EXPECT_GT(d.lowestVisual, -0.005);
    EXPECT_LT(d.lowestVisual, 0.05); // on the ground, not hovering
    EXPECT_NEAR(d.mass, d.density * d.primitiveVolume, 1e-6 * d.mass);
}
