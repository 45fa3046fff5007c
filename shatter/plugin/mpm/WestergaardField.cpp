#include <shatter/plugin/mpm/WestergaardField.h>

#include <cmath>
#include <complex>
#include <numbers>

namespace shatter::mpm {

namespace {

using C = std::complex<double>;

// √(z² − a²) with its cut on the crack [−a, a] and ~z far away.
C root(C z, double a) { return std::sqrt(z - a) * std::sqrt(z + a); }

} // namespace

double WestergaardField::KI() const { return sigma * std::sqrt(std::numbers::pi * a); }
double WestergaardField::KII() const { return tau * std::sqrt(std::numbers::pi * a); }

WestergaardField::State WestergaardField::at(double x, double y) const {
    const C z(x, y);
    const C s = root(z, a);
    const C unit = z / s;                         // Z/load
    const C unitPrime = -a * a / (s * s * s);     // Z'/load
    const C unitBar = s;                          // ∫Z/load
    const double mu = E / (2 * (1 + nu));
    const double kappa = analysis == Analysis::PlaneStress ? (3 - nu) / (1 + nu) : 3 - 4 * nu;
    State out;
    // Mode I (Z = σ·unit): σxx = Re Z − y Im Z', σyy = Re Z + y Im Z', σxy = −y Re Z'.
    const C Z1 = sigma * unit, Z1p = sigma * unitPrime, Z1b = sigma * unitBar;
    // Mode II (Z = τ·unit): σxx = 2 Im Z + y Re Z', σyy = −y Re Z', σxy = Re Z − y Im Z'.
    const C Z2 = tau * unit, Z2p = tau * unitPrime, Z2b = tau * unitBar;
    const double sxx = Z1.real() - y * Z1p.imag() + 2 * Z2.imag() + y * Z2p.real();
    const double syy = Z1.real() + y * Z1p.imag() - y * Z2p.real();
    const double sxy = -y * Z1p.real() + Z2.real() - y * Z2p.imag();
    out.stress << sxx, sxy, sxy, syy;
    // Displacements: 2μ u_x = (κ−1)/2 Re Z̄ − y Im Z (+ mode II: (κ+1)/2 Im Z̄ + y Re Z),
    //                2μ u_y = (κ+1)/2 Im Z̄ − y Re Z (+ mode II: −(κ−1)/2 Re Z̄ − y Im Z).
    const double ux = (0.5 * (kappa - 1) * Z1b.real() - y * Z1.imag() + 0.5 * (kappa + 1) * Z2b.imag() + y * Z2.real());
    const double uy = (0.5 * (kappa + 1) * Z1b.imag() - y * Z1.real() - 0.5 * (kappa - 1) * Z2b.real() - y * Z2.imag());
    out.u = Vec2(ux, uy) / (2 * mu);
    // Their derivatives, using d/dx = d/dz and d/dy = i·d/dz on analytic functions.
    const double uxx = 0.5 * (kappa - 1) * Z1.real() - y * Z1p.imag() + 0.5 * (kappa + 1) * Z2.imag() + y * Z2p.real();
    const double uxy = -0.5 * (kappa + 1) * Z1.imag() - y * Z1p.real() + 0.5 * (kappa + 3) * Z2.real() - y * Z2p.imag();
    const double uyx = 0.5 * (kappa + 1) * Z1.imag() - y * Z1p.real() - 0.5 * (kappa - 1) * Z2.real() - y * Z2p.imag();
    const double uyy = 0.5 * (kappa - 1) * Z1.real() + y * Z1p.imag() + 0.5 * (kappa - 3) * Z2.imag() - y * Z2p.real();
    out.gradU << uxx, uxy, uyx, uyy;
    out.gradU /= 2 * mu;
    return out;
}

} // namespace shatter::mpm
