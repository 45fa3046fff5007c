#pragma once
// Small scenes built in code for the MPM tests.
#include <shatter/plugin/mpm/Scene.h>

#include <memory>

namespace shatter::mpm::test {

inline Material elastic(ConstitutiveModelType model, double E, double nu, double rho) {
    Material m;
    m.name = "test";
    m.model = model;
    m.E = E;
    m.nu = nu;
    m.rho = rho;
    return m;
}

inline Scene baseScene(double dx, const Material& material) {
    Scene s;
    s.grid.dx = dx;
    s.grid.ppc = 2;
    s.materials.push_back(material);
    return s;
}

inline Scene diskScene(double dx, const Material& material, Vec2 centre, double radius, Vec2 velocity) {
    Scene s = baseScene(dx, material);
    s.bodies.push_back(Body{Shape(CircleShape{centre, radius}), 0, velocity});
    return s;
}

inline std::shared_ptr<const Collider> ground(double y = 0) {
    return std::make_shared<HalfPlaneCollider>(Vec2(0, y), Vec2(0, 1));
}

} // namespace shatter::mpm::test
