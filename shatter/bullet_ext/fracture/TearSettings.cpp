#include <shatter/bullet_ext/fracture/TearSettings.h>

#include <shatter/plugin/common/SettingCheck.h>

namespace shatter {

void TearSettings::check(const std::string& body) const {
    if (!enabled) return;
    requirePositive(body, "tear distance", distance);
}

} // namespace shatter
