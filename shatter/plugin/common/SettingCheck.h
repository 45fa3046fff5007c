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
#include <string_view>

namespace shatter {

// The names and rules are views, not strings: a check is called with literals, and a
// std::string parameter made (and, past 15 characters, allocated) one per call even when the
// value passes (a fracture's ~28 new bodies checked their settings for ~0.15 M instructions).
[[noreturn]] inline void rejectSetting(std::string_view body, std::string_view field, std::string_view rule,
                                       double value) {
    std::ostringstream msg;
    msg << "body '" << body << "': " << field << " must be " << rule << ", got " << value;
    throw InputError(msg.str());
}

inline void requireSetting(bool ok, std::string_view body, std::string_view field, std::string_view rule,
                           double value) {
    if (!ok) rejectSetting(body, field, rule, value);
}

// > 0 and finite.
inline void requirePositive(std::string_view body, std::string_view field, double value) {
    requireSetting(std::isfinite(value) && value > 0.0, body, field, "positive and finite", value);
}

// >= 0 and finite.
inline void requireNonNegative(std::string_view body, std::string_view field, double value) {
    requireSetting(std::isfinite(value) && value >= 0.0, body, field, ">= 0 and finite", value);
}

// In [lowest, highest]. The rule's words are made only for the message.
inline void requireWithin(std::string_view body, std::string_view field, double value, double lowest,
                          double highest) {
    if (value >= lowest && value <= highest) return;
    std::ostringstream rule;
    rule << "in [" << lowest << ", " << highest << "]";
    rejectSetting(body, field, rule.str(), value);
}

// An integer count of at least `lowest`. The rule's words are made only for the message.
inline void requireAtLeast(std::string_view body, std::string_view field, long long value, long long lowest) {
    if (value < lowest) rejectSetting(body, field, ">= " + std::to_string(lowest), double(value));
}

} // namespace shatter
