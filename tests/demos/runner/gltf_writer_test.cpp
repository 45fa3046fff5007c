// scene.glb read back with tinygltf, as an importer would: one node per body, rigid motion as
// keys, shapes stored once and switched, late bodies hidden until they exist, removed ones
// hidden after, crack faces with their own material.
#include "demos/runner/GltfWriter.h"

#include "test_files.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstring>

using namespace shatter::demo;
using shatter::demo::test::TempDir;

namespace {

constexpr double kFps = 60;

NamedMesh cube(const std::string& name, Eigen::Vector3d at) {
    NamedMesh m;
    m.name = name;
    for (int i = 0; i < 8; ++i) m.mesh.positions.emplace_back(i & 1 ? 1 : 0, i & 2 ? 1 : 0, i & 4 ? 1 : 0);
    m.mesh.faces = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    m.pose = Eigen::Translation3d(at) * Eigen::Isometry3d::Identity();
    for (auto& p : m.mesh.positions) p = m.pose * p;
    return m;
}

// Frame 1: box, gone, dent. Frame 2: + chip (one crack face). Frame 3: gone removed, dent's
// corner pushed in by 0.2. The box moves 1 m along x per frame.
RunRecording threeFrames() {
    RunRecording r;
    for (int f = 1; f <= 3; ++f) {
        std::vector<NamedMesh> frame{cube("box", {double(f - 1), 0, 0})};
        if (f >= 2) {
            NamedMesh chip = cube("chip", {0, 0, 5});
            chip.mesh.crackFace = {false, false, false, false, false, true};
            frame.push_back(chip);
        }
        if (f <= 2) frame.push_back(cube("gone", {0, 0, -5}));
        NamedMesh dent = cube("dent", {5, 0, 0});
        if (f == 3) dent.mesh.positions[7] -= Eigen::Vector3d::Constant(0.2);
        frame.push_back(dent);
        r.add(f, frame);
    }
    return r;
}

std::vector<float> floatsOf(const tinygltf::Model& m, int accessor) {
    const auto& a = m.accessors[size_t(accessor)];
    const auto& v = m.bufferViews[size_t(a.bufferView)];
    const int components = a.type == TINYGLTF_TYPE_SCALAR ? 1 : a.type == TINYGLTF_TYPE_VEC3 ? 3 : 4;
    std::vector<float> out(a.count * size_t(components));
    std::memcpy(out.data(), m.buffers[size_t(v.buffer)].data.data() + v.byteOffset + a.byteOffset, out.size() * sizeof(float));
    return out;
}

int nodeNamed(const tinygltf::Model& m, const std::string& name) {
    for (size_t i = 0; i < m.nodes.size(); ++i)
        if (m.nodes[i].name == name) return int(i);
    return -1;
}

// Times and values of the channel animating `path` of `node`; empty when there is none.
std::pair<std::vector<float>, std::vector<float>> keys(const tinygltf::Model& m, int node, const std::string& path) {
    for (const auto& c : m.animations.at(0).channels)
        if (c.target_node == node && c.target_path == path) {
            const auto& s = m.animations[0].samplers[size_t(c.sampler)];
            return {floatsOf(m, s.input), floatsOf(m, s.output)};
        }
    return {};
}

tinygltf::Model load(const std::filesystem::path& path) {
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, path.string())) << err;
    return model;
}

} // namespace

TEST(GltfWriter, BodiesMoveAppearDisappearAndChangeShapeAsRecorded) {
    TempDir dir;
    const GltfStats stats = writeGltf(threeFrames(), kFps, dir.path() / "scene.glb");
    EXPECT_EQ(stats.bytes, std::filesystem::file_size(dir.path() / "scene.glb"));
    const tinygltf::Model m = load(dir.path() / "scene.glb");
    ASSERT_EQ(m.scenes.at(0).nodes.size(), 4u); // one per body
    EXPECT_EQ(m.meshes.size(), 5u);             // box, chip, gone: one shape each; dent: two

    // The box: one mesh for all frames, moved by keys at the frame times.
    const int box = nodeNamed(m, "box");
    ASSERT_GE(box, 0);
    EXPECT_GE(m.nodes[size_t(box)].mesh, 0);
    const auto [boxTimes, boxMoves] = keys(m, box, "translation");
    ASSERT_EQ(boxTimes.size(), 3u);
    EXPECT_FLOAT_EQ(boxTimes[2], float(3 / kFps));
    EXPECT_FLOAT_EQ(boxMoves[6], 2.0f); // x at frame 3
    EXPECT_TRUE(keys(m, box, "scale").first.empty()); // always there: never hidden

    // The chip: hidden (scale 0) until frame 2, then shown; its crack face has the crack material.
    const int chip = nodeNamed(m, "chip");
    EXPECT_EQ(m.nodes[size_t(chip)].scale, (std::vector<double>{0, 0, 0}));
    const auto [chipTimes, chipScale] = keys(m, chip, "scale");
    EXPECT_EQ(chipTimes, (std::vector<float>{float(1 / kFps), float(2 / kFps)}));
    EXPECT_EQ(chipScale, (std::vector<float>{0, 0, 0, 1, 1, 1}));
    const auto& chipMesh = m.meshes[size_t(m.nodes[size_t(chip)].mesh)];
    ASSERT_EQ(chipMesh.primitives.size(), 2u);
    EXPECT_EQ(m.materials[size_t(chipMesh.primitives[1].material)].name, "crack");
    EXPECT_EQ(m.accessors[size_t(chipMesh.primitives[1].indices)].count, 6u); // one quad: two triangles
    EXPECT_EQ(m.accessors[size_t(chipMesh.primitives[0].indices)].count, 30u);

    // Gone: shown, then hidden from frame 3 on.
    const auto [goneTimes, goneScale] = keys(m, nodeNamed(m, "gone"), "scale");
    EXPECT_EQ(goneTimes, (std::vector<float>{float(1 / kFps), float(3 / kFps)}));
    EXPECT_EQ(goneScale, (std::vector<float>{1, 1, 1, 0, 0, 0}));

    // Dent: two child shapes, the second shown from frame 3 with the corner pushed in.
    const int dent = nodeNamed(m, "dent");
    ASSERT_EQ(m.nodes[size_t(dent)].children.size(), 2u);
    const int after = m.nodes[size_t(dent)].children[1];
    EXPECT_EQ(m.nodes[size_t(after)].scale, (std::vector<double>{0, 0, 0}));
    EXPECT_EQ(keys(m, after, "scale").second, (std::vector<float>{0, 0, 0, 1, 1, 1}));
    const auto positions = floatsOf(m, m.meshes[size_t(m.nodes[size_t(after)].mesh)].primitives[0].attributes.at("POSITION"));
    EXPECT_NEAR(positions[7 * 3], 0.8f, 1e-6); // body coordinates: the pose is the node's
}

TEST(GltfWriter, SameRecordingGivesTheSameBytes) {
    TempDir dir;
    writeGltf(threeFrames(), kFps, dir.path() / "a.glb");
    writeGltf(threeFrames(), kFps, dir.path() / "b.glb");
    EXPECT_EQ(test::readText(dir.path() / "a.glb"), test::readText(dir.path() / "b.glb"));
}

TEST(GltfWriter, UnwritablePathIsAnErrorNamingIt) {
    try {
        writeGltf(threeFrames(), kFps, "/nonexistent-shatter-dir/scene.glb");
        FAIL() << "expected an error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("scene.glb"), std::string::npos) << e.what();
    }
}
