// Public meshes a user might bring (demos/assets/README.md gives origin and licence), dropped
// the way `shatter-drop --mesh` drops them: each comes to rest on the ground, its visual mesh
// stays above it, and a closed mesh weighs its density times the volume it encloses, carried
// by its primitives (PhysicalMeshSettings::fill, Fill::Solid).
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

// Volume a closed surface encloses, by the divergence theorem: Σ over a fan of each face of
// (a · (b × c)) / 6. From the file's own faces, independently of the physical mesh.
double enclosedVolume(const geometry::ObjFile& file) {
    const auto& p = file.positions;
    double volume = 0.0;
    for (const auto& object : file.objects)
        for (const auto& face : object.faces) {
            const auto& f = face.vertices;
            for (size_t k = 1; k + 1 < f.size(); ++k) volume += p[f[0]].dot(p[f[k]].cross(p[f[k + 1]])) / 6.0;
        }
    return volume;
}

struct Drop {
    double restSpeed = 0, restSpin = 0, lowestVisual = 0, mass = 0, primitiveVolume = 0, density = 0,
           enclosedVolume = 0;
    int primitives = 0;
};

// Drops the mesh from 0.3 m above the ground, tilted 20°, and steps `seconds` at 240 Hz.
Drop dropMesh(const std::string& file, double seconds) {
    test::TestWorld w;
    w.world.getSolverInfo().m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
    w.addGround();
    Plugin plugin(w.world);
    const geometry::ObjFile obj = geometry::loadObj(std::string(SHATTER_SOURCE_DIR) + "/" + file);
    const auto object = geometry::buildPhysicalObject(obj);
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
    d.enclosedVolume = enclosedVolume(obj);
    return d;
}

} // namespace

// Spot (Keenan Crane, CC0): a closed surface of 5,856 triangles in a 1.7 m box, extruded inward
// into as many prisms, which carry the mass of the solid cow (0.718 m³ at 1000 kg/m³). Rest: after 6 s the body is asleep or slower than 1 cm/s and 0.05 rad/s
// (it falls about 2.5 m; Bullet's sleeping thresholds are 0.8 m/s and 1 rad/s held for
// 2 s, so a body still moving faster is not at rest). Above the ground: no visual vertex lower
// than Bullet's default collision margin of the group shape (4 mm) plus 1 mm of contact slop.
// Mass: float mass in Bullet (7 significant digits), so 1e-6 relative.
TEST(PublicMeshGallery, SpotTheCowComesToRestOnTheGroundWeighingItsEnclosedVolume) {
    const Drop d = dropMesh("demos/assets/spot.obj", 6.0);
    EXPECT_EQ(d.primitives, 5856);
    EXPECT_LT(d.restSpeed, 0.01);
    EXPECT_LT(d.restSpin, 0.05);
    EXPECT_GT(d.lowestVisual, -0.005);
    EXPECT_LT(d.lowestVisual, 0.05); // on the ground, not hovering
    EXPECT_NEAR(d.enclosedVolume, 0.718, 0.001);
    EXPECT_NEAR(d.mass, 1000.0 * d.enclosedVolume, 1e-6 * d.mass);      // density given × enclosed volume
    EXPECT_NEAR(d.mass, d.density * d.primitiveVolume, 1e-6 * d.mass); // carried by the primitives
}
