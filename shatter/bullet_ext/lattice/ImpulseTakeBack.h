#pragma once
// Taking contact impulses of the step just solved back from their bodies (the lattice system's
// replay after a break, the hitters of a frozen piece that wakes). The lattice system runs
// after Bullet has integrated the step, so a body whose impulses are taken back was held
// where they stopped it, and leaves the step with the speed it would have had without them:
// gravity's gain included, though it did not fall. Step after step (a ball pressing on a table
// top that keeps breaking under it), the body stays put while its speed grows by gravity's
// every step: the table demo with single tets as debris gained 80 J of kinetic energy from a
// ball held in the hole it was making (+15%). So a body whose impulses are taken back does
// not gain gravity's speed for the step it was held in. (Moving it on by its change of
// velocity instead would be as consistent, but lets the ball plough through the wall as if
// it were not there in every step a piece breaks: 881 fragments instead of 361.)
#include <shatter/bullet_ext/ContactSnapshot.h>

#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <unordered_set>

namespace shatter {

class ImpulseTakeBack {
public:
    // Takes the point's impulse back from both bodies of the pair (static and kinematic bodies
    // are not moved).
    void takeBack(const ContactPair& pair, const ContactPoint& p);
    // Takes gravity's gain of a step of `dt` back from every body an impulse was taken back
    // from; forgets the bodies.
    void finish(double dt);

private:
    std::unordered_set<btRigidBody*> held_;
};

} // namespace shatter
