// StampedScratch: a value is made once per use, on its first ask; a new use makes it again.
#include <shatter/plugin/geometry/StampedScratch.h>

#include <gtest/gtest.h>

namespace shatter::geometry {
namespace {

TEST(StampedScratch, MakesEachValueOncePerUse) {
    int made = 0;
    const auto make = [&](int v) { return [&made, v] { ++made; return v; }; };
    {
        StampedScratch<int> use(4);
        EXPECT_EQ(use.get(2, make(7)), 7);
        EXPECT_EQ(use.get(2, make(8)), 7); // kept from the first ask
        EXPECT_EQ(use.get(0, make(5)), 5);
        EXPECT_EQ(made, 2);
    }
    StampedScratch<int> next(6); // larger: the scratch grows
    EXPECT_EQ(next.get(2, make(9)), 9); // last use's value is not this one's
    EXPECT_EQ(next.get(5, make(1)), 1);
    EXPECT_EQ(made, 4);
}

} // namespace
} // namespace shatter::geometry
