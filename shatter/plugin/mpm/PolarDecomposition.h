#pragma once
// Closed-form 2x2 polar decomposition and SVD. Closed forms are exact to rounding, cheap
// (a few flops, one atan2-free normalisation) and branch-free for the common case, which
// matters because every particle needs one per substep.
#include <shatter/plugin/mpm/Types.h>

#include <cmath>

namespace shatter::mpm {

// The rotation R maximising tr(Rᵀ F): F = R S with S symmetric. For an inverted F (det < 0)
// R is still a proper rotation and S has one negative eigenvalue, which is what the
// fixed-corotated model needs to push an inverted particle back.
inline Mat2 polarRotation(const Mat2& F) {
    const double c = F(0, 0) + F(1, 1), s = F(1, 0) - F(0, 1);
    // sqrt rather than hypot: entries of F are O(1), and hypot's overflow care is slow.
    const double n = std::sqrt(c * c + s * s);
    Mat2 R;
    if (n < 1e-300) {
        R.setIdentity(); // F is a pure reflection-free shear of zero trace: any R is optimal
        return R;
    }
    R << c / n, -s / n, s / n, c / n;
    return R;
}

struct Svd2 {
    Mat2 U, V;     // rotations
    Vec2 sigma;    // F = U diag(sigma) Vᵀ, sigma(0) >= sigma(1), sigma(1) < 0 when det F < 0
};

inline Svd2 svd(const Mat2& F) {
    const Mat2 R = polarRotation(F);
    const Mat2 S = R.transpose() * F; // symmetric up to rounding
    const double a = S(0, 0), d = S(1, 1), b = 0.5 * (S(0, 1) + S(1, 0));
    // Eigenvectors of [[a b][b d]] are at angle φ with tan 2φ = 2b / (a − d).
    const double phi = 0.5 * std::atan2(2 * b, a - d);
    const double c = std::cos(phi), s = std::sin(phi);
    Svd2 out;
    out.V << c, -s, s, c;
    const double mean = 0.5 * (a + d), radius = std::hypot(0.5 * (a - d), b);
    out.sigma = Vec2(mean + radius, mean - radius);
    out.U = R * out.V;
    return out;
}

} // namespace shatter::mpm
