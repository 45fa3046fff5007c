#include <shatter/plugin/mpm/StressIntensity.h>

#include <algorithm>
#include <cmath>

namespace shatter::mpm {

CrackOpening crackOpeningNearTip(const Crack& crack, int tip, double range) {
    const size_t n = crack.points.size();
    const Vec2 t = crack.tipDirection(tip);
    const Vec2 normal = leftNormal(t);
    // For the end tip the polyline's left ("above") is the tip's upper face; for the start
    // tip the polyline runs the other way, so its "below" face is the upper one.
    const double sign = tip == 1 ? 1.0 : -1.0;
    double s = 0, sumS = 0, sumI = 0, sumII = 0;
    for (size_t k = 1; k < n; ++k) {
        const size_t i = tip == 1 ? n - 1 - k : k;
        const size_t prev = tip == 1 ? i + 1 : i - 1;
        s += (crack.points[i] - crack.points[prev]).norm();
        if (s > range * (1 + 1e-9)) break;
        const Vec2 gap = sign * (crack.above[i] - crack.below[i]);
        const double root = std::sqrt(s);
        sumS += s;
        sumI += gap.dot(normal) * root;
        sumII += gap.dot(t) * root;
    }
    CrackOpening out;
    if (sumS <= 0) return out;
    out.opening = sumI / sumS;
    out.sliding = sumII / sumS;
    out.valid = true;
    return out;
}

StressIntensity stressIntensity(double J, const CrackOpening& opening, double effectiveModulus) {
    StressIntensity k;
    if (!(J > 0)) return k;
    const double magnitude = std::sqrt(J * effectiveModulus);
    const double delta = std::hypot(opening.opening, opening.sliding);
    if (!opening.valid || delta <= 0) {
        k.KI = magnitude;
        return k;
    }
    k.KI = opening.opening / delta * magnitude;
    k.KII = opening.sliding / delta * magnitude;
    return k;
}

StressIntensity stressIntensityFromInteraction(double J, double KIinteraction, double KIIinteraction,
                                               double effectiveModulus) {
    StressIntensity k;
    if (!(J > 0)) return k;
    const double magnitude = std::sqrt(J * effectiveModulus);
    const double psi = KIinteraction == 0 && KIIinteraction == 0 ? 0.0 : std::atan2(KIIinteraction, KIinteraction);
    k.KI = magnitude * std::cos(psi);
    k.KII = magnitude * std::sin(psi);
    return k;
}

} // namespace shatter::mpm
