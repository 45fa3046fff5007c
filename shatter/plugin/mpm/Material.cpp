#include <shatter/plugin/mpm/Material.h>

namespace shatter::mpm {

double Material::lameLambda(Analysis analysis) const {
    if (analysis == Analysis::PlaneStress) return E * nu / (1 - nu * nu);
    return E * nu / ((1 + nu) * (1 - 2 * nu));
}

double Material::effectiveModulus(Analysis analysis) const {
    return analysis == Analysis::PlaneStress ? E : E / (1 - nu * nu);
}

double Material::kolosov(Analysis analysis) const {
    return analysis == Analysis::PlaneStress ? (3 - nu) / (1 + nu) : 3 - 4 * nu;
}

std::optional<Material> materialPreset(std::string_view name) {
    Material m;
    m.name = std::string(name);
    if (name == "snow") {
        m.model = ConstitutiveModelType::Snow;
        m.E = 140e3, m.nu = 0.2, m.rho = 400, m.Kc = 10;
    } else if (name == "pmma") {
        m.E = 2.94e9, m.nu = 0.3, m.rho = 1190, m.Kc = 1.2e6;
    } else if (name == "glass") {
        m.E = 70e9, m.nu = 0.22, m.rho = 2500, m.Kc = 0.75e6;
    } else if (name == "jello") {
        m.E = 50, m.nu = 0.4, m.rho = 2, m.Kc = 10;
    } else {
        return std::nullopt;
    }
    return m;
}

} // namespace shatter::mpm
