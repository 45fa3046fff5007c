#pragma once
// The one way settings check themselves. Every settings struct has
//     void check(const std::string& body) const;
// which throws shatter::InputError naming the body, the field, the rule and the value:
//     body 'door': friction must be >= 0 and finite, got -1
// `field` is the setting's name in words (as a user reads it in the struct's comments).
#include <shatter/plugin/common/InputError.h>

#include <cmath>
#include <sstream>
#include <string>

namespace shatter {

[[noreturn]] inline void rejectSetting(const std::string& body, const std::string& field, const std::string& rule,
                                       double value) {
    std::ostringstream msg;
    msg << "body '" << body << "': " << field << " must be " << rule << ", got " << value;
    throw InputError(msg.str());
}

inline void requireSetting(bool ok, const std::string& body, const std::string& field, const std::string& rule,
                           double value) {
    if (!ok) rejectSetting(body, field, rule, value);
}

// > 0 and finite.
inline void requirePositive(const std::string& body, const std::string& field, double value) {
    requireSetting(std::isfinite(value) && value > 0.0, body, field, "positive and finite", value);
}

// >= 0 and finite.
inline void requireNonNegative(const std::string& body, const std::string& field, double value) {
    requireSetting(std::isfinite(value) && value >= 0.0, body, field, ">= 0 and finite", value);
}

// In [lowest, highest].
inline void requireWithin(const std::string& body, const std::string& field, double value, double lowest,
                          double highest) {
    std::ostringstream rule;
    rule << "in [" << lowest << ", " << highest << "]";
    requireSetting(value >= lowest && value <= highest, body, field, rule.str(), value);
}

// An integer count of at least `lowest`.
inline void requireAtLeast(const std::string& body, const std::string& field, long long value, long long lowest) {
    requireSetting(value >= lowest, body, field, ">= " + std::to_string(lowest), double(value));
}

} // namespace shatter
