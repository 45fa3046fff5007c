#include <shatter/bullet_ext/shape/NearBox.h>

#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace shatter {

namespace {

using Bits2 = std::int64_t __attribute__((vector_size(2 * sizeof(std::int64_t)))); // a Double2 comparison's lanes

// std::abs lane by lane: the sign bit cleared.
Double2 magnitude(Double2 x) {
    const Bits2 noSign = {std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::max()};
    return reinterpret_cast<Double2>(reinterpret_cast<Bits2>(x) & noSign);
}

// Two doubles from memory (an Eigen vector's x and y).
Double2 pairAt(const double* p) {
    Double2 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

constexpr double kNever = std::numeric_limits<double>::infinity(); // a spare lane's reach: never exceeded

} // namespace

BoxTurn::BoxTurn(const Eigen::Isometry3d& bToA)
    : bToA(bToA), r(bToA.linear()), absR(r.cwiseAbs().array() + 1e-9) { // parallel edges: no zero cross axis
    for (int k = 0; k < 10; ++k) {
        const int i = k % 3, j = k / 3, i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        const bool spare = k == 9;
        edgeAbs2[k / 2][k % 2] = spare ? 0.0 : absR(i2, j);
        edgeAbs1[k / 2][k % 2] = spare ? 0.0 : absR(i1, j);
        edgeR1[k / 2][k % 2] = spare ? 0.0 : r(i1, j);
        edgeR2[k / 2][k % 2] = spare ? 0.0 : r(i2, j);
    }
}

NearBox::NearBox(const geometry::Aabb& b, const BoxTurn& turn, double slack)
    : turn_(&turn), hb_(0.5 * b.extent()), centre_(turn.bToA * b.center()), slack_(slack) {
    const Eigen::Matrix3d& absR = turn.absR;
    centre01_ = pairAt(centre_.data());
    slack2_ = Double2{slack, slack};
    faceReach01_ = Double2{absR.row(0).dot(hb_), absR.row(1).dot(hb_)};
    faceReach2_ = absR.row(2).dot(hb_);
    for (int k = 0; k < 10; ++k) {
        const int i = k % 3, j = k / 3;
        edgeReach_[k / 2][k % 2] =
            k == 9 ? kNever : hb_[(j + 1) % 3] * absR(i, (j + 2) % 3) + hb_[(j + 2) % 3] * absR(i, (j + 1) % 3);
    }
}

bool NearBox::within(const geometry::Aabb& a) const { return test<false>(a, slack_) != 0; }

int NearBox::withinBoth(const geometry::Aabb& a, double narrowSlack) const {
    // A larger narrowSlack would be a wider reach than the list's; every caller passes the
    // contact reach, which is never larger. (Release builds, CI's included, skip the assert.)
    assert(!(narrowSlack > slack_));
    return test<true>(a, narrowSlack);
}

// Each axis's reach (before its slack) is compared with the slack, and with `Both` also with
// narrowSlack. The smaller slack's sum is never the larger (rounding is monotonic), so an axis
// far by the slack is far by the smaller one too, and the test may end there in either case.
// Without `Both`, the narrow compares compile away: within()'s instructions are those it had
// alone.
template <bool Both>
[[gnu::always_inline]] inline int NearBox::test(const geometry::Aabb& a, double narrowSlack) const {
    // a's half extent and its centre's offset from b's, as Aabb's extent() and center() give
    // them: x and y in one pair, z alone.
    const Double2 min01 = pairAt(a.min.data()), max01 = pairAt(a.max.data());
    const Double2 ha01 = 0.5 * (max01 - min01);
    const Double2 t01 = centre01_ - 0.5 * (min01 + max01);
    const double ha2 = 0.5 * (a.max.z() - a.min.z());
    const double t2 = centre_.z() - 0.5 * (a.min.z() + a.max.z());
    const Double2 narrow2 = {narrowSlack, narrowSlack};

    // A's face normals.
    const Double2 mag01 = magnitude(t01), reach01 = ha01 + faceReach01_;
    const double reach2 = ha2 + faceReach2_;
    const Bits2 far01 = mag01 > reach01 + slack2_;
    if ((far01[0] | far01[1]) != 0 || std::abs(t2) > reach2 + slack_) return 0;
    bool narrowFar = false;
    if constexpr (Both) {
        const Bits2 nearFar01 = mag01 > reach01 + narrow2;
        narrowFar = (nearFar01[0] | nearFar01[1]) != 0 || std::abs(t2) > reach2 + narrowSlack;
    }

    // B's face normals: Eigen's dot products.
    const Eigen::Vector3d ha(ha01[0], ha01[1], ha2), t(t01[0], t01[1], t2);
    const Eigen::Matrix3d &r = turn_->r, &absR = turn_->absR;
    for (int j = 0; j < 3; ++j) {
        const double distance = std::abs(t.dot(r.col(j))), reach = absR.col(j).dot(ha) + hb_[j];
        if (distance > reach + slack_) return 0;
        if constexpr (Both) narrowFar = narrowFar || distance > reach + narrowSlack;
    }

    // Edge pairs, axis a_i × b_j for k = 3j + i, two at a time: ha[i1], ha[i2], t[i1], t[i2]
    // (i1 = i + 1, i2 = i + 2 mod 3) run through (1, 2), (2, 0), (0, 1), (1, 2), (2, 0), ...
    const Double2 ha12 = {ha01[1], ha2}, ha20 = {ha2, ha01[0]};
    const Double2 t12 = {t01[1], t2}, t20 = {t2, t01[0]};
    const Double2 haI1[5] = {ha12, ha01, ha20, ha12, ha01}, haI2[5] = {ha20, ha12, ha01, ha20, ha12};
    const Double2 tI1[5] = {t12, t01, t20, t12, t01}, tI2[5] = {t20, t12, t01, t20, t12};
    Bits2 far = {0, 0}, farNarrow = {0, 0};
    for (int p = 0; p < 5; ++p) {
        const Double2 ra = haI1[p] * turn_->edgeAbs2[p] + haI2[p] * turn_->edgeAbs1[p];
        const Double2 distance = magnitude(tI2[p] * turn_->edgeR1[p] - tI1[p] * turn_->edgeR2[p]);
        const Double2 reach = ra + edgeReach_[p];
        far |= distance > reach + slack2_;
        if constexpr (Both) farNarrow |= distance > reach + narrow2;
    }
    if ((far[0] | far[1]) != 0) return 0;
    return narrowFar || (farNarrow[0] | farNarrow[1]) != 0 ? 1 : 2;
}

} // namespace shatter
