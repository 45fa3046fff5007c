#pragma once
// Self-contact of an oriented-particle body: primitives that are not connected (not touching
// at rest) must not pass through each other when the body folds or is squashed (a tyre
// pressed flat, a sheet folded onto itself). Candidate pairs come from a tree over the
// primitives' boxes; each pair is measured along the face normals of both primitives.
#include <shatter/plugin/geometry/AabbTree.h>
#include <shatter/plugin/geometry/ConvexPolyhedron.h>
#include <shatter/plugin/oriented/OrientedSolver.h>

#include <vector>

namespace shatter::oriented {

// How far apart two convex polyhedra are along the best of their face normals (the
// separating-axis test without edge-edge axes): `distance` > 0 apart, < 0 overlapping by at
// least that much; `normal` is unit, from b towards a. Edge-on-edge approaches are measured
// by the nearest face axis, which overestimates the overlap: a conservative contact.
struct PrimitiveSeparation {
    double distance = 0.0;
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};
PrimitiveSeparation faceSeparation(const geometry::ConvexPolyhedron& a, const geometry::ConvexPolyhedron& b);

// Appends a particle-pair contact (ParticleContact::otherParticle) for every pair of
// unconnected primitives whose boxes in `tree` overlap and whose face separation is below
// `reach` (m; pairs a little apart are speculative contacts that act only if the step closes
// them). `primitives` are the body's primitives where they are now, particle i's primitive
// at index i; `tree` is a tree over their boxes (grown by about `reach`/2).
void addSelfContacts(const std::vector<geometry::ConvexPolyhedron>& primitives, const geometry::AabbTree& tree,
                     const ShapeMatchingGroups& groups, double reach, double friction,
                     std::vector<ParticleContact>& contacts);

} // namespace shatter::oriented
