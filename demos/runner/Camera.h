#pragma once
// The fixed 3/4 view every demo picture uses: in front of the scene, to the right and above,
// looking down at it, Y up.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace shatter::demo {

class Camera {
public:
    // Looks at `points` from the fixed direction and zooms and centres so that their
    // projections fill most of the `width`×`height` image below a band of `topMargin`
    // pixels kept free for the title. Non-finite points are ignored; no points frame the origin.
    static Camera framing(const std::vector<Eigen::Vector3d>& points, int width, int height, int topMargin = 0);

    // x right, y up, z forward (the depth; in front of the camera when z >= nearDepth()).
    Eigen::Vector3d toCamera(const Eigen::Vector3d& world) const;
    // Pixel of a camera-space point in front of the camera (y grows downwards, as in images).
    Eigen::Vector2d toPixel(const Eigen::Vector3d& cameraPoint) const;
    // The direction through an image point, scaled so that its camera depth (z) is 1: the
    // point at depth d along it is eye() + d * ray(pixel).
    Eigen::Vector3d ray(const Eigen::Vector2d& pixel) const;
    // Polygons must be clipped to this depth before projection.
    double nearDepth() const { return near_; }
    // Direction from the scene towards the camera, in world coordinates.
    Eigen::Vector3d towardsEye() const { return -forward_; }
    Eigen::Vector3d eye() const { return eye_; }

private:
    Eigen::Vector3d eye_, right_, up_, forward_;
    double focal_ = 1.0;         // pixels per unit of x/z
    Eigen::Vector2d centre_{0, 0}; // image point of the view axis, in pixels
    double near_ = 1e-3;
};

} // namespace shatter::demo
