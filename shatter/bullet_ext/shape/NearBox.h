#pragma once
// Whether two oriented boxes come within a slack of each other: the 15-axis separating test
// the group pairs run on their primitives' boxes before Bullet's costlier hull-hull test
// (GroupCollisionAlgorithms.cpp). Plain C++ and Eigen.
#include <shatter/plugin/geometry/Aabb.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace shatter {

// Two doubles operated on lane by lane (GCC's vector extension: one SSE2 register), each lane
// with the scalar operation's bits.
using Double2 = double __attribute__((vector_size(2 * sizeof(double))));

// Frame B's turn in frame A, with what the box test (NearBox) needs of it: made once for all
// the box pairs of two bodies in a step (a group pair tests tens of thousands with the same turn).
struct BoxTurn {
    explicit BoxTurn(const Eigen::Isometry3d& bToA);
    Eigen::Isometry3d bToA;
    Eigen::Matrix3d r, absR;
    // The edge-pair axes a_i × b_j in the order k = 3j + i (two a pair, the last pair's second
    // lane spare, zero): absR(i2, j), absR(i1, j), r(i1, j), r(i2, j) with i1 = i + 1, i2 = i + 2
    // (mod 3), as NearBox::within reads them.
    Double2 edgeAbs2[5], edgeAbs1[5], edgeR1[5], edgeR2[5];
};

// The 15-axis separating test of two oriented boxes: whether box a (in frame A) and box b (in
// frame B, placed in A by the turn) come within `slack` of each other. The tree pairs boxes by
// the axis-aligned box of a rotated box, up to 1.7 times larger; this cheap exact test keeps
// Bullet's costlier hull-hull test for pairs that can touch. What depends on b alone is
// computed once (a group against one convex shape tests every leaf against the same b).
class NearBox {
public:
    NearBox(const geometry::Aabb& b, const BoxTurn& turn, double slack);

    // Each axis's test is |centre distance| > a's reach + b's reach + slack, in the same
    // operations whatever order the axes are tried in (the edge pairs two at a time), so the
    // answer does not depend on it.
    bool within(const geometry::Aabb& a) const;
    // within() for this box's slack and for one no larger, `narrowSlack`, in one pass: 0 when a
    // is not within the slack, 1 when it is within the slack only, 2 when it is within both.
    // Each answer has within()'s bits (a NearBox made with narrowSlack gives the second: the
    // slack is only ever added last), for little more than one test: a group pair that makes
    // its list of pairs within the list's reach needs the contact reach's answer for the same
    // pairs in the same step.
    int withinBoth(const geometry::Aabb& a, double narrowSlack) const;

private:
    template <bool Both>
    int test(const geometry::Aabb& a, double narrowSlack) const; // withinBoth's answer

    const BoxTurn* turn_; // outlives the box
    Eigen::Vector3d hb_, centre_;
    double slack_, faceReach2_; // absR.row(2) · hb
    Double2 centre01_, slack2_, faceReach01_; // x and y; the slack twice; absR.row(i) · hb, i = 0, 1
    Double2 edgeReach_[5]; // hb[j1] absR(i, j2) + hb[j2] absR(i, j1), in BoxTurn's edge order (+∞ spare)
};

// How deep (along A's axes) A's box grown by slackA and the axis-aligned box of B's box grown
// by slackB and turned by bToA overlap, at least, when NearBox keeps the two boxes within
// `reach`, so that a walk of trees over the grown boxes (AabbTree::pairsWith's depth) may skip
// node pairs overlapping by less: their leaves hold no pair the box test keeps. Along axis k the
// boxes come within reach, A grows by slackA and the turned box by slackB times row k's sum of
// |bToA|. Kept back: a millionth of the turned growth and 10 µm, for NearBox's 1e-9 widening
// (1e-9 times b's half-extent sum: covered while that stays under about 10 km) and rounding.
// None negative. Inline: the relist's code (and its bits) as before it was named.
inline Eigen::Vector3d relistDepth(const Eigen::Matrix3d& bToA, double slackA, double slackB, double reach) {
    const Eigen::Vector3d rowSums = bToA.cwiseAbs().rowwise().sum();
    return ((slackA - reach - 1e-5) + (slackB * (1 - 1e-6)) * rowSums.array()).cwiseMax(0.0);
}

} // namespace shatter
