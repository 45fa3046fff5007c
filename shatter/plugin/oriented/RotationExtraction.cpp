#include <shatter/plugin/oriented/RotationExtraction.h>

#include <cmath>

namespace shatter::oriented {

namespace {

// K fits as lanes (struct of arrays): every stage below is a loop over the lanes with no
// dependence between them, so the K dependent chains of a fit overlap in the processor and
// a stage's arithmetic can be packed into SIMD instructions. The arithmetic of a lane does
// not depend on K: one fit alone (K = 1, extractRotation) gives the same bits as in a batch.
template <int K>
struct Lanes {
    double a[9][K]; // A(i, j) = a[3 i + j], not changed
    double w[K], x[K], y[K], z[K]; // the fit q, in and out
};

// One fit step per lane, as a rotation vector in the frame of R (step) that increases
// trace(RᵀA). With M = RᵀA, trace((R exp[θ])ᵀ A) ≈ trace M + θ·τ − ½ θᵀ H θ,
// τ = (M₂₁−M₁₂, M₀₂−M₂₀, M₁₀−M₀₁), H = trace(M) 𝟙 − sym(M). Near the answer H is positive
// definite and the Newton step H⁻¹τ converges quadratically (newton = true). Elsewhere (far
// away, or a rank-deficient A) Müller's step τ / |trace M| is used: it always increases the
// fit and is finite for any A. Both are computed for every lane and one is chosen (no branch
// to split the lanes).
template <int K>
void fitSteps(const Lanes<K>& f, double (&step)[3][K], bool (&newton)[K]) {
    double m[9][K];
    for (int l = 0; l < K; ++l) { // R of q (as Eigen's toRotationMatrix), then M = RᵀA
        const double tx = 2.0 * f.x[l], ty = 2.0 * f.y[l], tz = 2.0 * f.z[l];
        const double twx = tx * f.w[l], twy = ty * f.w[l], twz = tz * f.w[l];
        const double txx = tx * f.x[l], txy = ty * f.x[l], txz = tz * f.x[l];
        const double tyy = ty * f.y[l], tyz = tz * f.y[l], tzz = tz * f.z[l];
        const double r[9] = {1.0 - (tyy + tzz), txy - twz, txz + twy, //
                             txy + twz, 1.0 - (txx + tzz), tyz - twx, //
                             txz - twy, tyz + twx, 1.0 - (txx + tyy)};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                m[3 * i + j][l] = r[i] * f.a[j][l] + r[3 + i] * f.a[3 + j][l] + r[6 + i] * f.a[6 + j][l];
    }
    for (int l = 0; l < K; ++l) {
        const double t0 = m[7][l] - m[5][l], t1 = m[2][l] - m[6][l], t2 = m[3][l] - m[1][l];
        const double trace = m[0][l] + m[4][l] + m[8][l];
        // The size of M for the degeneracy floors: its entry-wise 1-norm, within a factor 3
        // of the Frobenius norm and without its square root.
        double scale = 0.0;
        for (int e = 0; e < 9; ++e) scale += std::abs(m[e][l]);
        // H positive definite when its three pivots are (the LLT's squared diagonal); solved
        // by its adjugate, a fraction of a factorisation's cost.
        const double h00 = trace - m[0][l], h11 = trace - m[4][l], h22 = trace - m[8][l];
        const double h01 = -0.5 * (m[1][l] + m[3][l]), h02 = -0.5 * (m[2][l] + m[6][l]),
                     h12 = -0.5 * (m[5][l] + m[7][l]);
        const double c00 = h11 * h22 - h12 * h12, c01 = h02 * h12 - h01 * h22, c02 = h01 * h12 - h02 * h11;
        const double c11 = h00 * h22 - h02 * h02, c12 = h01 * h02 - h00 * h12;
        const double minor2 = h00 * h11 - h01 * h01;
        const double det = h00 * c00 + h01 * c01 + h02 * c02;
        const double floor = 1e-12 * scale;
        const double inverse = 1.0 / det;
        const double n0 = inverse * (c00 * t0 + c01 * t1 + c02 * t2);
        const double n1 = inverse * (c01 * t0 + c11 * t1 + c12 * t2);
        const double n2 = inverse * (c02 * t0 + c12 * t1 + minor2 * t2);
        // A squared length under 0.25 is also finite (an infinite or NaN step fails it).
        newton[l] = h00 > floor && minor2 > floor * h00 && det > floor * minor2 && n0 * n0 + n1 * n1 + n2 * n2 < 0.25;
        const double mueller = std::abs(trace) + 1e-9 * scale + 1e-300;
        step[0][l] = newton[l] ? n0 : t0 / mueller;
        step[1][l] = newton[l] ? n1 : t1 / mueller;
        step[2][l] = newton[l] ? n2 : t2 / mueller;
    }
}

template <int K>
void fit(Lanes<K>& f, int count, int maxIterations, double tolerance, double newtonStop) {
    bool running[K];
    for (int l = 0; l < K; ++l) {
        running[l] = l < count;
        // The warm start may be off unit by more than the renormalisation below repairs.
        const double norm = std::sqrt(f.w[l] * f.w[l] + f.x[l] * f.x[l] + f.y[l] * f.y[l] + f.z[l] * f.z[l]);
        f.w[l] /= norm, f.x[l] /= norm, f.y[l] /= norm, f.z[l] /= norm;
    }
    for (int iteration = 0; iteration < maxIterations; ++iteration) {
        bool any = false;
        for (int l = 0; l < K; ++l) any = any || running[l];
        if (!any) break;
        double step[3][K];
        bool newton[K];
        fitSteps(f, step, newton);
        // The turn by `step` as a quaternion t: below 0.05 rad by its series (relative error
        // under 1e-9; unit to that error, and renormalised with q below), which spares the
        // square root, sine and cosine; the rare larger turns exactly, lane by lane.
        double angle2[K], t[4][K];
        for (int l = 0; l < K; ++l) {
            angle2[l] = step[0][l] * step[0][l] + step[1][l] * step[1][l] + step[2][l] * step[2][l];
            const double half = 0.5 - angle2[l] / 48.0; // sin(θ/2)/θ ≈ 1/2 − θ²/48
            t[0][l] = 1.0 - angle2[l] / 8.0 + angle2[l] * angle2[l] / 384.0;
            for (int e = 0; e < 3; ++e) t[1 + e][l] = half * step[e][l];
        }
        for (int l = 0; l < K; ++l) {
            if (!(running[l] && angle2[l] >= 0.05 * 0.05)) continue;
            const double angle = std::sqrt(angle2[l]);
            const double sine = std::sin(0.5 * angle) / angle;
            t[0][l] = std::cos(0.5 * angle);
            for (int e = 0; e < 3; ++e) t[1 + e][l] = sine * step[e][l];
        }
        for (int l = 0; l < K; ++l) {
            // A lane stops without turning once its step is under the tolerance (also on
            // NaN), and after turning by a Newton step under newtonStop: that leaves an error
            // of order its square (warm-started fits mostly end there, after one evaluation).
            const bool turn = running[l] && angle2[l] > tolerance * tolerance;
            running[l] = turn && !(newton[l] && angle2[l] < newtonStop * newtonStop);
            // q t, renormalised by one Newton step of the inverse square root (|q t|² = 1 + ε,
            // exact to ε², without a square root or a division): unit to ~1e-18 each turn.
            const double w = f.w[l], x = f.x[l], y = f.y[l], z = f.z[l];
            const double tw = t[0][l], tx = t[1][l], ty = t[2][l], tz = t[3][l];
            const double pw = w * tw - x * tx - y * ty - z * tz;
            const double px = w * tx + x * tw + y * tz - z * ty;
            const double py = w * ty - x * tz + y * tw + z * tx;
            const double pz = w * tz + x * ty - y * tx + z * tw;
            const double unit = 1.5 - 0.5 * (pw * pw + px * px + py * py + pz * pz);
            f.w[l] = turn ? unit * pw : w;
            f.x[l] = turn ? unit * px : x;
            f.y[l] = turn ? unit * py : y;
            f.z[l] = turn ? unit * pz : z;
        }
    }
}

template <int K>
void load(Lanes<K>& f, int l, const Eigen::Matrix3d& A, const Eigen::Quaterniond& q) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) f.a[3 * i + j][l] = A(i, j);
    f.w[l] = q.w(), f.x[l] = q.x(), f.y[l] = q.y(), f.z[l] = q.z();
}

template <int K>
Eigen::Quaterniond answer(const Lanes<K>& f, int l) {
    return Eigen::Quaterniond(f.w[l], f.x[l], f.y[l], f.z[l]);
}

} // namespace

Eigen::Quaterniond extractRotation(const Eigen::Matrix3d& A, Eigen::Quaterniond q, int maxIterations,
                                   double tolerance, double newtonStop) {
    Lanes<1> f;
    load(f, 0, A, q);
    fit(f, 1, maxIterations, tolerance, newtonStop);
    return answer(f, 0);
}

void extractRotations(const Eigen::Matrix3d* A, Eigen::Quaterniond* q, int count, int maxIterations,
                      double tolerance, double newtonStop) {
    Lanes<kRotationLanes> f;
    for (int l = 0; l < kRotationLanes; ++l) // unused lanes: a fit with nothing to fit
        l < count ? load(f, l, A[l], q[l]) : load(f, l, Eigen::Matrix3d::Zero(), Eigen::Quaterniond::Identity());
    fit(f, count, maxIterations, tolerance, newtonStop);
    for (int l = 0; l < count; ++l) q[l] = answer(f, l);
}

} // namespace shatter::oriented
