#include <shatter/plugin/mpm/HoopStress.h>

#include <algorithm>
#include <cmath>

namespace shatter::mpm {

double kinkAngle(double KI, double KII) {
    if (KII == 0) return 0;
    const double kI = std::max(KI, 0.0);
    // The cosine form is free of the 0/0 of the tangent form at K_II → 0 and at K_I = 0.
    const double c = (3 * KII * KII + kI * std::sqrt(kI * kI + 8 * KII * KII)) / (kI * kI + 9 * KII * KII);
    const double theta = std::acos(std::clamp(c, -1.0, 1.0));
    return KII > 0 ? -theta : theta;
}

double effectiveStressIntensity(double KI, double KII, double theta) {
    const double c = std::cos(0.5 * theta);
    return KI * c * c * c - 1.5 * KII * c * std::sin(theta);
}

} // namespace shatter::mpm
