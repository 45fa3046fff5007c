// Fill::Solid: a body whose faces form closed surfaces weighs density × the volume they
// enclose, carried by its primitives; Fill::Shell and open surfaces keep the extruded shell.
// Every volume here is computed by the test itself (closed forms, or the divergence theorem
// over the input triangles), not by geometry::MassProperties.
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include "MeshFixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

using namespace shatter::geometry;
using shatter::test::FaceMesh;

namespace {

// Divergence theorem: Σ over a fan of each face of (a · (b × c)) / 6, about the origin.
double enclosedVolume(const std::vector<Eigen::Vector3d>& p, const std::vector<std::vector<int>>& faces) {
    double v = 0.0;
    for (const auto& f : faces)
        for (size_t k = 1; k + 1 < f.size(); ++k) v += p[f[0]].dot(p[f[k]].cross(p[f[k + 1]])) / 6.0;
    return v;
}

// What the fracture and lattice code sum: each primitive's mass at the body's density.
double primitiveMass(const PhysicalMesh& mesh) {
    double m = 0.0;
    for (const auto& p : mesh.primitives) m += p.massProperties(mesh.density).mass;
    return m;
}

// An L-shaped prism: the L of a 2 × 2 square less its 1 × 1 corner (area 3), height h;
// closed, outward, not convex (area × h = 3h).
FaceMesh lPrism(double h) {
    const double xy[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    FaceMesh m;
    for (double z : {0.0, h})
        for (const auto& c : xy) m.positions.emplace_back(c[0], c[1], z);
    m.faces.push_back({5, 4, 3, 2, 1, 0}); // bottom, seen from below
    m.faces.push_back({6, 7, 8, 9, 10, 11});
    for (int i = 0; i < 6; ++i) m.faces.push_back({i, (i + 1) % 6, 6 + (i + 1) % 6, 6 + i});
    return m;
}

// Icosahedron subdivided `levels` times onto the unit sphere, scaled by r; with dent < 1
// the 12 original vertices are pulled in to dent × r (a closed, non-convex, star-shaped
// surface).
FaceMesh icosphere(double r, int levels, double dent = 1.0) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    FaceMesh m;
    for (const auto& v : {Eigen::Vector3d(-1, t, 0), Eigen::Vector3d(1, t, 0), Eigen::Vector3d(-1, -t, 0),
                          Eigen::Vector3d(1, -t, 0), Eigen::Vector3d(0, -1, t), Eigen::Vector3d(0, 1, t),
                          Eigen::Vector3d(0, -1, -t), Eigen::Vector3d(0, 1, -t), Eigen::Vector3d(t, 0, -1),
                          Eigen::Vector3d(t, 0, 1), Eigen::Vector3d(-t, 0, -1), Eigen::Vector3d(-t, 0, 1)})
        m.positions.push_back(v.normalized());
    m.faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
               {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
               {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<int, int>, int> middle;
        auto mid = [&](int a, int b) {
            auto [it, fresh] = middle.try_emplace({std::min(a, b), std::max(a, b)}, int(m.positions.size()));
            if (fresh) m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
            return it->second;
        };
        std::vector<std::vector<int>> finer;
        for (const auto& f : m.faces) {
            const int a = mid(f[0], f[1]), b = mid(f[1], f[2]), c = mid(f[2], f[0]);
            finer.insert(finer.end(), {{f[0], a, c}, {f[1], b, a}, {f[2], c, b}, {a, b, c}});
        }
        m.faces = std::move(finer);
    }
    for (size_t i = 0; i < m.positions.size(); ++i) m.positions[i] *= r * (i < 12 ? dent : 1.0);
    return m;
}

PhysicalMeshSettings withDensity(double rho, Fill fill = Fill::Solid) {
    PhysicalMeshSettings s;
    s.density = rho;
    s.fill = fill;
    return s;
}

} // namespace

// Mass round-off: sums of ~10⁴ polyhedron integrals, relative error ~1e-14; checked at 1e-12.
constexpr double kMassTolerance = 1e-12;

TEST(SolidFill, ClosedConvexCubeIsItsOwnSolidPrimitive) {
    const FaceMesh cube = shatter::test::closedBox({-0.2, 0.1, 0.3}, {0.3, 0.6, 0.8});
    const PhysicalMesh mesh = buildPhysicalMesh("cube", cube.positions, cube.faces, withDensity(2700));
    ASSERT_EQ(mesh.primitives.size(), 1u);
    EXPECT_EQ(mesh.density, 2700.0); // nothing extruded: the density is the one given
    EXPECT_NEAR(mesh.enclosedVolume, 0.125, kMassTolerance * 0.125);
    EXPECT_NEAR(mesh.mass.mass, 2700 * 0.125, kMassTolerance * 2700 * 0.125);
}

TEST(SolidFill, ConvexIcosphereWeighsItsEnclosedVolume) {
    const FaceMesh ball = icosphere(0.5, 2);
    const double volume = enclosedVolume(ball.positions, ball.faces);
    // The 320-face polyhedron is inside the sphere and close to it.
    EXPECT_LT(volume, 4.0 / 3.0 * M_PI * 0.125);
    EXPECT_GT(volume, 0.95 * 4.0 / 3.0 * M_PI * 0.125);
    const PhysicalMesh mesh = buildPhysicalMesh("ball", ball.positions, ball.faces, withDensity(1000));
    EXPECT_EQ(mesh.primitives.size(), 1u);
    EXPECT_NEAR(mesh.mass.mass, 1000 * volume, kMassTolerance * 1000 * volume);
}

TEST(SolidFill, NonConvexLPrismWeighsAreaTimesHeightNotItsShell) {
    const double h = 0.5, rho = 800, mass = rho * 3 * h;
    const FaceMesh l = lPrism(h);
    const PhysicalMesh solid = buildPhysicalMesh("L", l.positions, l.faces, withDensity(rho));
    EXPECT_GT(solid.primitives.size(), 8u); // extruded: not one convex primitive
    EXPECT_NEAR(solid.enclosedVolume, 3 * h, kMassTolerance * 3 * h);
    EXPECT_NEAR(solid.mass.mass, mass, kMassTolerance * mass);
    EXPECT_NEAR(primitiveMass(solid), mass, kMassTolerance * mass);
    // The shell it was before: lighter, at the density given, enclosing nothing.
    const PhysicalMesh shell = buildPhysicalMesh("L", l.positions, l.faces, withDensity(rho, Fill::Shell));
    EXPECT_EQ(shell.density, rho);
    EXPECT_EQ(shell.enclosedVolume, 0.0);
    EXPECT_LT(shell.mass.mass, 0.5 * mass);
    EXPECT_EQ(shell.primitives.size(), solid.primitives.size());
    EXPECT_NEAR(solid.density / rho, mass / shell.mass.mass, 1e-12 * solid.density / rho);
}

TEST(SolidFill, DentedIcosphereWeighsItsEnclosedVolume) {
    const FaceMesh ball = icosphere(0.5, 2, 0.7);
    const double volume = enclosedVolume(ball.positions, ball.faces);
    const PhysicalMesh mesh = buildPhysicalMesh("dented", ball.positions, ball.faces, withDensity(1000));
    EXPECT_EQ(mesh.primitives.size(), ball.faces.size()); // not convex: a prism per face
    EXPECT_NEAR(mesh.mass.mass, 1000 * volume, kMassTolerance * 1000 * volume);
    EXPECT_NEAR(primitiveMass(mesh), 1000 * volume, kMassTolerance * 1000 * volume);
}

TEST(SolidFill, SpotTheCowWeighsDensityTimesItsDivergenceTheoremVolume) {
    const ObjFile file = loadObj(std::string(SHATTER_SOURCE_DIR) + "/demos/assets/spot.obj");
    std::vector<std::vector<int>> faces;
    for (const auto& object : file.objects)
        for (const auto& face : object.faces) faces.push_back(face.vertices);
    const double volume = enclosedVolume(file.positions, faces);
    EXPECT_NEAR(volume, 0.718, 0.001); // the figure of the issue 13 note
    const PhysicalObject object = buildPhysicalObject(file, withDensity(1000));
    ASSERT_EQ(object.bodies.size(), 1u);
    const PhysicalMesh& spot = object.bodies[0];
    EXPECT_EQ(spot.primitives.size(), 5856u);
    EXPECT_NEAR(spot.enclosedVolume, volume, kMassTolerance * volume);
    EXPECT_NEAR(spot.mass.mass, 1000 * volume, kMassTolerance * 1000 * volume);
    EXPECT_NEAR(primitiveMass(spot), 1000 * volume, kMassTolerance * 1000 * volume);
}

TEST(SolidFill, OpenSurfacesStayShells) {
    const FaceMesh grid = shatter::test::quadGrid(4, 3, 0.25);
    PhysicalMeshSettings s = withDensity(500);
    s.thickness = 0.01;
    const PhysicalMesh mesh = buildPhysicalMesh("sheet", grid.positions, grid.faces, s);
    EXPECT_EQ(mesh.density, 500.0);
    EXPECT_EQ(mesh.enclosedVolume, 0.0);
    EXPECT_NEAR(mesh.mass.mass, 500 * 1.0 * 0.75 * 0.01, 1e-12);
    // An L prism with its top missing is open too.
    FaceMesh l = lPrism(0.5);
    l.faces.erase(l.faces.begin() + 1);
    EXPECT_EQ(buildPhysicalMesh("open L", l.positions, l.faces, s).density, 500.0);
}

TEST(SolidFill, ASurfaceWoundInwardWeighsItsVolumeWithAWarning) {
    FaceMesh l = lPrism(0.5);
    for (auto& f : l.faces) std::reverse(f.begin(), f.end());
    const PhysicalMesh mesh = buildPhysicalMesh("inside-out", l.positions, l.faces, withDensity(1000));
    EXPECT_NEAR(mesh.mass.mass, 1500, kMassTolerance * 1500);
    ASSERT_EQ(mesh.warnings.size(), 1u);
    EXPECT_NE(mesh.warnings[0].find("wound inward"), std::string::npos) << mesh.warnings[0];
}

TEST(SolidFill, AFlatClosedSurfaceEnclosesNothingAndMustBeAShell) {
    // A tetrahedron flattened into its base plane: closed (every edge once each way) around
    // no volume, the way a card modelled on both sides with a fold is.
    FaceMesh sheet;
    sheet.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    sheet.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    try {
        buildPhysicalMesh("card", sheet.positions, sheet.faces, withDensity(1000));
        FAIL() << "a zero-volume solid was accepted";
    } catch (const shatter::InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("body 'card'"), std::string::npos) << what;
        EXPECT_NE(what.find("encloses no volume"), std::string::npos) << what;
        EXPECT_NE(what.find("--fill shell"), std::string::npos) << what;
    }
    EXPECT_GT(buildPhysicalMesh("card", sheet.positions, sheet.faces, withDensity(1000, Fill::Shell)).mass.mass, 0.0);
    EXPECT_EQ(fillNamed("shell"), Fill::Shell);
    EXPECT_THROW(fillNamed("hollow"), shatter::InputError);
}
