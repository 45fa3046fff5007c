// fractureMesh with a PrimitiveIndex (a tree over the primitives' boxes kept by the body)
// against the same fracture without one: the index only spares reading far primitives.
#include "FractureFixtures.h"

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/fracture/FractureMesh.h>

#include <gtest/gtest.h>

using namespace shatter;
using namespace shatter::fracture;

namespace {

// The body's primitives in another frame (as a rigid body's collision shape holds them) and
// the tree over their boxes there.
struct MovedTree {
    geometry::AabbTree tree;
    Eigen::Isometry3d treeToMesh;
    MovedTree(const geometry::PhysicalMesh& body, const Eigen::Isometry3d& meshToTree) : treeToMesh(meshToTree.inverse()) {
        std::vector<geometry::Aabb> boxes;
        for (const auto& p : body.primitives) boxes.push_back(p.transformed(meshToTree).bounds());
        tree = geometry::AabbTree(boxes);
    }
    PrimitiveIndex index() const { return {&tree, treeToMesh}; }
};

Eigen::Isometry3d someFrame() {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
    t.translation() = Eigen::Vector3d(-3.1, 0.4, 12.0);
    return t;
}

} // namespace

TEST(PrimitiveIndex, AFractureWithTheBodysTreeIsTheFractureWithoutBitForBit) {
    const auto sheet = test::sheetBody(24, 24, 0.05, 0.02);
    const auto ring = test::ringShellBody(0.1);
    for (const auto* body : {&sheet, &ring}) {
        for (const Eigen::Isometry3d& frame : {Eigen::Isometry3d(Eigen::Isometry3d::Identity()), someFrame()}) {
            const MovedTree moved(*body, frame);
            for (int cells : {8, 32, 128})
                for (std::uint64_t seed : {1u, 2u})
                    for (bool inPlace : {false, true}) {
                        VoronoiPatternSettings s;
                        s.cells = cells;
                        s.radius = body == &sheet ? 0.4 : 1.2;
                        Placement where = body == &sheet ? Placement{.point = {0.6, 0.5, 0.0}, .normal = {0.2, 0.1, -1.0}}
                                                         : test::ringShellSideHit();
                        CutSettings settings;
                        settings.remainderInPlace = inPlace;
                        const auto pattern = voronoiPattern(s, seed);
                        SCOPED_TRACE(body->name + " cells " + std::to_string(cells) + " seed " + std::to_string(seed));
                        const FractureResult plain = fractureMesh(*body, pattern, where, settings);
                        const FractureResult indexed = fractureMesh(*body, pattern, where, settings, moved.index());
                        ASSERT_GT(plain.primitivesCut, 0);
                        test::expectSameResult(plain, indexed);
                    }
        }
    }
}

TEST(PrimitiveIndex, AnIndexOfAnotherPrimitiveCountIsAnErrorNamingTheBody) {
    const auto body = test::sheetBody(4, 4, 0.1, 0.02);
    const auto other = test::sheetBody(4, 5, 0.1, 0.02);
    const MovedTree moved(other, Eigen::Isometry3d::Identity());
    VoronoiPatternSettings s;
    s.cells = 8;
    s.radius = 0.2;
    const Placement where{.point = {0.2, 0.2, 0.0}, .normal = {0.0, 0.0, -1.0}};
    try {
        fractureMesh(body, voronoiPattern(s, 1), where, CutSettings{}, moved.index());
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("sheet"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("20 items for 16 primitives"), std::string::npos) << e.what();
    }
}
