#pragma once
// Small meshes with known geometry for the geometry tests.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace shatter::test {

struct FaceMesh {
    std::vector<Eigen::Vector3d> positions;
    std::vector<std::vector<int>> faces;
};

// nx × ny unit-square-like cells of size `cell` in the z = 0 plane, normals +z.
// Vertex (i, j) has index j·(nx+1) + i; face (i, j) has index j·nx + i.
inline FaceMesh quadGrid(int nx, int ny, double cell) {
    FaceMesh m;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) m.positions.emplace_back(i * cell, j * cell, 0.0);
    auto v = [nx](int i, int j) { return j * (nx + 1) + i; };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) m.faces.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)});
    return m;
}

// Axis-aligned box with outward counter-clockwise quads; vertex i has coordinate bits
// (x: bit 0, y: bit 1, z: bit 2) choosing lo or hi. Faces: -z, +z, -y, +y, -x, +x.
inline FaceMesh closedBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    FaceMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
    m.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return m;
}

// Appends b to a (indices shifted).
inline void append(FaceMesh& a, const FaceMesh& b) {
    const int offset = int(a.positions.size());
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    for (auto face : b.faces) {
        for (int& v : face) v += offset;
        a.faces.push_back(face);
    }
}

inline void transform(FaceMesh& m, const Eigen::Isometry3d& t) {
    for (auto& p : m.positions) p = t * p;
}

// OBJ text of a mesh under one `o` name, with 1-based indices offset by `firstVertex`-1.
inline std::string objText(const FaceMesh& m, const std::string& object, int firstVertex = 1) {
    std::string out = "o " + object + "\n";
    char buffer[128];
    for (const auto& p : m.positions) {
        std::snprintf(buffer, sizeof buffer, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
        out += buffer;
    }
    for (const auto& f : m.faces) {
        out += "f";
        for (int v : f) {
            out += ' ';
            out += std::to_string(v + firstVertex);
        }
        out += "\n";
    }
    return out;
}

// Writes text to a fresh file under the system temp directory and returns its path.
inline std::string writeTempFile(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::temp_directory_path() / "shatter_geometry_tests";
    std::filesystem::create_directories(dir);
    const auto path = dir / name;
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
}

} // namespace shatter::test
