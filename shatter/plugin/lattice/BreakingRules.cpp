#include <shatter/plugin/lattice/BreakingRules.h>

#include <shatter/plugin/common/SettingCheck.h>

#include <cmath>
#include <sstream>

namespace shatter::lattice {

void BreakingSettings::check(const std::string& body) const {
    requireSetting(weakeningOnset > 0.0 && weakeningOnset <= 1.0, body, "weakening onset", "in (0, 1]", weakeningOnset);
    requireSetting(removalFraction >= 0.0 && removalFraction < 1.0, body, "removal fraction", "in [0, 1)", removalFraction);
    requireAtLeast(body, "max rounds", maxRounds, 1);
}

} // namespace shatter::lattice
