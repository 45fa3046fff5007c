#pragma once
// The moment matrix of one oriented particle (source 000 §3.2.1, with the errata of
// ../shared/seeds/README.md): C = ∫ρ r rᵀ dV about the particle's centre of mass, in the
// particle's rest frame. A particle turned by R contributes A_i = R C to a group's moment
// (rest orientation is the identity: primitives are stored in rest coordinates).
#include <shatter/plugin/geometry/MassProperties.h>

#include <Eigen/Core>

namespace shatter::oriented {

// From exact mass properties: C = ½ trace(I) 𝟙 − I, with I the inertia tensor about the
// centre of mass (I = trace(C) 𝟙 − C).
Eigen::Matrix3d secondMoment(const geometry::MassProperties& mass);

// Closed forms (the source's eq. 2): solid sphere of radius r, C = m r²/5 𝟙; solid
// ellipsoid with semi-axes a, b, c along the frame axes, C = m/5 diag(a², b², c²).
Eigen::Matrix3d sphereMoment(double mass, double radius);
Eigen::Matrix3d ellipsoidMoment(double mass, const Eigen::Vector3d& semiAxes);

// Inertia tensor (about the centre of mass) of a particle with moment C: trace(C) 𝟙 − C.
Eigen::Matrix3d inertiaFromMoment(const Eigen::Matrix3d& C);

} // namespace shatter::oriented
