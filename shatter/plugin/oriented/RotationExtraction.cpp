#include <shatter/plugin/oriented/RotationExtraction.h>
#include <shatter/plugin/oriented/RotationLanes.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/oriented/SimdLanes.h>

#include <algorithm>
#include <cmath>
#include <string>

// The lane helpers take and return 32-byte vectors by value; they are always inlined, never
// called across the ABI that GCC warns changed for such vectors.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace shatter::oriented {

namespace {

// K fits as lanes (struct of arrays): every quantity is a DoubleLanes<K> and every operation
// acts on all lanes (two SSE2 or one AVX2 instruction for 4 lanes), so the K dependent chains
// of a fit overlap in the processor. The arithmetic of a lane does not depend on K or on the
// instruction set (no lane reads another, no fused multiply-add): one fit alone (K = 1,
// extractRotation) gives the same bits as in a batch, on either path.
template <int K>
using Lane = DoubleLanes<K>;
template <int K>
using LaneFlags = LaneMask<K>;

template <int K>
using Lanes = FitLanes<K>; // the matrix a is not changed; q is the fit, in and out

template <int K>
SHATTER_LANES_INLINE bool anyLane(const LaneFlags<K>& flags) {
    for (int l = 0; l < K; ++l)
        if (flags[l]) return true;
    return false;
}

// One fit step per lane, as a rotation vector in the frame of R (step) that increases
// trace(RᵀA). With M = RᵀA, trace((R exp[θ])ᵀ A) ≈ trace M + θ·τ − ½ θᵀ H θ,
// τ = (M₂₁−M₁₂, M₀₂−M₂₀, M₁₀−M₀₁), H = trace(M) 𝟙 − sym(M). Near the answer H is positive
// definite and the Newton step H⁻¹τ converges quadratically (newton). Elsewhere (far away,
// or a rank-deficient A) Müller's step τ / |trace M| is used: it always increases the fit and
// is finite for any A. Both are computed for every lane and one is chosen (no branch to split
// the lanes).
template <int K>
SHATTER_LANES_INLINE void fitSteps(const Lanes<K>& f, Lane<K> (&step)[3], LaneFlags<K>& newton) {
    // R of q (as Eigen's toRotationMatrix), then M = RᵀA.
    Lane<K> r[9];
    rotationMatrices<K>(f.w, f.x, f.y, f.z, r);
    Lane<K> m[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m[3 * i + j] = r[i] * f.a[j] + r[3 + i] * f.a[3 + j] + r[6 + i] * f.a[6 + j];
    const Lane<K> t0 = m[7] - m[5], t1 = m[2] - m[6], t2 = m[3] - m[1];
    const Lane<K> trace = m[0] + m[4] + m[8];
    // The size of M for the degeneracy floors: its entry-wise 1-norm, within a factor 3 of
    // the Frobenius norm and without its square root.
    Lane<K> scale = abs<K>(m[0]);
    for (int e = 1; e < 9; ++e) scale += abs<K>(m[e]);
    // H positive definite when its three pivots are (the LLT's squared diagonal); solved by
    // its adjugate, a fraction of a factorisation's cost.
    const Lane<K> h00 = trace - m[0], h11 = trace - m[4], h22 = trace - m[8];
    const Lane<K> h01 = -0.5 * (m[1] + m[3]), h02 = -0.5 * (m[2] + m[6]), h12 = -0.5 * (m[5] + m[7]);
    const Lane<K> c00 = h11 * h22 - h12 * h12, c01 = h02 * h12 - h01 * h22, c02 = h01 * h12 - h02 * h11;
    const Lane<K> c11 = h00 * h22 - h02 * h02, c12 = h01 * h02 - h00 * h12;
    const Lane<K> minor2 = h00 * h11 - h01 * h01;
    const Lane<K> det = h00 * c00 + h01 * c01 + h02 * c02;
    const Lane<K> floor = 1e-12 * scale;
    const Lane<K> inverse = 1.0 / det;
    const Lane<K> n0 = inverse * (c00 * t0 + c01 * t1 + c02 * t2);
    const Lane<K> n1 = inverse * (c01 * t0 + c11 * t1 + c12 * t2);
    const Lane<K> n2 = inverse * (c02 * t0 + c12 * t1 + minor2 * t2);
    // A squared length under 0.25 is also finite (an infinite or NaN step fails it).
    newton = (h00 > floor) & (minor2 > floor * h00) & (det > floor * minor2) & (n0 * n0 + n1 * n1 + n2 * n2 < 0.25);
    const Lane<K> mueller = abs<K>(trace) + 1e-9 * scale + 1e-300;
    step[0] = select<K>(newton, n0, t0 / mueller);
    step[1] = select<K>(newton, n1, t1 / mueller);
    step[2] = select<K>(newton, n2, t2 / mueller);
}

template <int K>
SHATTER_LANES_INLINE void fit(Lanes<K>& f, int count, int maxIterations, double tolerance, double newtonStop) {
    LaneFlags<K> running;
    for (int l = 0; l < K; ++l) running[l] = l < count ? -1 : 0;
    // The warm start may be off unit by more than the renormalisation below repairs.
    Lane<K> norm = f.w * f.w + f.x * f.x + f.y * f.y + f.z * f.z;
    for (int l = 0; l < K; ++l) norm[l] = std::sqrt(norm[l]);
    f.w /= norm, f.x /= norm, f.y /= norm, f.z /= norm;
    for (int iteration = 0; iteration < maxIterations && anyLane<K>(running); ++iteration) {
        Lane<K> step[3];
        LaneFlags<K> newton;
        fitSteps(f, step, newton);
        // The turn by `step` as a quaternion t: below 0.05 rad by its series (relative error
        // under 1e-9; unit to that error, and renormalised with q below), which spares the
        // square root, sine and cosine; the rare larger turns exactly, lane by lane.
        const Lane<K> angle2 = step[0] * step[0] + step[1] * step[1] + step[2] * step[2];
        const Lane<K> half = 0.5 - angle2 / 48.0; // sin(θ/2)/θ ≈ 1/2 − θ²/48
        Lane<K> t[4] = {1.0 - angle2 / 8.0 + angle2 * angle2 / 384.0, half * step[0], half * step[1], half * step[2]};
        for (int l = 0; l < K; ++l) {
            if (!(running[l] && angle2[l] >= 0.05 * 0.05)) continue;
            const double angle = std::sqrt(angle2[l]);
            const double sine = std::sin(0.5 * angle) / angle;
            t[0][l] = std::cos(0.5 * angle);
            for (int e = 0; e < 3; ++e) t[1 + e][l] = sine * step[e][l];
        }
        // A lane stops without turning once its step is under the tolerance (also on NaN),
        // and after turning by a Newton step under newtonStop: that leaves an error of order
        // its square (warm-started fits mostly end there, after one evaluation).
        const LaneFlags<K> turn = running & (angle2 > tolerance * tolerance);
        running = turn & ~(newton & (angle2 < newtonStop * newtonStop));
        // q t, renormalised by one Newton step of the inverse square root (|q t|² = 1 + ε,
        // exact to ε², without a square root or a division): unit to ~1e-18 each turn.
        const Lane<K> pw = f.w * t[0] - f.x * t[1] - f.y * t[2] - f.z * t[3];
        const Lane<K> px = f.w * t[1] + f.x * t[0] + f.y * t[3] - f.z * t[2];
        const Lane<K> py = f.w * t[2] - f.x * t[3] + f.y * t[0] + f.z * t[1];
        const Lane<K> pz = f.w * t[3] + f.x * t[2] - f.y * t[1] + f.z * t[0];
        const Lane<K> unit = 1.5 - 0.5 * (pw * pw + px * px + py * py + pz * pz);
        f.w = select<K>(turn, unit * pw, f.w);
        f.x = select<K>(turn, unit * px, f.x);
        f.y = select<K>(turn, unit * py, f.y);
        f.z = select<K>(turn, unit * pz, f.z);
    }
}

// fit<kRotationLanes> compiled for each path.
void fitPortable(Lanes<kRotationLanes>& f, int count, int maxIterations, double tolerance, double newtonStop) {
    fit(f, count, maxIterations, tolerance, newtonStop);
}
SHATTER_AVX2 void fitAvx2(Lanes<kRotationLanes>& f, int count, int maxIterations, double tolerance,
                          double newtonStop) {
    fit(f, count, maxIterations, tolerance, newtonStop);
}

// fitRotations's refusal, out of line: the check is on the solver's hot path (once a batch).
[[noreturn, gnu::noinline, gnu::cold]] void refuseFits(int count) {
    if (count < 0 || count > kRotationLanes)
        throw InputError("fitRotations: " + std::to_string(count) + " fits in " + std::to_string(kRotationLanes) +
                         " lanes");
    throw InputError("fitRotations: a SIMD path this processor does not have (AVX2 without AVX2)");
}

} // namespace

Eigen::Quaterniond extractRotation(const Eigen::Matrix3d& A, Eigen::Quaterniond q, int maxIterations,
                                   double tolerance, double newtonStop) {
    Lanes<1> f;
    f.set(0, A, q);
    fit(f, 1, maxIterations, tolerance, newtonStop);
    return f.answer(0);
}

void fitRotations(RotationLanes& f, int count, int maxIterations, double tolerance, double newtonStop,
                  SimdPath path) {
    if (count < 0 || count > kRotationLanes || !simdPathAvailable(path)) refuseFits(count);
    if (count == 1) { // one fit (a dent's relaxation, a tail): the same bits without 3 idle lanes
        Lanes<1> one;
        for (int e = 0; e < 9; ++e) one.a[e][0] = f.a[e][0];
        one.w[0] = f.w[0], one.x[0] = f.x[0], one.y[0] = f.y[0], one.z[0] = f.z[0];
        fit(one, 1, maxIterations, tolerance, newtonStop);
        f.w[0] = one.w[0], f.x[0] = one.x[0], f.y[0] = one.y[0], f.z[0] = one.z[0];
        return;
    }
    path == SimdPath::Avx2 ? fitAvx2(f, count, maxIterations, tolerance, newtonStop)
                           : fitPortable(f, count, maxIterations, tolerance, newtonStop);
}

void extractRotations(std::span<const Eigen::Matrix3d> A, std::span<Eigen::Quaterniond> q, int maxIterations,
                      double tolerance, double newtonStop, SimdPath path) {
    if (!simdPathAvailable(path)) throw InputError("extractRotations: the AVX2 path on a processor without AVX2");
    if (A.size() < q.size())
        throw InputError("extractRotations: " + std::to_string(q.size()) + " rotations but only " +
                         std::to_string(A.size()) + " matrices");
    for (size_t first = 0; first < q.size(); first += kRotationLanes) {
        const int count = int(std::min(q.size() - first, size_t(kRotationLanes)));
        RotationLanes f; // unused lanes: a fit with nothing to fit
        for (int l = 0; l < count; ++l) f.set(l, A[first + l], q[first + l]);
        fitRotations(f, count, maxIterations, tolerance, newtonStop, path);
        for (int l = 0; l < count; ++l) q[first + l] = f.answer(l);
    }
}

} // namespace shatter::oriented
