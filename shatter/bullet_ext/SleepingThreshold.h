#pragma once
// Bullet's angular sleeping threshold (1 rad/s by default) is meant for bodies of about a
// metre; on a piece of a few centimetres it means a rim speed of a few cm/s, which a piece
// lying in a heap exceeds every few steps as contacts nudge it, each time restarting the timer
// of its whole island, so the heap never sleeps (lattice pieces: 270 loose tets awake after
// 10 s; the shards of Spot the cow, a closed mesh broken twice: 162 of 164 bodies awake after
// 10 s, turning at 1-30 rad/s with 1-15 cm/s at their centre). A piece counts as slow instead
// when its turning moves no point within `radius` (m) of its centre of mass faster than the
// linear threshold (Bullet tests the two speeds apart, so a point may move at up to twice it);
// never below Bullet's own angular threshold.
#include <BulletDynamics/Dynamics/btRigidBody.h>

namespace shatter {

inline void sleepWhenNoPointIsFast(btRigidBody& rigid, btScalar radius) {
    const btScalar linear = rigid.getLinearSleepingThreshold();
    if (radius > 0) rigid.setSleepingThresholds(linear, btMax(rigid.getAngularSleepingThreshold(), linear / radius));
}

} // namespace shatter
