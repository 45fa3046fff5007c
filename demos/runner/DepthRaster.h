#pragma once
// The canvas the PNG renderer draws on: colour, depth and face id per sample, several
// samples per pixel side for anti-aliased edges. A triangle only covers samples where it is
// nearer than what is already there, so a chair's seat hides the tops of its legs whatever
// order the faces come in.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace shatter::demo {

class DepthRaster {
public:
    static constexpr int kNoFace = -1;

    // `width`×`height` pixels of `samples`×`samples` samples each, all `background`, at
    // infinite depth.
    DepthRaster(int width, int height, int samples, std::uint32_t background);

    int samplesWide() const { return sw_; }
    int samplesHigh() const { return sh_; }
    int samples() const { return samples_; }

    // A triangle given in pixels, with 1/depth at each corner (depth along the view axis):
    // 1/depth is affine in the image, so interpolating it is exact under perspective. Samples
    // it covers and where it is nearer take `colour` and `face`.
    void triangle(const std::array<Eigen::Vector2d, 3>& pixels, const std::array<double, 3>& inverseDepth,
                  std::uint32_t colour, int face);
    // Calls `visit(sample index)` for every sample a triangle (in pixels) covers, depth ignored.
    void cover(const std::array<Eigen::Vector2d, 3>& pixels, const std::function<void(size_t)>& visit) const;

    // Sample index -> its centre in pixels.
    Eigen::Vector2d centre(size_t sample) const;

    std::vector<std::uint32_t>& colour() { return colour_; }
    std::vector<float>& inverseDepth() { return inverseDepth_; }
    const std::vector<int>& face() const { return face_; }

    // One 0xRRGGBB value per pixel, the mean of its samples, row-major.
    std::vector<std::uint32_t> pixels() const;

private:
    template <class Visit>
    void scan(const std::array<Eigen::Vector2d, 3>& pixels, Visit&& visit) const;

    int width_, height_, samples_, sw_, sh_;
    std::vector<std::uint32_t> colour_;
    std::vector<float> inverseDepth_; // 0 = nothing drawn (infinitely far)
    std::vector<int> face_;
};

std::uint32_t packRgb(double r, double g, double b);

} // namespace shatter::demo
