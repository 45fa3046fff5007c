// Mass properties and visual data of built physical meshes against closed forms.
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include "MeshFixtures.h"

#include <gtest/gtest.h>

using namespace shatter::geometry;
using shatter::test::FaceMesh;

namespace {

// Solid box a × b × c of mass m about its centre: m/12 (b²+c², a²+c², a²+b²).
Eigen::Matrix3d boxInertia(double m, double a, double b, double c) {
    return Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b).asDiagonal() * (m / 12.0);
}

} // namespace

TEST(PhysicalMeshMass, ClosedBoxMatchesClosedForm) {
    const double a = 0.4, b = 0.25, c = 0.1, rho = 2700.0;
    const FaceMesh m = shatter::test::closedBox({1, -1, 2}, {1 + a, -1 + b, 2 + c});
    PhysicalMeshSettings s;
    s.density = rho;
    const PhysicalMesh mesh = buildPhysicalMesh("block", m.positions, m.faces, s);
    const double mass = rho * a * b * c;
    // Exact polyhedron integrals: relative round-off ~1e-15, checked at 1e-12.
    EXPECT_NEAR(mesh.mass.mass, mass, 1e-12 * mass);
    EXPECT_NEAR(mesh.mass.volume, a * b * c, 1e-12 * a * b * c);
    EXPECT_LT((mesh.mass.centerOfMass - Eigen::Vector3d(1 + a / 2, -1 + b / 2, 2 + c / 2)).norm(), 1e-12);
    const Eigen::Matrix3d expected = boxInertia(mass, a, b, c);
    EXPECT_LT((mesh.mass.inertia - expected).norm(), 1e-12 * expected.norm());
    EXPECT_EQ(mesh.density, rho);
}

TEST(PhysicalMeshMass, ExtrudedPlateIsAreaTimesThicknessTimesDensity) {
    const int nx = 8, ny = 5;
    const double cell = 0.125, t = 0.02, rho = 500.0;
    const FaceMesh grid = shatter::test::quadGrid(nx, ny, cell);
    PhysicalMeshSettings s;
    s.thickness = t;
    s.density = rho;
    const PhysicalMesh mesh = buildPhysicalMesh("plate", grid.positions, grid.faces, s);
    const double a = nx * cell, b = ny * cell;
    const double mass = a * b * t * rho;
    EXPECT_NEAR(mesh.mass.mass, mass, 1e-12 * mass);
    // The prisms tile the plate below the surface (z from -t to 0) without overlap, so the
    // sum is the solid plate.
    EXPECT_LT((mesh.mass.centerOfMass - Eigen::Vector3d(a / 2, b / 2, -t / 2)).norm(), 1e-12);
    const Eigen::Matrix3d expected = boxInertia(mass, a, b, t);
    EXPECT_LT((mesh.mass.inertia - expected).norm(), 1e-12 * expected.norm());
}

TEST(PhysicalMeshVisual, KeepsInputPositionsFacesAndIds) {
    const FaceMesh grid = shatter::test::quadGrid(3, 2, 0.5);
    const PhysicalMesh mesh = buildPhysicalMesh("g", grid.positions, grid.faces);
    EXPECT_EQ(mesh.name, "g");
    EXPECT_EQ(mesh.visual.positions, grid.positions);
    EXPECT_EQ(mesh.visual.faces, grid.faces);
    const int n = int(grid.positions.size());
    EXPECT_EQ(mesh.globalIdCount, 2 * n);
    // Visual ids on top, inner ids below, each inner vertex exactly under its visual one.
    for (const auto& p : mesh.primitives)
        for (size_t k = 0; k < p.vertices().size(); ++k) {
            const int id = p.globalIds()[k];
            ASSERT_GE(id, 0);
            ASSERT_LT(id, 2 * n);
            const Eigen::Vector3d expected = id < n ? grid.positions[id] : Eigen::Vector3d(grid.positions[id - n] - mesh.thickness * Eigen::Vector3d::UnitZ());
            EXPECT_EQ(p.vertices()[k], expected);
        }
    EXPECT_TRUE(mesh.warnings.empty());
}

