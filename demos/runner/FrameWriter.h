#pragma once
// One Wavefront OBJ file per frame: every object of the scene in world coordinates, one
// `o <name>` per object, polygon faces kept, so Blender or Houdini can play the sequence.
#include "demos/runner/NamedMesh.h"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace shatter::demo {

// `frame_0001.obj` for index 1: at least four digits, as many as `count` needs.
std::string frameFileName(int index, int count, std::string_view extension);

// The OBJ text of one frame. Coordinates use a fixed six decimals, so equal meshes give
// equal bytes; `comment` goes on the first line after `# `.
void appendObj(std::string& text, const std::vector<NamedMesh>& meshes, std::string_view comment);

class FrameWriter {
public:
    FrameWriter(std::filesystem::path directory, int frameCount);

    // Writes frame `index` (1-based) and returns its path. Throws std::runtime_error naming
    // the file when it cannot be written.
    std::filesystem::path write(int index, const std::vector<NamedMesh>& meshes, std::string_view comment);

    int written() const { return written_; }

private:
    std::filesystem::path directory_;
    int frameCount_;
    int written_ = 0;
    std::string buffer_; // reused: a frame is formatted in memory and written in one call
};

// Writes `bytes` to `path` in one call, replacing the file. Throws std::runtime_error naming it.
void writeFile(const std::filesystem::path& path, std::string_view bytes);

} // namespace shatter::demo
