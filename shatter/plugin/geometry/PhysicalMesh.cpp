#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <shatter/plugin/common/SettingCheck.h>

namespace shatter::geometry {

void PhysicalMeshSettings::check(const std::string& body) const {
    const std::string orDefault = "positive and finite (or 0 for the default)";
    requireSetting(std::isfinite(thickness) && thickness >= 0.0, body, "thickness", orDefault, thickness);
    requirePositive(body, "density", density);
    requireSetting(std::isfinite(contactTolerance) && contactTolerance >= 0.0, body, "contact tolerance", orDefault,
                   contactTolerance);
}

} // namespace shatter::geometry
