#include <shatter/plugin/mpm/Diagnostics.h>

#include <shatter/plugin/mpm/BSpline.h>

namespace shatter::mpm {

Totals totals(const Solver2D& solver) {
    const Particles& P = solver.particles();
    const Vec2 g = solver.scene().gravity;
    const double inertia = 1 / apicInverseInertia(solver.scene().grid.kernel) * solver.scene().grid.dx *
                           solver.scene().grid.dx; // D = dx²/3 or dx²/4
    Totals t;
    for (size_t p = 0; p < P.size(); ++p) {
        const double m = P.mass[p];
        t.mass += m;
        t.momentum += m * P.v[p];
        t.centreOfMass += m * P.x[p];
        // A particle's APIC affine field carries spin m·D·(C₁₀ − C₀₁).
        t.angularMomentum += m * (P.x[p].x() * P.v[p].y() - P.x[p].y() * P.v[p].x()) +
                             m * inertia * (P.C[p](1, 0) - P.C[p](0, 1));
        t.kinetic += 0.5 * m * P.v[p].squaredNorm();
        t.elastic += P.volume0[p] * solver.energyDensity(p);
        t.gravitational -= m * g.dot(P.x[p]);
    }
    t.centreOfMass /= t.mass;
    return t;
}

double gridMass(const Solver2D& solver) {
    const Grid& g = solver.state().grid;
    double m = 0;
    for (int f = 0; f < g.fields; ++f)
        for (const Grid::Node& n : g.node[size_t(f)]) m += n.mass;
    return m;
}

} // namespace shatter::mpm
