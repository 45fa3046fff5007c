#include "demos/runner/FrameWriter.h"
#include <shatter/plugin/fracture/CrackUv.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <system_error>

namespace shatter::demo {

namespace {

void appendNumber(std::string& text, double value) {
    // Anything that prints as zero is written as zero: "-0.000000" would only be noise.
    if (std::abs(value) < 5e-7) value = 0.0;
    char digits[64];
    const auto result = std::to_chars(digits, digits + sizeof digits, value, std::chars_format::fixed, 6);
    text.append(digits, result.ptr);
}

void appendInt(std::string& text, long long value) {
    char digits[24];
    const auto result = std::to_chars(digits, digits + sizeof digits, value);
    text.append(digits, result.ptr);
}

// An object name must stay on its own line.
void appendName(std::string& text, const std::string& name) {
    if (name.empty()) {
        text += "unnamed";
        return;
    }
    for (char c : name) text += (c == '\n' || c == '\r') ? '_' : c;
}

} // namespace

std::string frameFileName(int index, int count, std::string_view extension) {
    const int width = std::max<int>(4, int(std::to_string(std::max(count, index)).size()));
    std::string number = std::to_string(index);
    return "frame_" + std::string(size_t(std::max(0, width - int(number.size()))), '0') + number + "." +
           std::string(extension);
}

void appendObj(std::string& text, const std::vector<NamedMesh>& meshes, std::string_view comment) {
    text += "# ";
    text += comment;
    text += '\n';
    long long base = 1, uvBase = 1; // OBJ indices are 1-based and global over the file
    for (const NamedMesh& object : meshes) {
        text += "o ";
        appendName(text, object.name);
        text += '\n';
        for (const Eigen::Vector3d& p : object.mesh.positions) {
            text += "v ";
            appendNumber(text, p.x());
            text += ' ';
            appendNumber(text, p.y());
            text += ' ';
            appendNumber(text, p.z());
            text += '\n';
        }
        // Crack faces (fracture opened them inside the solid) under their own material, with
        // planar texture coordinates in metres (fracture::crackFaceUvs).
        bool crack = false;
        for (size_t f = 0; f < object.mesh.faces.size(); ++f) {
            const auto& face = object.mesh.faces[f];
            if (object.mesh.isCrackFace(f) != crack) {
                crack = !crack;
                text += crack ? "usemtl crack\n" : "usemtl surface\n";
            }
            if (crack)
                for (const Eigen::Vector2d& uv : fracture::crackFaceUvs(object.mesh.positions, face)) {
                    text += "vt ";
                    appendNumber(text, uv.x());
                    text += ' ';
                    appendNumber(text, uv.y());
                    text += '\n';
                }
            text += 'f';
            for (size_t k = 0; k < face.size(); ++k) {
                text += ' ';
                appendInt(text, base + face[k]);
                if (crack) {
                    text += '/';
                    appendInt(text, uvBase++);
                }
            }
            text += '\n';
        }
        base += (long long)object.mesh.positions.size();
    }
}

FrameWriter::FrameWriter(std::filesystem::path directory, int frameCount)
    : directory_(std::move(directory)), frameCount_(frameCount) {}

std::filesystem::path FrameWriter::write(int index, const std::vector<NamedMesh>& meshes, std::string_view comment) {
    buffer_.clear();
    appendObj(buffer_, meshes, comment);
    const std::filesystem::path path = directory_ / frameFileName(index, frameCount_, "obj");
    writeFile(path, buffer_);
    ++written_;
    return path;
}

void writeFile(const std::filesystem::path& path, std::string_view bytes) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "wb"), &std::fclose);
    if (!file) throw std::runtime_error(path.string() + ": cannot open for writing: " + std::generic_category().message(errno));
    const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), file.get()) == bytes.size();
    const bool closed = std::fclose(file.release()) == 0;
    if (!ok || !closed) throw std::runtime_error(path.string() + ": write failed: " + std::generic_category().message(errno));
}

} // namespace shatter::demo