TEST(PhysicalMeshVisual, ClosedPartsAndExtrudedFacesMix) {
    // A closed box standing on an open plate: the box is one primitive, the plate's quads
    // are prisms, and they are connected where the box rests on the plate.
    FaceMesh m = shatter::test::quadGrid(2, 2, 1.0);
    shatter::test::append(m, shatter::test::closedBox({0.5, 0.5, 0.0}, {1.5, 1.5, 1.0}));
    const PhysicalMesh mesh = buildPhysicalMesh("mix", m.positions, m.faces);
    ASSERT_EQ(mesh.primitives.size(), 5u);
    EXPECT_EQ(mesh.sourceFace, (std::vector<int>{0, 1, 2, 3, -1}));
    EXPECT_EQ(mesh.globalIdCount, 2 * 17);
    int boxContacts = 0;
    for (const auto& [a, b] : mesh.connections)
        if (b == 4) ++boxContacts;
    EXPECT_EQ(boxContacts, 4);
    EXPECT_EQ(mesh.componentCount(), 1);
}

TEST(PhysicalMeshUnits, AMeshInMillimetresIsTheSameBodyAsInMetres) {
    // A 400 × 250 × 100 mm block read in millimetres weighs what the 0.4 × 0.25 × 0.1 m one
    // does; a scale of 2 on top makes it 8 times heavier; thickness stays in metres.
    const FaceMesh metres = shatter::test::closedBox({0, 0, 0}, {0.4, 0.25, 0.1});
    const FaceMesh millimetres = shatter::test::closedBox({0, 0, 0}, {400, 250, 100});
    PhysicalMeshSettings s;
    s.density = 1000.0;
    const double mass = buildPhysicalMesh("m", metres.positions, metres.faces, s).mass.mass;
    s.units = LengthUnit::Millimetres;
    const PhysicalMesh mm = buildPhysicalMesh("mm", millimetres.positions, millimetres.faces, s);
    EXPECT_NEAR(mm.mass.mass, mass, 1e-12 * mass);
    EXPECT_NEAR(mm.visual.positions.back().norm(), metres.positions.back().norm(), 1e-15);
    s.scale = 2.0;
    EXPECT_NEAR(buildPhysicalMesh("mm2", millimetres.positions, millimetres.faces, s).mass.mass, 8 * mass, 8e-12 * mass);
    s.scale = 0.0;
    EXPECT_THROW(buildPhysicalMesh("zero", millimetres.positions, millimetres.faces, s), shatter::InputError);
    EXPECT_EQ(lengthUnitNamed("cm"), LengthUnit::Centimetres);
    EXPECT_THROW(lengthUnitNamed("inch"), shatter::InputError);
}

TEST(PhysicalMeshUnits, JointBoxesScaleWithTheirBodies) {
    // Two planks on a hinge box, authored in centimetres: the joint box must still hold the
    // primitives at the planks' ends once both are in metres.
    const FaceMesh planks = shatter::test::closedBox({-70, -2, -8}, {0, 2, 8});
    std::string text = shatter::test::objText(planks, "a");
    text += shatter::test::objText(shatter::test::closedBox({0, -2, -8}, {70, 2, 8}), "b", 9);
    text += shatter::test::objText(shatter::test::closedBox({-1.5, -2.5, -9}, {1.5, 2.5, 9}), "joint.hinge.a.b", 17);
    PhysicalMeshSettings s;
    s.units = LengthUnit::Centimetres;
    const PhysicalObject object = buildPhysicalObject(shatter::geometry::parseObj(text, "planks.obj"), s);
    ASSERT_EQ(object.joints.size(), 1u);
    EXPECT_EQ(object.joints[0].attachmentsA.size(), 1u);
    EXPECT_EQ(object.joints[0].attachmentsB.size(), 1u);
    EXPECT_NEAR(object.joints[0].halfExtents.maxCoeff(), 0.09, 1e-12);
    EXPECT_NEAR(object.bodies[0].mass.volume, 0.7 * 0.04 * 0.16, 1e-12);
}
