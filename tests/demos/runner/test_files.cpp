#include "test_files.h"

#include <cairo.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace shatter::demo::test {

TempDir::TempDir() {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("shatter-demo-test-" + std::to_string(getpid()) + "-" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

ObjCounts readObj(const std::filesystem::path& path) {
    ObjCounts c;
    std::istringstream file(readText(path));
    std::string line;
    while (std::getline(file, line)) {
        std::istringstream words(line);
        std::string tag;
        words >> tag;
        if (tag == "o") {
            c.objects.push_back(line.substr(2));
            c.verticesPerObject.push_back(0);
            c.facesPerObject.push_back(0);
        } else if (tag == "v") {
            double x, y, z;
            if (!(words >> x >> y >> z) || !std::isfinite(x + y + z)) ++c.badNumbers;
            ++c.vertices;
            if (!c.verticesPerObject.empty()) ++c.verticesPerObject.back();
        } else if (tag == "f") {
            int count = 0;
            long index;
            while (words >> index) {
                if (index < 1 || index > c.vertices) ++c.badIndices;
                ++count;
            }
            if (count < 3) ++c.shortFaces;
            ++c.faces;
            if (!c.facesPerObject.empty()) ++c.facesPerObject.back();
        }
    }
    return c;
}

int PngImage::distinctColours() const { return int(std::set<unsigned>(pixels.begin(), pixels.end()).size()); }

PngImage readPng(const std::filesystem::path& path) {
    cairo_surface_t* surface = cairo_image_surface_create_from_png(path.c_str());
    if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(surface);
        throw std::runtime_error(path.string() + ": not a readable PNG");
    }
    PngImage image;
    image.width = cairo_image_surface_get_width(surface);
    image.height = cairo_image_surface_get_height(surface);
    const unsigned char* data = cairo_image_surface_get_data(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    image.pixels.resize(size_t(image.width) * size_t(image.height));
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            unsigned argb;
            std::memcpy(&argb, data + size_t(y) * size_t(stride) + 4 * size_t(x), 4);
            image.pixels[size_t(y) * size_t(image.width) + size_t(x)] = argb & 0xFFFFFFu;
        }
    cairo_surface_destroy(surface);
    return image;
}

} // namespace shatter::demo::test
