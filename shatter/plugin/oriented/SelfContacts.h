#pragma once
// Self-contact of an oriented-particle body: primitives that are not connected (not touching
// at rest) must not pass through each other when the body folds or is squashed (a tyre
// pressed flat, a sheet folded onto itself). Candidate pairs come from a tree over the
// primitives' boxes, kept across steps; each pair is measured along the face normals of both
// primitives.
#include <shatter/plugin/geometry/AabbTree.h>
#include <shatter/plugin/geometry/ConvexPolyhedron.h>
#include <shatter/plugin/oriented/OrientedSolver.h>

#include <utility>
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

// The self-contacts of one body, step after step: a particle-pair contact
// (ParticleContact::otherParticle) for every pair of unconnected primitives whose boxes
// overlap and whose face separation is below `reach` (m; pairs a little apart are
// speculative contacts that act only if the step closes them), particle < otherParticle.
//
// Candidate pairs are kept across calls (a Verlet list): the pairs whose boxes, each grown
// by `skin` (m), overlapped when the list was made. While every primitive's box stays inside
// its grown box, every pair whose boxes overlap now is on the list, so the list gives exactly
// the pairs a walk over a tree of the current boxes gives, without the walk; and so it does
// while every box, moved back by one common shift, is inside its grown box (overlaps do not
// change when all boxes move alike: a falling or swaying sheet keeps its list). The list is
// made again (a walk over the body's tree with the grown boxes) when no shift puts every box
// inside its grown box,
// the primitive count changes or the connections changed (ShapeMatchingGroups::connectionsVersion:
// tearing cuts connections), and holds the unconnected pairs only. While the body moves so fast that
// grown lists last a single call, the walks are over the boxes as they are (skin 0).
class SelfContactCandidates {
public:
    explicit SelfContactCandidates(double skin);
    // `primitives` are the body's primitives where they are now, particle i's primitive at
    // index i; `tree` a tree over them (its shape is used, not its boxes; contacts come in its
    // walk's order, which decides the solver's order); `groups` the body's shape-matching
    // groups (which say what is connected). Throws std::invalid_argument when the tree has
    // another number of items than `primitives`.
    void addContacts(const std::vector<geometry::ConvexPolyhedron>& primitives, const geometry::AabbTree& tree,
                     const ShapeMatchingGroups& groups, double reach, double friction,
                     std::vector<ParticleContact>& contacts);
    // How many times the list was made (for tests and benchmarks).
    int rebuilds() const { return rebuilds_; }

private:
    bool covers(const std::vector<geometry::ConvexPolyhedron>& primitives) const;
    void rebuild(const std::vector<geometry::ConvexPolyhedron>& primitives, const geometry::AabbTree& tree,
                 const ShapeMatchingGroups& groups, double skin);

    double skin_;
    std::vector<geometry::Aabb> grown_;     // per primitive, its box grown by skin_ at the last rebuild
    geometry::AabbTree tree_;               // the body's tree over grown_
    std::vector<std::pair<int, int>> pairs_; // unconnected, a < b, in the walk's order
    std::pair<std::uint64_t, size_t> groups_{0, 0}; // connectionsVersion() of the groups that said which are connected
    // Whether the last walk was over grown boxes, the calls its list has served, how many
    // walks are still to be over the boxes as they are, and how many the next fast move sets.
    bool lastGrown_ = false;
    int callsSinceRebuild_ = 0, exactWalksLeft_ = 0, backoff_ = 1;
    int rebuilds_ = 0;
};

} // namespace shatter::oriented
