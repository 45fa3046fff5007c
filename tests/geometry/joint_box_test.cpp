// Bodies and joint boxes from one OBJ file (source 000 §3.1).
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/JointBoxes.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include "MeshFixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace shatter::geometry;
using shatter::InputError;
using shatter::test::FaceMesh;

namespace {

// An OBJ text assembled object by object, remembering the line of each `o`.
class ObjBuilder {
public:
    ObjBuilder& add(const FaceMesh& m, const std::string& name) {
        objectLine_.push_back(int(std::count(text_.begin(), text_.end(), '\n')) + 1);
        text_ += shatter::test::objText(m, name, nextVertex_);
        nextVertex_ += int(m.positions.size());
        return *this;
    }
    const std::string& text() const { return text_; }
    int lineOf(int object) const { return objectLine_.at(object); }

private:
    std::string text_ = "# bodies and joints\n";
    int nextVertex_ = 1;
    std::vector<int> objectLine_;
};

// Box with the given half extents along its own x, y, z, turned by `rotation`, at `centre`.
FaceMesh box(const Eigen::Vector3d& half, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& centre) {
    FaceMesh m = shatter::test::closedBox(-half, half);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = rotation;
    pose.translation() = centre;
    shatter::test::transform(m, pose);
    return m;
}

const Eigen::Matrix3d kTurn30 = Eigen::AngleAxisd(std::numbers::pi / 6, Eigen::Vector3d::UnitZ()).toRotationMatrix();

ObjBuilder twoBodies() {
    ObjBuilder obj;
    obj.add(shatter::test::closedBox({-1, -0.2, -0.2}, {0, 0.2, 0.2}), "a");
    obj.add(shatter::test::closedBox({0, -0.2, -0.2}, {1, 0.2, 0.2}), "b");
    obj.add(shatter::test::closedBox({-0.95, 0.2, -0.05}, {-0.85, 0.3, 0.05}), "a.handle");
    return obj;
}

std::string objectError(const std::string& text) {
    try {
        buildPhysicalObject(parseObj(text, "joint.obj"));
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(JointBoxes, RotatedHingeBoxGivesTypeBodiesFrameAndAttachments) {
    ObjBuilder obj = twoBodies();
    const Eigen::Vector3d centre(0.0, 0.05, 0.0);
    obj.add(box({0.2, 0.05, 0.1}, kTurn30, centre), "joint.hinge.a.b.left");
    const PhysicalObject object = buildPhysicalObject(parseObj(obj.text(), "hinge.obj"));

    ASSERT_EQ(object.bodies.size(), 2u);
    EXPECT_EQ(object.bodies[0].name, "a");
    EXPECT_EQ(object.bodies[1].name, "b");
    EXPECT_EQ(object.bodies[0].primitives.size(), 2u); // `a` and `a.handle` are one body
    EXPECT_EQ(object.findBody("b"), 1);
    EXPECT_EQ(object.findBody("a.handle"), -1);

    ASSERT_EQ(object.joints.size(), 1u);
    const JointBox& j = object.joints[0];
    EXPECT_EQ(j.name, "joint.hinge.a.b.left");
    EXPECT_EQ(j.type, JointType::Hinge);
    EXPECT_EQ(j.bodyA, "a");
    EXPECT_EQ(j.bodyB, "b");
    // Coordinates are written with 17 digits: the fit is exact to round-off (1e-12).
    EXPECT_LT((j.pose.translation() - centre).norm(), 1e-12);
    EXPECT_LT((j.halfExtents - Eigen::Vector3d(0.2, 0.1, 0.05)).norm(), 1e-12); // sorted, decreasing
    const Eigen::Matrix3d r = j.pose.linear();
    EXPECT_LT((r.col(0) - kTurn30.col(0)).norm(), 1e-12); // hinge axis along the long edge
    EXPECT_LT((r.col(1) - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
    EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    // The box straddles x = 0: it touches the main box of each body, not the handle.
    EXPECT_EQ(j.attachmentsA, std::vector<int>{0});
    EXPECT_EQ(j.attachmentsB, std::vector<int>{0});
    EXPECT_TRUE(object.warnings.empty());
}

TEST(JointBoxes, BoxWrittenWithSixDecimalsStillFits) {
    // Exporters round to 6 decimals: positions are trusted to 1e-6 m, so the frame to
    // about 1e-6 / 0.05 rad; checked at 1e-4.
    const FaceMesh m = box({0.2, 0.05, 0.1}, kTurn30, {0.3, 0.05, -0.1});
    std::string text = "o joint.ball.a.b\n";
    char line[128];
    for (const auto& p : m.positions) {
        std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", p.x(), p.y(), p.z());
        text += line;
    }
    for (const auto& f : m.faces) text += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " +
                                          std::to_string(f[2] + 1) + " " + std::to_string(f[3] + 1) + "\n";
    const ObjFile file = parseObj(text, "six.obj");
    std::vector<std::vector<int>> faces;
    for (const auto& f : file.objects[0].faces) faces.push_back(f.vertices);
    const OrientedBox fitted = fitBox(file.positions, faces, "six.obj:1");
    EXPECT_LT((fitted.pose.translation() - Eigen::Vector3d(0.3, 0.05, -0.1)).norm(), 2e-6);
    EXPECT_LT((fitted.halfExtents - Eigen::Vector3d(0.2, 0.1, 0.05)).norm(), 2e-6);
    EXPECT_LT((fitted.pose.linear().col(0) - kTurn30.col(0)).norm(), 1e-4);
}

TEST(JointBoxes, TriangulatedBoxIsABox) {
    FaceMesh m = box({0.3, 0.2, 0.1}, Eigen::Matrix3d::Identity(), {1, 2, 3});
    std::vector<std::vector<int>> triangles;
    for (const auto& f : m.faces) {
        triangles.push_back({f[0], f[1], f[2]});
        triangles.push_back({f[0], f[2], f[3]});
    }
    const OrientedBox fitted = fitBox(m.positions, triangles, "tri");
    EXPECT_LT((fitted.halfExtents - Eigen::Vector3d(0.3, 0.2, 0.1)).norm(), 1e-12);
    EXPECT_LT((fitted.pose.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(JointBoxes, NonBoxShapesAreRejectedWithTheirLine) {
    // A wedge: triangular prism, normals in 4 directions.
    FaceMesh wedge;
    wedge.positions = {{0, 0, 0}, {0.2, 0, 0}, {0, 0.2, 0}, {0, 0, 0.2}, {0.2, 0, 0.2}, {0, 0.2, 0.2}};
    wedge.faces = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}};
    ObjBuilder obj = twoBodies();
    obj.add(wedge, "joint.fixed.a.b");
    std::string message = objectError(obj.text());
    EXPECT_EQ(message.rfind("joint.obj:" + std::to_string(obj.lineOf(3)) + ": joint 'joint.fixed.a.b': not a box (", 0), 0u)
        << message;
    EXPECT_NE(message.find("directions"), std::string::npos) << message;

    // A box with one corner pulled out by 1 mm.
    FaceMesh dented = box({0.1, 0.1, 0.1}, kTurn30, {0, 0, 0});
    dented.positions[7] += Eigen::Vector3d(0.001, 0, 0);
    ObjBuilder obj2 = twoBodies();
    obj2.add(dented, "joint.fixed.a.b");
    message = objectError(obj2.text());
    EXPECT_EQ(message.rfind("joint.obj:" + std::to_string(obj2.lineOf(3)) + ": joint 'joint.fixed.a.b': not a box (", 0), 0u)
        << message;

    // An open box: five sides.
    FaceMesh open = box({0.1, 0.1, 0.1}, Eigen::Matrix3d::Identity(), {0, 0, 0});
    open.faces.pop_back();
    ObjBuilder obj3 = twoBodies();
    obj3.add(open, "joint.fixed.a.b");
    message = objectError(obj3.text());
    EXPECT_NE(message.find("not a box (the faces do not cover each side of the box exactly once)"), std::string::npos)
        << message;
}

TEST(JointBoxes, BadNamesAndUnknownBodiesAreErrors) {
    const FaceMesh cube = box({0.05, 0.05, 0.05}, Eigen::Matrix3d::Identity(), {0, 0, 0});
    ObjBuilder unknownBody = twoBodies();
    unknownBody.add(cube, "joint.ball.a.c");
    EXPECT_EQ(objectError(unknownBody.text()), "joint.obj:" + std::to_string(unknownBody.lineOf(3)) +
                                                   ": joint 'joint.ball.a.c': body 'c' does not exist (bodies: a, b)");
    ObjBuilder unknownType = twoBodies();
    unknownType.add(cube, "joint.slider.a.b");
    EXPECT_EQ(objectError(unknownType.text()),
              "joint.obj:" + std::to_string(unknownType.lineOf(3)) +
                  ": joint 'joint.slider.a.b': unknown joint type 'slider' (expected fixed, hinge or ball)");
    ObjBuilder tooShort = twoBodies();
    tooShort.add(cube, "joint.hinge.a");
    EXPECT_EQ(objectError(tooShort.text()).rfind("joint.obj:" + std::to_string(tooShort.lineOf(3)) +
                                                  ": joint 'joint.hinge.a': the name needs the form", 0),
              0u);
    ObjBuilder self = twoBodies();
    self.add(cube, "joint.fixed.b.b");
    EXPECT_NE(objectError(self.text()).find("joins body 'b' to itself"), std::string::npos);
}

TEST(JointBoxes, JointTouchingNothingIsAWarningAndFileWarningsPassOn) {
    ObjBuilder obj = twoBodies();
    obj.add(box({0.05, 0.05, 0.05}, Eigen::Matrix3d::Identity(), {0, 3, 0}), "joint.fixed.a.b");
    const std::string text = obj.text() + "f 1 2 1\n"; // a degenerate face in the last object
    const PhysicalObject object = buildPhysicalObject(parseObj(text, "far.obj"));
    ASSERT_EQ(object.joints.size(), 1u);
    EXPECT_TRUE(object.joints[0].attachmentsA.empty());
    const std::string line = std::to_string(obj.lineOf(3));
    const std::vector<std::string> expected = {
        "far.obj: skipped 1 degenerate face (line " + std::to_string(obj.lineOf(3) + 15) + ")",
        "far.obj:" + line + ": joint 'joint.fixed.a.b': touches no primitive of body 'a'",
        "far.obj:" + line + ": joint 'joint.fixed.a.b': touches no primitive of body 'b'"};
    EXPECT_EQ(object.warnings, expected);
}

TEST(JointBoxes, BodyMeshWarningsNameTheBody) {
    FaceMesh inward = shatter::test::closedBox({0, 0, 0}, {1, 1, 1});
    for (auto& f : inward.faces) std::reverse(f.begin(), f.end());
    ObjBuilder obj;
    obj.add(inward, "crate");
    const PhysicalObject object = buildPhysicalObject(parseObj(obj.text(), "crate.obj"));
    ASSERT_EQ(object.warnings.size(), 1u);
    // Faces are named by file and line: the first face follows `o` and 8 vertices.
    EXPECT_EQ(object.warnings[0].rfind("body 'crate': the closed part (crate.obj:11, crate.obj:12", 0), 0u)
        << object.warnings[0];
}

TEST(JointBoxes, DemoAssetsLoad) {
    const std::string dir = std::string(SHATTER_SOURCE_DIR) + "/demos/assets/";
    if (!std::filesystem::exists(dir + "hinged_planks.obj")) GTEST_SKIP() << "demo assets not present";
    const PhysicalObject planks = buildPhysicalObject(loadObj(dir + "hinged_planks.obj"));
    ASSERT_EQ(planks.bodies.size(), 2u);
    ASSERT_EQ(planks.joints.size(), 1u);
    EXPECT_EQ(planks.joints[0].type, JointType::Hinge);
    EXPECT_FALSE(planks.joints[0].attachmentsA.empty());
    EXPECT_FALSE(planks.joints[0].attachmentsB.empty());
    const PhysicalObject chair = buildPhysicalObject(loadObj(dir + "chair.obj"));
    ASSERT_EQ(chair.bodies.size(), 1u);
    EXPECT_EQ(chair.bodies[0].primitives.size(), 6u); // six closed boxes
    EXPECT_EQ(chair.bodies[0].componentCount(), 1);   // connected where they overlap
}
