// The breakable-body scenes of the demos (demos/LatticeScenes): breaking must not make energy.
// Taking back the impulses between a breaking piece and loose fragments (which keep their
// other contacts) once shot tets out of the table demo at hundreds of m/s: 350 kJ of kinetic
// energy from a 144 J ball and a table top 0.75 m up.
#include "demos/LatticeScenes.h"

#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>

#include <gtest/gtest.h>

namespace shatter::demo {
namespace {

// Kinetic energy plus potential energy above the ground (y = 0) of a dynamic body (J).
double energy(const btRigidBody& r, double g) {
    if (r.getInvMass() == 0) return 0.0;
    const double m = 1.0 / double(r.getInvMass());
    const btVector3 w = r.getAngularVelocity();
    const double spin = double(w.dot(r.getInvInertiaTensorWorld().inverse() * w));
    return 0.5 * m * double(r.getLinearVelocity().length2()) + 0.5 * spin + m * g * double(r.getCenterOfMassPosition().y());
}

double totalEnergy(Scene& scene) {
    const double g = double(scene.world().getGravity().length());
    double e = 0.0;
    for (const auto& b : scene.plugin().bodies()) e += energy(b->rigidBody(), g);
    for (const auto& b : scene.rigidBodies()) e += energy(*b->body, g);
    return e;
}

template <class Options>
void expectNoEnergyGain(const Options& options, int frames) {
    Scene scene(1);
    const auto bodies = buildScene(scene, options, "test");
    const double start = totalEnergy(scene);
    double most = start;
    int mostAt = 0;
    for (int f = 1; f <= frames; ++f) {
        for (int s = 0; s < 4; ++s) scene.world().stepSimulation(btScalar(1.0 / 240 * (1 + 1e-5)), 1, btScalar(1.0 / 240));
        const double e = totalEnergy(scene);
        if (e > most) most = e, mostAt = f;
    }
    int pieces = 0;
    for (const auto* b : bodies) pieces += b->pieceCount();
    EXPECT_GT(pieces, 10) << "the scene should have broken";
    // Contacts and breaking only take energy away, but two things give some back: the
    // impulses of the hitter's contacts with a breaking body are taken back (the next step
    // meets the fragments with their own masses), and split impulses move overlapping fresh
    // fragments apart without velocity. Measured: at most +4.2% for one frame of the table
    // (557 J from 535 J at the break), none on the wall; the bug this guards against gave
    // +65,000%.
    EXPECT_LT(most, 1.05 * start) << "energy went from " << start << " J up to " << most << " J at frame " << mostAt;
}

TEST(LatticeScenes, TheTableBreaksWithoutGainingEnergy) { expectNoEnergyGain(TableOptions{}, 60); }

TEST(LatticeScenes, TheWallBreaksWithoutGainingEnergy) { expectNoEnergyGain(WallOptions{}, 30); }

} // namespace
} // namespace shatter::demo
