// A body's surface index kept between breaks (SurfaceIndex, patched by each RemainderEdit)
// must be, after every break, the index built from the edited body, and a break reading it
// must give the bits of a break that builds its own.
#include "FractureFixtures.h"

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/fracture/FractureMesh.h>
#include <shatter/plugin/fracture/SurfaceIndex.h>

#include <gtest/gtest.h>

using namespace shatter;
using namespace shatter::fracture;

namespace {

Placement surfaceHitAt(double x, double y) {
    Placement at;
    at.point = {x, y, 0.0};
    at.normal = {0.0, 0.0, -1.0};
    return at;
}

} // namespace

TEST(SurfaceIndex, PatchedByEachBreakItIsTheIndexOfTheEditedBody) {
    // A sheet of 30 × 30 quads (open: its rest is edited in place) hit four times, each hit
    // overlapping the cracks of the one before, so that the edits drop faces gained earlier,
    // move faces into holes and add visual vertices.
    geometry::PhysicalMesh body = test::sheetBody(30, 30, 0.05, 0.01);
    const FracturePattern pattern = voronoiPattern({.cells = 24, .radius = 0.35}, 5);
    CutSettings inPlace;
    inPlace.remainderInPlace = true;
    SurfaceIndex kept(body);
    EXPECT_FALSE(kept.closed());
    const Placement hits[] = {surfaceHitAt(0.75, 0.75), surfaceHitAt(0.45, 0.6), surfaceHitAt(1.0, 1.0), surfaceHitAt(0.6, 0.95)};
    int edits = 0;
    for (const Placement& where : hits) {
        PrimitiveIndex index;
        index.surface = &kept;
        const FractureResult withIndex = fractureMesh(body, pattern, where, inPlace, index);
        const FractureResult own = fractureMesh(body, pattern, where, inPlace);
        test::expectSameResult(withIndex, own);
        if (!withIndex.remainderEdit) continue;
        ++edits;
        const RemainderEdit& edit = *withIndex.remainderEdit;
        ASSERT_FALSE(edit.droppedFaces.empty());
        ASSERT_FALSE(edit.newVisualPositions.empty());
        const SurfaceIndex stale = kept;
        kept.patch(body, edit); // before the edit: it reads the faces the edit drops and moves
        applyRemainderEdit(body, edit);
        const SurfaceIndex fresh(body);
        EXPECT_TRUE(kept == fresh) << "after edit " << edits;
        EXPECT_FALSE(stale == fresh); // the comparison sees an edit
        EXPECT_FALSE(kept.closed());
        for (int f = 0; f < fresh.faceCount(); ++f) ASSERT_EQ(kept.primitivesOf(f), fresh.primitivesOf(f));
    }
    EXPECT_GE(edits, 3);
}

TEST(SurfaceIndex, ClosedWhenEveryEdgeIsUsedAsOftenEachWay) {
    // A cube of 2 × 2 × 2 cells: every visual edge once each way. Dropping one face opens it.
    geometry::PhysicalMesh cube = test::cubeBody({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                                                  {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}});
    EXPECT_TRUE(SurfaceIndex(cube).closed());
    cube.visual.faces.pop_back();
    EXPECT_FALSE(SurfaceIndex(cube).closed());
    EXPECT_FALSE(SurfaceIndex(test::sheetBody(3, 3, 0.1, 0.01)).closed());
}

TEST(SurfaceIndex, ABreakRefusesAnIndexOfAnotherSurface) {
    const geometry::PhysicalMesh body = test::sheetBody(6, 6, 0.05, 0.01);
    const SurfaceIndex other(test::sheetBody(5, 6, 0.05, 0.01));
    PrimitiveIndex index;
    index.surface = &other;
    const FracturePattern pattern = voronoiPattern({.cells = 8, .radius = 0.1}, 5);
    EXPECT_THROW(fractureMesh(body, pattern, surfaceHitAt(0.15, 0.15), CutSettings{}, index), InputError);
}
