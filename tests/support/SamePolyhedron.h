#pragma once
// Two polyhedra built two ways (e.g. createTrustedDroppingFlatFaces against createTrusted) that
// must be one: the same faces, planes, volume, centre of mass, inertia and box, to the bit.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <gtest/gtest.h>

namespace shatter::test {

inline void expectSamePolyhedron(const geometry::ConvexPolyhedron& made, const geometry::ConvexPolyhedron& plain) {
    EXPECT_EQ(made.faces(), plain.faces());
    ASSERT_EQ(made.planes().size(), plain.planes().size());
    for (size_t f = 0; f < plain.planes().size(); ++f) {
        EXPECT_EQ(made.planes()[f].normal, plain.planes()[f].normal);
        EXPECT_EQ(made.planes()[f].offset, plain.planes()[f].offset);
    }
    EXPECT_EQ(made.volume(), plain.volume());
    EXPECT_EQ(made.centerOfMass(), plain.centerOfMass());
    EXPECT_EQ(made.massProperties(1.0).inertia, plain.massProperties(1.0).inertia);
    EXPECT_EQ(made.bounds().min, plain.bounds().min);
    EXPECT_EQ(made.bounds().max, plain.bounds().max);
}

} // namespace shatter::test
