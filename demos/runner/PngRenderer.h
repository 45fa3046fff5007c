#pragma once
// A picture of one frame without a GPU or a display: the scene's polygons are rasterized with
// a depth buffer (DepthRaster, 3×3 samples per pixel) and flat Lambert shading, over a
// checkered floor with soft shadows; cairo adds the title line and writes the PNG.
#include "demos/runner/Camera.h"
#include "demos/runner/NamedMesh.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace shatter::demo {

struct Picture {
    int width = 1280;
    int height = 720;
    std::string title;   // first line, bold (e.g. "shatter-drop")
    std::string caption; // after the title (e.g. "frame 240/240 · 3 bodies")
};

// What a camera must see of a frame: the objects and, with a floor, their footprint on it
// (where their shadows fall).
std::vector<Eigen::Vector3d> framingPoints(const std::vector<NamedMesh>& meshes);

// The camera every picture of a run uses: frames framingPoints(meshes), leaving room for
// the title; or, when `focus` has points, frames those (a close-up).
Camera frameScene(const std::vector<NamedMesh>& meshes, const Picture& picture,
                  const std::vector<Eigen::Vector3d>& focus = {});

// The scene without any text, width×height pixels of 0xRRGGBB, row-major, and the floor's
// scale for a caption ("floor squares 0.5 m", empty without a floor).
struct SceneImage {
    int width = 0, height = 0;
    std::vector<std::uint32_t> pixels;
    std::string floorScale;
};
SceneImage renderScene(const std::vector<NamedMesh>& meshes, const Camera& camera, int width, int height);

// Renders `meshes` seen by `camera` under the picture's title and writes a PNG. Throws
// std::runtime_error naming the file when it cannot be written.
void renderPng(const std::vector<NamedMesh>& meshes, const Camera& camera, const Picture& picture,
               const std::filesystem::path& path);

} // namespace shatter::demo
