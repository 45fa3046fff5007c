// The picture must be a PNG of the asked size in which the objects are actually visible,
// lit from above, where the camera says they are.
#include "demos/runner/PngRenderer.h"

#include "test_files.h"

#include <gtest/gtest.h>

using namespace shatter;
using namespace shatter::demo;
using shatter::demo::test::readPng;
using shatter::demo::test::readText;
using shatter::demo::test::TempDir;

namespace {

NamedMesh cube(const std::string& name, Eigen::Vector3d lo, double size) {
    NamedMesh m;
    m.name = name;
    for (int i = 0; i < 8; ++i)
        m.mesh.positions.push_back(lo + size * Eigen::Vector3d(i & 1 ? 1 : 0, i & 2 ? 1 : 0, i & 4 ? 1 : 0));
    m.mesh.faces = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    return m;
}

NamedMesh ground() {
    NamedMesh m;
    m.name = "ground";
    m.ground = true;
    m.mesh.positions = {{-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}};
    m.mesh.faces = {{0, 1, 2, 3}};
    return m;
}

double luminance(unsigned rgb) { return 0.3 * (rgb >> 16 & 255) + 0.59 * (rgb >> 8 & 255) + 0.11 * (rgb & 255); }

unsigned pixelOf(const test::PngImage& image, const Camera& camera, const Eigen::Vector3d& world) {
    const Eigen::Vector2d px = camera.toPixel(camera.toCamera(world));
    return image.at(int(px.x()), int(px.y()));
}

} // namespace

TEST(PngRenderer, PictureHasTheSizeAndShowsTheObjectLitFromAbove) {
    TempDir dir;
    const std::vector<NamedMesh> meshes = {cube("crate", {-0.5, 0, -0.5}, 1.0), ground()};
    const Picture picture{1280, 720, "shatter-test", "frame 1/1"};
    const Camera camera = frameScene(meshes, picture);
    renderPng(meshes, camera, picture, dir.path() / "p.png");

    const auto image = readPng(dir.path() / "p.png");
    ASSERT_EQ(image.width, 1280);
    ASSERT_EQ(image.height, 720);
    EXPECT_GT(image.distinctColours(), 20); // floor, shading, edges, text: not a flat picture

    const unsigned background = image.at(2, 60);
    const unsigned top = pixelOf(image, camera, {0, 1, 0});    // centre of the top face
    const unsigned front = pixelOf(image, camera, {0, 0.5, 0.5}); // centre of the +z face
    const unsigned side = pixelOf(image, camera, {0.5, 0.5, 0});  // centre of the +x face
    EXPECT_NE(top, background);
    EXPECT_NE(front, background);
    EXPECT_NE(side, background);
    // The light comes from above and in front: top brighter than front, front than side.
    EXPECT_GT(luminance(top), luminance(front));
    EXPECT_GT(luminance(front), luminance(side));
    // A far-away point of the picture is background, not object.
    EXPECT_EQ(image.at(1279, 60), background);
}

NamedMesh box(const std::string& name, Eigen::Vector3d lo, Eigen::Vector3d hi) {
    NamedMesh m = cube(name, {0, 0, 0}, 1.0);
    for (auto& p : m.mesh.positions) p = lo + p.cwiseProduct(hi - lo);
    return m;
}

// A chair's seat over the top of a leg at its front corner (the corner nearest the camera).
// The leg's top face is nearer the camera by its centre than the seat's top face is, so a
// renderer that sorts faces by their centres draws the leg's top over the seat. Where that
// hidden top projects, the picture must be exactly the seat-only picture; where the leg shows
// below the seat, it must differ.
TEST(PngRenderer, NearerSurfacesHideFartherOnesWhateverTheirCentres) {
    TempDir dir;
    const NamedMesh seat = box("seat", {-0.5, 0.5, -0.5}, {0.5, 0.56, 0.5});
    const NamedMesh leg = box("leg", {0.3, 0.0, 0.3}, {0.42, 0.5, 0.42});
    const Picture picture{640, 400, "", ""};
    const Camera camera = frameScene({seat, leg}, picture);
    const Eigen::Vector3d legTop(0.36, 0.5, 0.36), seatTop(0, 0.56, 0);
    ASSERT_LT(camera.toCamera(legTop).z(), camera.toCamera(seatTop).z()); // the painter's trap is set
    renderPng({seat}, camera, picture, dir.path() / "seat.png");
    renderPng({seat, leg}, camera, picture, dir.path() / "chair.png");
    const auto seatOnly = readPng(dir.path() / "seat.png"), chair = readPng(dir.path() / "chair.png");
    const Eigen::Vector2d hidden = camera.toPixel(camera.toCamera(legTop));
    for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
            const int x = int(hidden.x()) + dx, y = int(hidden.y()) + dy;
            EXPECT_EQ(chair.at(x, y), seatOnly.at(x, y)) << "leg shows through the seat at " << x << "," << y;
        }
    const unsigned legFront = pixelOf(chair, camera, {0.36, 0.2, 0.42});
    EXPECT_NE(legFront, pixelOf(seatOnly, camera, {0.36, 0.2, 0.42}));
}

TEST(PngRenderer, TitleLineIsDrawn) {
    TempDir dir;
    const std::vector<NamedMesh> meshes = {cube("crate", {0, 0, 0}, 1.0)};
    const Picture picture{640, 360, "shatter-title", "caption"};
    renderPng(meshes, frameScene(meshes, picture), picture, dir.path() / "t.png");
    const auto image = readPng(dir.path() / "t.png");
    int dark = 0;
    for (int y = 10; y < 45; ++y)
        for (int x = 20; x < 300; ++x) dark += luminance(image.at(x, y)) < 100;
    EXPECT_GT(dark, 100);
}

TEST(PngRenderer, SameSceneGivesTheSameBytes) {
    TempDir dir;
    const std::vector<NamedMesh> meshes = {cube("a", {0, 0, 0}, 1.0), cube("b", {1.5, 0, 0.2}, 0.5), ground()};
    const Picture picture{320, 240, "x", "y"};
    const Camera camera = frameScene(meshes, picture);
    renderPng(meshes, camera, picture, dir.path() / "1.png");
    renderPng(meshes, camera, picture, dir.path() / "2.png");
    EXPECT_EQ(readText(dir.path() / "1.png"), readText(dir.path() / "2.png"));
}

TEST(PngRenderer, NonFiniteVerticesAreSkippedNotDrawn) {
    TempDir dir;
    NamedMesh broken = cube("broken", {0, 0, 0}, 1.0);
    broken.mesh.positions[0].x() = std::numeric_limits<double>::quiet_NaN();
    const std::vector<NamedMesh> meshes = {broken, ground()};
    const Picture picture{320, 240, "x", "y"};
    EXPECT_NO_THROW(renderPng(meshes, frameScene(meshes, picture), picture, dir.path() / "n.png"));
    EXPECT_EQ(readPng(dir.path() / "n.png").width, 320);
}

TEST(PngRenderer, UnwritablePathIsAnErrorNamingIt) {
    const std::vector<NamedMesh> meshes = {cube("a", {0, 0, 0}, 1.0)};
    const Picture picture{64, 64, "x", "y"};
    try {
        renderPng(meshes, frameScene(meshes, picture), picture, "/nonexistent-shatter-dir/final.png");
        FAIL() << "expected an error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("final.png"), std::string::npos) << e.what();
    }
}
