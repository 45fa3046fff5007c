#pragma once
// What the runner tests need to look at output: a scratch directory, and readers that
// check an OBJ or a PNG the way an outside tool would.
#include <filesystem>
#include <string>
#include <vector>

namespace shatter::demo::test {

// A fresh directory under the system temp directory, removed with everything in it.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

std::string readText(const std::filesystem::path& path);

// Counts of an OBJ file read back line by line. Face indices are checked to be 1-based and
// to refer to a vertex written before the face.
struct ObjCounts {
    int vertices = 0;
    int faces = 0;
    std::vector<std::string> objects; // `o` names in order
    std::vector<int> verticesPerObject, facesPerObject;
    int badIndices = 0;   // zero, negative, or past the vertices seen so far
    int shortFaces = 0;   // fewer than 3 vertices
    int badNumbers = 0;   // a `v` line without three finite numbers
};
ObjCounts readObj(const std::filesystem::path& path);

// A PNG read back with cairo.
struct PngImage {
    int width = 0, height = 0;
    std::vector<unsigned> pixels; // 0xRRGGBB, row-major
    unsigned at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
    int distinctColours() const;
};
// Throws std::runtime_error when cairo cannot read it.
PngImage readPng(const std::filesystem::path& path);

} // namespace shatter::demo::test
