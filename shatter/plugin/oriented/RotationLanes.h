#pragma once
// Internal to the oriented module (the batched projection and the rotation extraction share
// it; not part of the API): rotation fits, and rotation matrices, as interleaved lanes.
#include <shatter/plugin/oriented/RotationExtraction.h>
#include <shatter/plugin/oriented/SimdLanes.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace shatter::oriented {

// K fits as lanes (struct of arrays): fit l is A(i, j) = a[3 i + j][l] and q = (w, x, y, z)[l].
// Every lane of a default FitLanes starts as a fit with nothing to fit (a zero matrix, the
// identity), which is what fitRotations needs of the lanes it does not fit (clear() makes one
// lane so). RotationLanes, kRotationLanes of them, is for
// a caller that makes its matrices lane by lane (the batched projection writes its sums here
// instead of into matrices that are then read back one entry at a time).
template <int K>
struct FitLanes {
    DoubleLanes<K> a[9];
    DoubleLanes<K> w, x, y, z;

    FitLanes() {
        for (int l = 0; l < K; ++l) clear(l);
    }
    // Every lane left unset, for a caller that sets or clears each one itself (the batched
    // projection sets all four in most batches: zeroing them first cost 13 instructions a group).
    struct Unset {};
    explicit FitLanes(Unset) {}
    // Lane l becomes a fit with nothing to fit.
    SHATTER_LANES_INLINE void clear(int l) {
        for (auto& e : a) e[l] = 0.0;
        w[l] = 1.0, x[l] = 0.0, y[l] = 0.0, z[l] = 0.0;
    }

    SHATTER_LANES_INLINE void set(int l, const Eigen::Matrix3d& A, const Eigen::Quaterniond& q) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) a[3 * i + j][l] = A(i, j);
        w[l] = q.w(), x[l] = q.x(), y[l] = q.y(), z[l] = q.z();
    }
    Eigen::Quaterniond answer(int l) const { return Eigen::Quaterniond(w[l], x[l], y[l], z[l]); }
};
using RotationLanes = FitLanes<kRotationLanes>;

// The fits of lanes [0, count) of `f` (the others left as they are: set none of them, or set
// them to a fit with nothing to fit), answers in their q: extractRotations's bits, on `path`.
// shatter::InputError for a count outside [0, kRotationLanes] or a path this processor lacks.
void fitRotations(RotationLanes& f, int count, int maxIterations, double tolerance, double newtonStop,
                  SimdPath path);

// r[3 i + j] = R(i, j) of the unit quaternions (w, x, y, z), lane by lane: Eigen's
// toRotationMatrix, operation for operation (the same bits).
template <int K>
SHATTER_LANES_INLINE void rotationMatrices(const DoubleLanes<K>& w, const DoubleLanes<K>& x, const DoubleLanes<K>& y,
                                           const DoubleLanes<K>& z, DoubleLanes<K> (&r)[9]) {
    const DoubleLanes<K> tx = 2.0 * x, ty = 2.0 * y, tz = 2.0 * z;
    const DoubleLanes<K> twx = tx * w, twy = ty * w, twz = tz * w;
    const DoubleLanes<K> txx = tx * x, txy = ty * x, txz = tz * x;
    const DoubleLanes<K> tyy = ty * y, tyz = tz * y, tzz = tz * z;
    r[0] = 1.0 - (tyy + tzz), r[1] = txy - twz, r[2] = txz + twy;
    r[3] = txy + twz, r[4] = 1.0 - (txx + tzz), r[5] = tyz - twx;
    r[6] = txz - twy, r[7] = tyz + twx, r[8] = 1.0 - (txx + tyy);
}

} // namespace shatter::oriented
