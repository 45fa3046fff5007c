#include <shatter/plugin/oriented/SolverSettings.h>

#include <shatter/plugin/common/InputError.h>

#include <cmath>
#include <sstream>

namespace shatter::oriented {

namespace {

[[noreturn]] void reject(const std::string& object, const char* what, double value, const char* range) {
    std::ostringstream msg;
    msg << "object '" << object << "': " << what << " must be " << range << ", got " << value;
    throw InputError(msg.str());
}

} // namespace

void SolverSettings::check(const std::string& object) const {
    if (!(stiffness >= 0.0 && stiffness <= 1.0)) reject(object, "stiffness", stiffness, "in [0, 1]");
    if (iterations < 1) reject(object, "iterations", iterations, ">= 1");
    if (rotationIterations < 1) reject(object, "rotation iterations", rotationIterations, ">= 1");
    if (!(std::isfinite(damping) && damping >= 0.0)) reject(object, "damping", damping, "finite and >= 0 (1/s)");
    if (!(std::isfinite(epsilon) && epsilon >= 0.0)) reject(object, "epsilon", epsilon, "finite and >= 0 (rad)");
    if (!gravity.allFinite()) reject(object, "gravity", gravity.norm(), "finite (m/s²)");
}

} // namespace shatter::oriented
