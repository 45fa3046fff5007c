#pragma once
// A picture of one frame without a GPU or a display: cairo fills the scene's polygons far to
// near (painter's algorithm) with flat Lambert shading, over a checkered floor with soft
// shadows, under a title line.
#include "demos/runner/Camera.h"
#include "demos/runner/NamedMesh.h"

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

// The camera every picture of a run uses: frames the objects and their footprint on the
// ground, leaving room for the title.
Camera frameScene(const std::vector<NamedMesh>& meshes, const Picture& picture);

// Renders `meshes` seen by `camera` and writes a PNG. Throws std::runtime_error naming the
// file when cairo cannot write it.
void renderPng(const std::vector<NamedMesh>& meshes, const Camera& camera, const Picture& picture,
               const std::filesystem::path& path);

} // namespace shatter::demo
