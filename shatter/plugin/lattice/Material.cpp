#include <shatter/plugin/lattice/Material.h>

#include <shatter/plugin/common/InputError.h>

#include <cmath>
#include <sstream>

namespace shatter::lattice {

Material adobe() { return {"adobe", 1700.0, 2.0e5, 4.0}; }
Material brick() { return {"brick", 1900.0, 1.5e6, 8.0}; }
Material concrete() { return {"concrete", 2400.0, 3.0e6, 10.0}; }
Material glass() { return {"glass", 2500.0, 2.5e5, 10.0}; }
Material ceramic() { return {"ceramic", 2400.0, 3.0e5, 10.0}; }

std::vector<std::string> materialNames() { return {"adobe", "brick", "concrete", "glass", "ceramic"}; }

Material materialNamed(const std::string& name) {
    for (const Material& m : {adobe(), brick(), concrete(), glass(), ceramic()})
        if (m.name == name) return m;
    std::string names;
    for (const auto& n : materialNames()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("material '" + name + "' is unknown (known: " + names + ")");
}

void validateMaterial(const Material& m, const std::string& body) {
    auto check = [&](double v, const char* what, const char* unit) {
        if (std::isfinite(v) && v > 0.0) return;
        std::ostringstream msg;
        msg << body << ": material '" << m.name << "' " << what << " must be positive and finite, got " << v << unit;
        throw InputError(msg.str());
    };
    check(m.density, "density", " kg/m^3");
    check(m.strength, "strength", " Pa");
    check(m.compressionRatio, "compression ratio", "");
}

} // namespace shatter::lattice
