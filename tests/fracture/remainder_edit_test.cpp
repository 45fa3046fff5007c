// The rest of a body as an edit of it (CutSettings::remainderInPlace) must be the rest a full
// rebuild gives: same mass properties (to 1e-9), primitives, connections and surface.
#include "FractureFixtures.h"

#include <shatter/plugin/fracture/FractureMesh.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace shatter;
using namespace shatter::fracture;

namespace {

void expectSameMass(const geometry::MassProperties& a, const geometry::MassProperties& b, double size) {
    EXPECT_NEAR(a.mass, b.mass, 1e-9 * b.mass);
    EXPECT_NEAR(a.volume, b.volume, 1e-9 * b.volume);
    EXPECT_LT((a.centerOfMass - b.centerOfMass).norm(), 1e-9 * size);
    EXPECT_LT((a.inertia - b.inertia).norm(), 1e-9 * b.inertia.norm());
}

// Area of the visual faces, and of the crack faces among them.
std::pair<double, double> areas(const geometry::VisualMesh& visual) {
    double all = 0.0, crack = 0.0;
    for (size_t f = 0; f < visual.faces.size(); ++f) {
        const double a = 0.5 * geometry::newellNormal(visual.positions, visual.faces[f]).norm();
        all += a;
        if (visual.isCrackFace(f)) crack += a;
    }
    return {all, crack};
}

// Visual ids come first and sit where the primitive vertices carrying them are.
void expectVisualIdsFirstAndInPlace(const geometry::PhysicalMesh& mesh) {
    const int visual = int(mesh.visual.positions.size());
    for (const auto& face : mesh.visual.faces)
        for (int id : face) ASSERT_LT(id, visual);
    for (const auto& p : mesh.primitives)
        for (size_t v = 0; v < p.vertices().size(); ++v) {
            const int id = p.globalIds()[v];
            ASSERT_LT(id, mesh.globalIdCount);
            if (id < visual) {
                EXPECT_LT((p.vertices()[v] - mesh.visual.positions[size_t(id)]).norm(), 1e-12);
            }
        }
    test::expectShownIdsCarried(mesh, mesh.name);
}

struct Case {
    FractureResult full, edited;
    geometry::PhysicalMesh rest; // the body with the edit applied
};

Case fractureBothWays(const geometry::PhysicalMesh& body, const FracturePattern& pattern, const Placement& where) {
    CutSettings inPlace;
    inPlace.remainderInPlace = true;
    Case c{fractureMesh(body, pattern, where, CutSettings{}), fractureMesh(body, pattern, where, inPlace), body};
    if (c.edited.remainderEdit) applyRemainderEdit(c.rest, *c.edited.remainderEdit);
    return c;
}

} // namespace

TEST(RemainderEdit, TheRestEditedInPlaceIsTheRestRebuilt) {
    // A sheet of 30 × 30 quads hit in the middle by 24 Voronoi cells, then the rest hit again
    // near its new edge: both times the edited rest has the rebuilt rest's mass properties,
    // primitives, connections (one island) and surface (faces, areas, crack faces).
    const auto body = test::sheetBody(30, 30, 0.05, 0.01);
    const auto pattern = voronoiPattern({.cells = 24, .radius = 0.35}, 5);
    Placement where;
    where.point = {0.75, 0.75, 0.0};
    where.normal = {0.0, 0.0, -1.0};
    const Case once = fractureBothWays(body, pattern, where);
    ASSERT_TRUE(once.edited.remainderEdit);
    ASSERT_GE(once.full.remainder, 0);
    EXPECT_EQ(once.edited.remainder, -1);
    ASSERT_EQ(once.edited.pieces.size() + 1, once.full.pieces.size());
    const auto& rebuilt = once.full.pieces[size_t(once.full.remainder)];
    expectSameMass(once.rest.mass, rebuilt.mass, 1.5);
    // The subtracted mass is also the sum over the edited rest's own primitives.
    geometry::MassProperties summed;
    for (const auto& p : once.rest.primitives) summed += p.massProperties(once.rest.density);
    expectSameMass(once.rest.mass, summed, 1.5);
    EXPECT_EQ(once.rest.primitives.size(), rebuilt.primitives.size());
    EXPECT_EQ(once.rest.connections.size(), rebuilt.connections.size());
    EXPECT_EQ(once.rest.componentCount(), 1);
    EXPECT_EQ(once.rest.visual.faces.size(), rebuilt.visual.faces.size());
    const auto [area, crack] = areas(rebuilt.visual);
    const auto [editedArea, editedCrack] = areas(once.rest.visual);
    EXPECT_NEAR(editedArea, area, 1e-12);
    EXPECT_NEAR(editedCrack, crack, 1e-12);
    EXPECT_GT(crack, 0.0);
    expectVisualIdsFirstAndInPlace(once.rest);
    // The other fragments are the same either way.
    for (size_t i = 0, k = 0; i < once.full.pieces.size(); ++i) {
        if (int(i) == once.full.remainder) continue;
        EXPECT_EQ(once.edited.pieces[k].mass.mass, once.full.pieces[i].mass.mass);
        ++k;
    }

    // Again, on both rests: the edited one and the rebuilt one break alike.
    where.point = {0.75, 1.05, 0.0};
    const Case twiceEdited = fractureBothWays(once.rest, pattern, where);
    const Case twiceRebuilt = fractureBothWays(rebuilt, pattern, where);
    ASSERT_TRUE(twiceEdited.edited.remainderEdit);
    expectSameMass(twiceEdited.rest.mass, twiceRebuilt.rest.mass, 1.5);
    expectSameMass(twiceEdited.rest.mass, twiceEdited.full.pieces[size_t(twiceEdited.full.remainder)].mass, 1.5);
    EXPECT_EQ(twiceEdited.edited.pieces.size(), twiceRebuilt.edited.pieces.size());
    EXPECT_EQ(twiceEdited.rest.componentCount(), 1);
    EXPECT_NEAR(areas(twiceEdited.rest.visual).second, areas(twiceRebuilt.rest.visual).second, 1e-12);
    expectVisualIdsFirstAndInPlace(twiceEdited.rest);
}

TEST(RemainderEdit, AClosedSurfaceIsRebuiltNotEdited) {
    // A closed shell shows its inner side on every fragment after a break, which is not a
    // local change: the rest comes back as a piece.
    const auto body = test::ringShellBody(0.1);
    const auto pattern = voronoiPattern({.cells = 16, .radius = 0.8}, 3);
    Placement where;
    where.point = {2.0, 0.0, 0.5};
    where.normal = {0.0, 1.0, 0.0};
    const Case c = fractureBothWays(body, pattern, where);
    EXPECT_FALSE(c.edited.remainderEdit);
    EXPECT_EQ(c.edited.pieces.size(), c.full.pieces.size());
    EXPECT_EQ(c.edited.remainder, c.full.remainder);
}
