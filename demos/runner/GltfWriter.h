#pragma once
// scene.glb: a whole run as one glTF 2.0 binary, which Blender, three.js, Godot, Unity and
// Unreal import. One node per body; its motion is a translation/rotation animation sampled
// at every frame; a body that changes shape (dent, tear, lost piece, soft body) gets one
// child node per shape, shown (scale 1) while it has that shape and hidden (scale 0)
// otherwise; a body that appears during the run (a fragment) is hidden until it exists and a
// removed body from then on. A shape is stored once however long the body keeps it, so a
// rigid fragment costs its mesh plus 28 bytes per frame. One material per body colour
// (BodyColour.h) and one for crack faces. The scene's extras hold "fps" and
// "events_per_frame" (Shatter events of each frame), which the browser viewer shows. Built with
// tinygltf (Debian's libtinygltf-dev).
#include "demos/runner/RunRecording.h"

#include <cstddef>
#include <filesystem>

namespace shatter::demo {

struct GltfStats {
    size_t bytes = 0; // file size
    int nodes = 0;
    int meshes = 0;
    int animationChannels = 0;
};

// Writes `recording` (frame k at time k / fps) to `path`. Throws std::runtime_error naming
// the file when it cannot be written.
GltfStats writeGltf(const RunRecording& recording, double fps, const std::filesystem::path& path);

} // namespace shatter::demo
