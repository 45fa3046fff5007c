#include <shatter/plugin/lattice/BreakingRules.h>

#include <shatter/plugin/common/InputError.h>

#include <cmath>
#include <sstream>

namespace shatter::lattice {

double tensileEquivalent(double lambda, double compressionRatio) {
    return lambda < 0.0 ? -lambda : lambda / compressionRatio;
}

double linkUtilisation(const Link& link, double lambda, double compressionRatio) {
    const double force = tensileEquivalent(lambda, compressionRatio);
    return link.strength > 0.0 ? force / link.strength : (force > 0.0 ? INFINITY : 0.0);
}

void validateBreakingSettings(const BreakingSettings& s, const std::string& body) {
    auto fail = [&](const char* what, double v) {
        std::ostringstream msg;
        msg << body << ": breaking setting " << what << " is out of range (" << v << ")";
        throw InputError(msg.str());
    };
    if (!(s.weakeningOnset > 0.0 && s.weakeningOnset <= 1.0)) fail("weakening onset, must be in (0, 1],", s.weakeningOnset);
    if (!(s.removalFraction >= 0.0 && s.removalFraction < 1.0)) fail("removal fraction, must be in [0, 1),", s.removalFraction);
    if (s.maxRounds < 1) fail("max rounds, must be >= 1,", s.maxRounds);
}

} // namespace shatter::lattice
