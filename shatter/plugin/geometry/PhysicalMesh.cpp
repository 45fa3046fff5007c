#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <shatter/plugin/common/SettingCheck.h>

namespace shatter::geometry {

double metresPer(LengthUnit unit) {
    switch (unit) {
    case LengthUnit::Centimetres: return 0.01;
    case LengthUnit::Millimetres: return 0.001;
    case LengthUnit::Metres: break;
    }
    return 1.0;
}

LengthUnit lengthUnitNamed(const std::string& name) {
    if (name == "m") return LengthUnit::Metres;
    if (name == "cm") return LengthUnit::Centimetres;
    if (name == "mm") return LengthUnit::Millimetres;
    throw InputError("length unit '" + name + "' is unknown (known: m, cm, mm)");
}

void PhysicalMeshSettings::check(const std::string& body) const {
    requirePositive(body, "scale", scale);
    const std::string orDefault = "positive and finite (or 0 for the default)";
    requireSetting(std::isfinite(thickness) && thickness >= 0.0, body, "thickness", orDefault, thickness);
    requirePositive(body, "density", density);
    requireSetting(std::isfinite(contactTolerance) && contactTolerance >= 0.0, body, "contact tolerance", orDefault,
                   contactTolerance);
    requireAtLeast(body, "maxPrimitives", maxPrimitives, 1);
    requireAtLeast(body, "maxOverlapsPerPrimitive", maxOverlapsPerPrimitive, 1);
}

Fill fillNamed(const std::string& name) {
    if (name == "solid") return Fill::Solid;
    if (name == "shell") return Fill::Shell;
    throw InputError("fill '" + name + "' is unknown (known: solid, shell)");
}

} // namespace shatter::geometry
