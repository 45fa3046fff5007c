// The recording must give back every frame as it was, storing a shape only when it changed.
#include "demos/runner/RunRecording.h"

#include <gtest/gtest.h>

using namespace shatter::demo;

namespace {

NamedMesh triangle(const std::string& name, const Eigen::Isometry3d& pose, double tip = 1.0) {
    NamedMesh m;
    m.name = name;
    m.pose = pose;
    m.mesh.positions = {pose * Eigen::Vector3d(0, 0, 0), pose * Eigen::Vector3d(1, 0, 0), pose * Eigen::Vector3d(0, tip, 0)};
    m.mesh.faces = {{0, 1, 2}};
    return m;
}

Eigen::Isometry3d pose(double angle, Eigen::Vector3d at) {
    return Eigen::Translation3d(at) * Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, 3).normalized());
}

} // namespace

TEST(RunRecording, RigidMotionKeepsOneShapeAndFramesComeBackAsTheyWere) {
    RunRecording r;
    std::vector<std::vector<NamedMesh>> frames;
    for (int f = 1; f <= 5; ++f) {
        frames.push_back({triangle("a", pose(0.3 * f, {double(f), 0, 0}))});
        r.add(f, frames.back());
    }
    ASSERT_EQ(r.tracks().size(), 1u);
    EXPECT_EQ(r.tracks()[0].shapes.size(), 1u);
    for (int f = 1; f <= 5; ++f) {
        const auto back = r.meshesAt(f);
        ASSERT_EQ(back.size(), 1u);
        for (size_t v = 0; v < 3; ++v)
            EXPECT_LT((back[0].mesh.positions[v] - frames[size_t(f - 1)][0].mesh.positions[v]).norm(), 1e-12);
    }
}

TEST(RunRecording, ChangeOfShapeAddsOneAndLateOrRemovedBodiesAreAbsentThen) {
    RunRecording r;
    const auto at = Eigen::Isometry3d::Identity();
    r.add(1, {triangle("a", at), triangle("gone", at)});
    r.add(2, {triangle("a", at, 1.5), triangle("late", at)}); // a dented, gone removed, late appears
    r.add(3, {triangle("a", at, 1.5), triangle("late", at)});
    ASSERT_EQ(r.tracks().size(), 3u);
    EXPECT_EQ(r.tracks()[0].shapes.size(), 2u);
    EXPECT_EQ(r.tracks()[0].at(3)->shape, 1);
    EXPECT_EQ(r.tracks()[1].at(2), nullptr);
    EXPECT_EQ(r.tracks()[2].at(1), nullptr);
    EXPECT_EQ(r.meshesAt(1).size(), 2u);
    EXPECT_EQ(r.meshesAt(3).size(), 2u);
}

TEST(RunRecording, RepeatedNamesAreTrackedApart) {
    RunRecording r;
    const auto at = Eigen::Isometry3d::Identity();
    r.add(1, {triangle("piece", at), triangle("piece", pose(0, {3, 0, 0}))});
    ASSERT_EQ(r.tracks().size(), 2u);
    EXPECT_EQ(r.tracks()[1].name, "piece#2");
}
