#include <shatter/plugin/lattice/MaterialSettings.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/common/SettingCheck.h>


namespace shatter::lattice {

MaterialSettings adobe() { return {"adobe", 1700.0, 2.0e5, 4.0}; }
MaterialSettings brick() { return {"brick", 1900.0, 1.5e6, 8.0}; }
MaterialSettings concrete() { return {"concrete", 2400.0, 3.0e6, 10.0}; }
MaterialSettings glass() { return {"glass", 2500.0, 2.5e5, 10.0}; }
MaterialSettings ceramic() { return {"ceramic", 2400.0, 3.0e5, 10.0}; }

std::vector<std::string> materialNames() { return {"adobe", "brick", "concrete", "glass", "ceramic"}; }

MaterialSettings materialNamed(const std::string& name) {
    for (const MaterialSettings& m : {adobe(), brick(), concrete(), glass(), ceramic()})
        if (m.name == name) return m;
    std::string names;
    for (const auto& n : materialNames()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("material '" + name + "' is unknown (known: " + names + ")");
}

void MaterialSettings::check(const std::string& body) const {
    const std::string material = "material '" + name + "' ";
    requirePositive(body, material + "density", density);
    requirePositive(body, material + "strength", strength);
    requirePositive(body, material + "compression ratio", compressionRatio);
}

} // namespace shatter::lattice
